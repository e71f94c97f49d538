// Shared by the PRT tests that write light-probe files: a fresh temporary folder, a float
// image written through OpenImageIO, and a diagnostics text check.
#pragma once
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <filesystem>
#include <string>
#include <vector>

#include "marionette/core/diagnostic.hpp"

namespace marionette::prt::test {

inline std::filesystem::path tempDir(const std::string& name) {
  std::filesystem::path dir = std::filesystem::temp_directory_path() / ("marionette_prt_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline void writeFloatImage(const std::string& path, int w, int h, int nch, const std::vector<float>& data) {
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out) << OIIO::geterror();
  OIIO::ImageSpec spec(w, h, nch, OIIO::TypeDesc::FLOAT);
  ASSERT_TRUE(out->open(path, spec)) << out->geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, data.data())) << out->geterror();
  out->close();
}

inline bool mentions(const Diagnostics& d, const std::string& text) {
  return d.format().find(text) != std::string::npos;
}

}  // namespace marionette::prt::test
