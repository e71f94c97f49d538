// Running marionette-ar (programPath("marionette-ar")) and reading the
// frames it writes headless: shared by the renderer's end-to-end tests.
#pragma once
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "cli_run.hpp"
#include "marionette_ar/render/image.hpp"

namespace marionette::test {

inline CliRun runAr(const std::string& args) { return runCommand(::marionette::test::programPath("marionette-ar") + " " + args); }

// DIR/frame_NNNN.png, failing the test if it cannot be read.
inline ar::Image8 frame(const std::filesystem::path& dir, int index) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04d.png", index);
  ar::Image8 image;
  Diagnostics error;
  EXPECT_TRUE(ar::readImage((dir / name).string(), image, error)) << error.format();
  return image;
}

}  // namespace marionette::test
