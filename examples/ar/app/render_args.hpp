// marionette-ar's own command line (rendering a scene; the calibrate, track and author
// commands parse theirs): the options, their usage text and the parser.
#pragma once
#include <cstdio>
#include <string>

namespace marionette::ar {

struct RenderArgs {
  std::string scene, outDir, screenshot, audioDir, restore, truth, author, inputScript;
  bool headless = false, hideCharacters = false, json = false, help = false, version = false;
  long frames = -1;  // headless default: 5 s of scene time
  float exposure = -1.0f;
  int width = 0, height = 0;
  std::string prtMode, prtCache;  // empty: as the scene file says
  int prtBands = 0, prtRays = 0;  // 0: as the scene file says
};

// To stdout for --help (exit 0), to stderr after a bad command line (exit 2); returns the exit code.
int renderUsage(std::FILE* to = stderr);
// False after a bad option (the reason printed to stderr).
[[nodiscard]] bool parseRenderArgs(int argc, char** argv, RenderArgs& args);

}  // namespace marionette::ar
