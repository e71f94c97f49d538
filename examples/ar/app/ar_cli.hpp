// marionette-ar's command-line conventions, the renderer's and each command's alike (as the
// `marionette` tool's, docs/cli.md): --help (-h) prints the usage to stdout and exits 0, a bad
// command line prints it to stderr and exits 2; --version prints the library's version.
#pragma once
#include <cstdio>
#include <string_view>

#include "marionette/version.h"

namespace marionette::ar {

[[nodiscard]] inline bool isHelpFlag(std::string_view arg) noexcept { return arg == "--help" || arg == "-h"; }

// The exit code for a usage printed to `to`: 0 when asked for (stdout), 2 after an error.
[[nodiscard]] inline int usageExitCode(std::FILE* to) noexcept { return to == stdout ? 0 : 2; }

inline int printVersion() {
  std::printf("marionette-ar %s\n", MARIONETTE_VERSION_STRING);
  return 0;
}

}  // namespace marionette::ar
