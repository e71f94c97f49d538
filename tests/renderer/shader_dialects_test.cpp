// The renderer's shaders compile as GLSL 3.30 core and as GLSL ES 3.00 (phones,
// as the seed paper's renderer ran), checked by Khronos' glslangValidator.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "marionette_ar/render/shader_program.hpp"

namespace marionette::test {
namespace {

struct Validation {
  int status = -1;
  std::string output;
};

Validation validate(const std::string& source, const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "marionette_shader_test";
  std::filesystem::create_directories(dir);
  const auto file = dir / name;  // the extension (.vert / .frag) gives the stage
  std::ofstream(file) << source;
  Validation v;
  FILE* p = popen(("glslangValidator " + file.string() + " 2>&1").c_str(), "r");
  if (!p) return v;
  char buf[4096];
  while (std::size_t n = std::fread(buf, 1, sizeof buf, p)) v.output.append(buf, n);
  const int s = pclose(p);
  v.status = WIFEXITED(s) ? WEXITSTATUS(s) : -1;
  return v;
}

TEST(ShaderDialects, EveryStageCompilesBothWays) {
  int stages = 0;
  for (const char* const* name = ar::shaderStageNames(); *name; ++name, ++stages) {
    for (auto dialect : {ar::ShaderDialect::Glsl330Core, ar::ShaderDialect::GlslEs300}) {
      const Validation v = validate(ar::shaderSource(*name, dialect), *name);
      EXPECT_EQ(v.status, 0) << *name << (dialect == ar::ShaderDialect::GlslEs300 ? " as GLSL ES 3.00" : " as GLSL 3.30")
                             << ":\n" << v.output;
    }
  }
  EXPECT_EQ(stages, 7);  // character, background, the contact shadow's depth pass and catcher
}

TEST(ShaderDialects, TheValidatorRejectsABrokenShader) {
  // So that the test above could fail: ES 3.00 has no implicit int-to-float in this assignment.
  const std::string broken = ar::shaderSource("background.vert", ar::ShaderDialect::GlslEs300) + "\nfloat broken = 1;\n";
  EXPECT_NE(validate(broken, "broken.vert").status, 0);
}

}  // namespace
}  // namespace marionette::test
