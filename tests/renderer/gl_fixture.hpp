// One hidden OpenGL 3.3 context for the renderer's GL tests (run under xvfb-run
// by ctest; see tests/renderer/CMakeLists.txt), and image comparisons.
#pragma once
#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
#include <string>

#include "marionette_ar/render/gl_context.hpp"
#include "marionette_ar/render/image.hpp"
#include "marionette_ar/render/shader_program.hpp"

namespace marionette::test {

class GlTest : public ::testing::Test {
 public:
  // The character shader, built in this suite's context.
  static const ar::ShaderProgram& characterProgram() { return *program_; }

 protected:
  static void SetUpTestSuite() {
    Diagnostics error;
    context_ = ar::GlContext::create({256, 256, false, "marionette GL test"}, error);
    ASSERT_NE(context_, nullptr) << error.format() << " (DISPLAY=" << (std::getenv("DISPLAY") ? std::getenv("DISPLAY") : "")
                                 << ")";
    program_ = std::make_unique<ar::ShaderProgram>();
    ASSERT_TRUE(program_->build("character.vert", "character.frag", error)) << error.format();
  }
  static void TearDownTestSuite() {
    program_.reset();  // GL objects go before their context
    context_.reset();
  }
  void SetUp() override { ASSERT_NE(context_, nullptr) << "no OpenGL context"; }
  static inline std::unique_ptr<ar::GlContext> context_;
  static inline std::unique_ptr<ar::ShaderProgram> program_;
};

struct ImageDifference {
  double meanAbs = 0.0;        // mean absolute channel difference, 0..255
  double fractionOver = 0.0;   // fraction of pixels with a channel differing by more than the threshold
  int pixels = 0;              // pixels compared
};

inline ImageDifference compareImages(const ar::Image8& a, const ar::Image8& b, int threshold) {
  ImageDifference d;
  if (a.width != b.width || a.height != b.height || a.channels != b.channels) return {1e9, 1.0, 0};
  const int n = a.width * a.height;
  long sum = 0, over = 0;
  for (int p = 0; p < n; ++p) {
    int worst = 0;
    for (int c = 0; c < a.channels; ++c) {
      const int diff = std::abs(int(a.pixels[std::size_t(p * a.channels + c)]) - int(b.pixels[std::size_t(p * a.channels + c)]));
      sum += diff;
      worst = std::max(worst, diff);
    }
    over += worst > threshold;
  }
  d.pixels = n;
  d.meanAbs = double(sum) / double(n * a.channels);
  d.fractionOver = double(over) / double(n);
  return d;
}

// Pixels differing from the background colour (the flat clear of these tests).
inline int coveredPixels(const ar::Image8& image, unsigned char r, unsigned char g, unsigned char b) {
  int n = 0;
  for (std::size_t p = 0; p + 2 < image.pixels.size(); p += std::size_t(image.channels))
    n += image.pixels[p] != r || image.pixels[p + 1] != g || image.pixels[p + 2] != b;
  return n;
}

}  // namespace marionette::test
