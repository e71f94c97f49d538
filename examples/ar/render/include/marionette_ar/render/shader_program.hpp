// GLSL programs. The shader files (examples/ar/shaders) carry no #version
// line: one text serves GLSL 3.30 core (desktop) and GLSL ES 3.00 (phones, as
// the seed paper's renderer ran), and the dialect's header is prepended here.
#pragma once
#include <string>
#include <string_view>

#include <glm/glm.hpp>

#include "marionette/core/diagnostic.hpp"

namespace marionette::ar {

enum class ShaderDialect { Glsl330Core, GlslEs300 };

// The embedded source of a shader file ("character.vert", ...), or empty.
[[nodiscard]] std::string_view embeddedShader(std::string_view name);
// A compilable stage: the dialect's header, the file, and for fragment shaders
// the shared lighting functions (lighting.glsl) and the occlusion lookup (occlusion.glsl).
[[nodiscard]] std::string shaderSource(std::string_view name, ShaderDialect dialect);
// Every embedded stage file (for the compile test).
[[nodiscard]] const char* const* shaderStageNames();  // null-terminated

class ShaderProgram {
 public:
  ShaderProgram() = default;
  ~ShaderProgram();
  ShaderProgram(const ShaderProgram&) = delete;
  ShaderProgram& operator=(const ShaderProgram&) = delete;

  // Compiles and links; on failure returns false with an error in `diagnostics` naming the stage
  // file and the log.
  bool build(std::string_view vertexFile, std::string_view fragmentFile, Diagnostics& diagnostics);
  void use() const;
  [[nodiscard]] unsigned id() const noexcept { return program_; }
  [[nodiscard]] int location(const char* name) const;

  void set(const char* name, int value) const;
  void set(const char* name, float value) const;
  void set(const char* name, const glm::vec3& value) const;
  void set(const char* name, const glm::vec4& value) const;
  void set(const char* name, const glm::mat4& value) const;

 private:
  unsigned program_ = 0;
};

}  // namespace marionette::ar
