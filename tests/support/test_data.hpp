// Where the tests find third-party data. Missing data is a test failure, never a skip.
#pragma once
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "test_paths.hpp"

namespace marionette::test {

inline std::string sharedAsset(const std::string& relative) {
  return sharedDir() + "/assets/" + relative;
}
inline std::string assimpModel(const std::string& relative) {
  return assimpModelsDir() + "/" + relative;
}
inline std::string blenderStudiolight(const std::string& relative) {
  return studiolightsDir() + "/" + relative;
}
inline std::string vispImage(const std::string& relative) {  // Debian visp-images-data
  return vispImagesDir() + "/" + relative;
}
inline std::string opencvData(const std::string& relative) {  // Debian opencv-doc
  return opencvDataDir() + "/" + relative;
}
inline std::string sourceFile(const std::string& relative) {
  return sourceDir() + "/" + relative;
}

// The whole file as bytes (empty when it cannot be read).
inline std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Fails the current test (fatally) if the file is missing, naming it.
#define MARIONETTE_REQUIRE_FILE(path)                                                              \
  ASSERT_TRUE(std::filesystem::exists(path))                                                       \
      << "test data missing: " << (path)                                                          \
      << " (../shared beside the checkout, and Debian assimp-testmodels, must be present)"

}  // namespace marionette::test
