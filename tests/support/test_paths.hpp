// Where the tests find third-party data, the source tree and the programs they run
// (tests/support/test_paths.cpp holds the paths; tests/CMakeLists.txt sets them).
#pragma once
#include <string>

namespace marionette::test {

std::string sharedDir();        // ../shared beside the checkout (assets, bml-corpus, repro)
std::string assimpModelsDir();  // Debian assimp-testmodels
std::string studiolightsDir();  // Debian blender-data's studio lights
std::string vispImagesDir();    // Debian visp-images-data
std::string opencvDataDir();    // Debian opencv-doc
std::string sourceDir();        // the checkout

// The built program of a CMake target (marionette, marionette-ar, c_embedding,
// marionette_write_sequence); empty when this configuration does not build it.
std::string programPath(const std::string& target);

}  // namespace marionette::test
