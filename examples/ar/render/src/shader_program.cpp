#include "marionette_ar/render/shader_program.hpp"

#include <epoxy/gl.h>

#include <glm/gtc/type_ptr.hpp>

#include "shader_sources.hpp"  // generated: kShaderFiles

namespace marionette::ar {

std::string_view embeddedShader(std::string_view name) {
  for (const ShaderFile& f : kShaderFiles)
    if (name == f.name) return f.text;
  return {};
}

const char* const* shaderStageNames() {
  static const char* const names[] = {"character.vert", "character.frag", "background.vert", "background.frag",
                                     "shadow_depth.frag", "shadow_catcher.vert", "shadow_catcher.frag", nullptr};
  return names;
}

std::string shaderSource(std::string_view name, ShaderDialect dialect) {
  std::string out = dialect == ShaderDialect::Glsl330Core
                        ? "#version 330 core\n"
                        : "#version 300 es\nprecision highp float;\nprecision highp int;\nprecision highp sampler2D;\n";
  out += "#line 1\n";
  out += embeddedShader(name);
  if (name.size() > 5 && name.substr(name.size() - 5) == ".frag") {
    out += "\n#line 1\n";
    out += embeddedShader("lighting.glsl");
    out += "\n#line 1\n";
    out += embeddedShader("occlusion.glsl");
  }
  return out;
}

namespace {

unsigned compileStage(unsigned type, std::string_view file, Diagnostics& diagnostics) {
  if (embeddedShader(file).empty()) {
    diagnostics.error(std::string(file), "shader '" + std::string(file) + "' is not embedded in the program");
    return 0;
  }
  const std::string text = shaderSource(file, ShaderDialect::Glsl330Core);
  const GLuint shader = glCreateShader(type);
  const char* src = text.c_str();
  glShaderSource(shader, 1, &src, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096] = {};
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    diagnostics.error(std::string(file), "shader '" + std::string(file) + "' does not compile: " + log);
    glDeleteShader(shader);
    return 0;
  }
  return shader;
}

}  // namespace

ShaderProgram::~ShaderProgram() {
  if (program_) glDeleteProgram(program_);
}

bool ShaderProgram::build(std::string_view vertexFile, std::string_view fragmentFile, Diagnostics& diagnostics) {
  const unsigned vs = compileStage(GL_VERTEX_SHADER, vertexFile, diagnostics);
  if (!vs) return false;
  const unsigned fs = compileStage(GL_FRAGMENT_SHADER, fragmentFile, diagnostics);
  if (!fs) {
    glDeleteShader(vs);
    return false;
  }
  program_ = glCreateProgram();
  glAttachShader(program_, vs);
  glAttachShader(program_, fs);
  glLinkProgram(program_);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[4096] = {};
    glGetProgramInfoLog(program_, sizeof log, nullptr, log);
    diagnostics.error(std::string(vertexFile),
                      "shaders '" + std::string(vertexFile) + "' + '" + std::string(fragmentFile) + "' do not link: " + log);
    return false;
  }
  return true;
}

void ShaderProgram::use() const { glUseProgram(program_); }
int ShaderProgram::location(const char* name) const { return glGetUniformLocation(program_, name); }
void ShaderProgram::set(const char* name, int value) const { glUniform1i(location(name), value); }
void ShaderProgram::set(const char* name, float value) const { glUniform1f(location(name), value); }
void ShaderProgram::set(const char* name, const glm::vec3& v) const { glUniform3fv(location(name), 1, glm::value_ptr(v)); }
void ShaderProgram::set(const char* name, const glm::vec4& v) const { glUniform4fv(location(name), 1, glm::value_ptr(v)); }
void ShaderProgram::set(const char* name, const glm::mat4& m) const {
  glUniformMatrix4fv(location(name), 1, GL_FALSE, glm::value_ptr(m));
}

}  // namespace marionette::ar
