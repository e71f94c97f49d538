// Where the tests find their data and the programs they run. The absolute paths are
// compiled into this one file only: every other test object stays the same from one
// checkout to the next, so a fresh clone (CI) reuses them from the compiler cache.
#include "test_paths.hpp"

#include <cstdlib>
#include <cstring>

namespace marionette::test {

std::string sharedDir() { return MARIONETTE_SHARED_DIR; }
std::string assimpModelsDir() { return MARIONETTE_ASSIMP_MODELS; }
std::string studiolightsDir() { return MARIONETTE_BLENDER_STUDIOLIGHTS; }
std::string vispImagesDir() { return MARIONETTE_VISP_IMAGES; }
std::string opencvDataDir() { return MARIONETTE_OPENCV_DATA; }
std::string sourceDir() { return MARIONETTE_SOURCE_DIR; }

std::string programPath(const std::string& target) {
  // Empty where this configuration does not build the program: running "" then fails the
  // test that asked, naming the command.
  struct Program {
    const char* target;
    const char* path;
  };
  static const Program programs[] = {
      {"marionette", MARIONETTE_PROGRAM_CLI},
      {"marionette-ar", MARIONETTE_PROGRAM_AR},
      {"c_embedding", MARIONETTE_PROGRAM_C_EMBEDDING},
      {"c_shared_assets", MARIONETTE_PROGRAM_C_SHARED_ASSETS},
      {"marionette_write_sequence", MARIONETTE_PROGRAM_WRITE_SEQUENCE},
  };
  for (const Program& p : programs) {
    if (target == p.target) return p.path;
  }
  return {};
}

}  // namespace marionette::test
