// marionette-ar follows the `marionette` tool's conventions (cli_conventions_test.cpp): --help
// for the renderer and each command, naming every option it takes, on stdout with exit 0;
// --version; unknown options named with exit 2.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cli_run.hpp"
#include "marionette/version.h"

namespace marionette::test {
namespace {

struct CommandHelp {
  std::string command;  // "" for the renderer itself
  std::vector<std::string> options;  // each must appear in the command's --help
};

std::vector<CommandHelp> commands() {
  return {
      {"", {"SCENE.json", "--headless", "--frames", "--out", "--screenshot", "--exposure", "--width", "--height",
            "--hide-characters", "--audio-dir", "--prt", "--prt-bands", "--prt-rays", "--prt-cache", "--restore",
            "--truth", "--json", "--author", "--input-script", "--help", "--version", "calibrate", "track", "author"}},
      {"calibrate", {"IMAGES", "--board", "--square", "-o", "--json"}},
      {"track", {"--camera", "--images", "--fps", "--tracker", "--target", "--target-width", "--tag-size", "--map",
                 "--save-map", "--poses", "--json", "--threads", "--no-smoothing"}},
      {"author", {"SCENE.json", "--actions", "-o", "--json"}},
  };
}

std::string program(const std::string& command) {
  return programPath("marionette-ar") + (command.empty() ? "" : " " + command);
}

// stdout alone, and the exit status.
CliRun stdoutOf(const std::string& commandLine) { return runCommand("( " + commandLine + " 2>/dev/null )"); }

TEST(ArCliConventions, EveryCommandHasHelpOnStdoutNamingEachOptionAndExitsZero) {
  for (const CommandHelp& c : commands()) {
    for (const char* flag : {"--help", "-h"}) {
      const CliRun r = stdoutOf(program(c.command) + " " + flag);
      EXPECT_EQ(r.status, 0) << c.command << ' ' << flag << '\n' << r.out;
      EXPECT_NE(r.out.find("usage: marionette-ar" + (c.command.empty() ? "" : " " + c.command)), std::string::npos)
          << c.command << ' ' << flag << '\n' << r.out;
      for (const std::string& option : c.options)
        EXPECT_NE(r.out.find(option), std::string::npos) << c.command << " --help lacks " << option << '\n' << r.out;
    }
  }
  // After other arguments too.
  const CliRun late = stdoutOf(program("track") + " --camera c.yml --help");
  EXPECT_EQ(late.status, 0) << late.out;
  EXPECT_NE(late.out.find("usage: marionette-ar track"), std::string::npos) << late.out;
  // No scene is still an error that shows the usage.
  const CliRun none = runCommand(program(""));
  EXPECT_EQ(none.status, 2);
  EXPECT_NE(none.out.find("usage: marionette-ar"), std::string::npos) << none.out;
}

TEST(ArCliConventions, VersionIsTheLibrarysVersion) {
  for (const CommandHelp& c : commands()) {
    const CliRun r = runCommand(program(c.command) + " --version");
    EXPECT_EQ(r.status, 0) << c.command;
    EXPECT_EQ(r.out, std::string("marionette-ar ") + MARIONETTE_VERSION_STRING + "\n") << c.command;
  }
}

TEST(ArCliConventions, UnknownOptionsAreNamedWithExitTwo) {
  for (const CommandHelp& c : commands()) {
    const CliRun r = runCommand(program(c.command) + " --frobnicate");
    EXPECT_EQ(r.status, 2) << c.command << '\n' << r.out;
    EXPECT_NE(r.out.find("'--frobnicate'"), std::string::npos) << c.command << '\n' << r.out;
  }
}

}  // namespace
}  // namespace marionette::test
