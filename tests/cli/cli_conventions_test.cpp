// The `marionette` tool follows command-line conventions (issue 23): --help for every
// command naming every option it takes, --version, unknown options named, output folders
// made and checked before any work, and `run` of a speaking scene to the end of the line.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli_run.hpp"
#include "marionette/version.h"
#include "test_data.hpp"

using namespace marionette::test;
namespace fs = std::filesystem;

namespace {

struct CommandHelp {
  std::string command;
  std::vector<std::string> options;  // each must appear in the command's --help
};

std::vector<CommandHelp> commands() {
  std::vector<CommandHelp> out = {
      {"inspect", {"FILE", "--json"}},
      {"run", {"SCENE", "--frames", "--fps", "--trace", "--morphs", "--audio-dir", "--stats"}},
      {"speak", {"TEXT", "--voice", "--rate", "--output", "--visemes", "--phonemes"}},
      {"lipsync", {"--audio", "--phones", "--visemes"}},
      {"retarget", {"SRC_MOTION", "--to", "--src-map", "--dst-map", "--clip", "--fps", "--ik", "--output", "--report",
                    "--json"}},
  };
#ifdef MARIONETTE_CLI_HAS_BML
  out[1].options.insert(out[1].options.end(), {"--bml", "--feedback"});
  out.push_back({"bml-check", {"FILE", "--character", "--json"}});
#endif
#ifdef MARIONETTE_CLI_HAS_PRT
  out.push_back({"prt", {"lighting-error", "precompute", "report"}});
  out.push_back({"prt lighting-error", {"--env", "--bands", "--window", "--probe", "--json"}});
  out.push_back({"prt precompute", {"MESH", "--output", "--bands", "--rays", "--shadowed", "--threads", "--json"}});
  out.push_back({"prt report", {"--docs", "--quick", "--assets", "--studiolights", "--scripts", "--threads"}});
#endif
  return out;
}

// "(N s of scene time)" from run's summary line; -1 when absent.
double sceneSeconds(const std::string& out) {
  const std::size_t at = out.find(" fps (");
  double s = -1.0;
  if (at != std::string::npos) std::sscanf(out.c_str() + at, " fps (%lf s of scene time)", &s);
  return s;
}

std::string robotScene() {
  const std::string path = ::testing::TempDir() + "conventions_scene.json";
  std::ofstream(path) << R"({"characters": [{"name": "robot", "asset": ")" +
                             sharedAsset("characters/RobotExpressive.glb") + R"("}]})";
  return path;
}

}  // namespace

TEST(CliConventions, EveryCommandHasHelpNamingEachOptionAndExitsZero) {
  for (const CommandHelp& c : commands()) {
    const CliRun r = runCli(c.command + " --help");
    EXPECT_EQ(r.status, 0) << c.command << '\n' << r.out;
    EXPECT_NE(r.out.find("Usage: marionette " + c.command), std::string::npos) << c.command << '\n' << r.out;
    for (const std::string& option : c.options)
      EXPECT_NE(r.out.find(option), std::string::npos) << c.command << " --help lacks " << option << '\n' << r.out;
  }
  // The overview lists every command, and --help-all every command's options.
  const CliRun top = runCli("--help");
  const CliRun all = runCli("--help-all");
  EXPECT_EQ(top.status, 0);
  EXPECT_EQ(all.status, 0);
  for (const CommandHelp& c : commands()) {
    EXPECT_NE(top.out.find(c.command.substr(0, c.command.find(' '))), std::string::npos) << c.command;
    if (c.command.find(' ') != std::string::npos) continue;  // `prt X --help` lists those
    for (const std::string& option : c.options)
      EXPECT_NE(all.out.find(option), std::string::npos) << "--help-all lacks " << c.command << ' ' << option;
  }
  // No command is an error that shows the overview.
  const CliRun none = runCli("");
  EXPECT_EQ(none.status, 2);
  EXPECT_NE(none.out.find("Usage: marionette"), std::string::npos) << none.out;
}

TEST(CliConventions, VersionIsTheLibrarysVersion) {
  const CliRun r = runCli("--version");
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.out, std::string("marionette ") + MARIONETTE_VERSION_STRING + "\n");
}

TEST(CliConventions, UnknownOptionsAndBadValuesAreNamedWithExitTwo) {
  for (const CommandHelp& c : commands()) {
    const CliRun r = runCli(c.command + " --frobnicate");
    EXPECT_EQ(r.status, 2) << c.command << '\n' << r.out;
    EXPECT_NE(r.out.find("marionette " + c.command + ": error:"), std::string::npos) << c.command << '\n' << r.out;
  }
  const CliRun unknown = runCli("inspect some.glb --frobnicate");
  EXPECT_NE(unknown.out.find("--frobnicate"), std::string::npos) << unknown.out;
  const CliRun frames = runCli("run scene.json --frames 2.5");
  EXPECT_EQ(frames.status, 2);
  EXPECT_NE(frames.out.find("--frames: '2.5': expected a whole number"), std::string::npos) << frames.out;
  const CliRun command = runCli("frobnicate");
  EXPECT_EQ(command.status, 2);
  EXPECT_NE(command.out.find("marionette: error: unknown command 'frobnicate'"), std::string::npos) << command.out;
#ifdef MARIONETTE_CLI_HAS_PRT
  const CliRun prt = runCli("prt frobnicate");
  EXPECT_EQ(prt.status, 2);
  EXPECT_NE(prt.out.find("marionette prt: error: unknown command 'frobnicate'"), std::string::npos) << prt.out;
#endif
}

TEST(CliConventions, OutputFoldersAreMadeAndCheckedBeforeAnyWork) {
  const std::string asset = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(asset);
  const std::string scene = robotScene();
  const fs::path dir = fs::path(::testing::TempDir()) / "conventions_out";
  fs::remove_all(dir);
  const std::string trace = (dir / "nested" / "trace.csv").string();
  const CliRun made = runCli("run " + scene + " --frames 3 --trace " + trace);
  ASSERT_EQ(made.status, 0) << made.out;
  std::ifstream in(trace);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "frame,time,character,joint,px,py,pz,qx,qy,qz,qw");

  // A folder that cannot be made (under a file) fails before the scene is loaded.
  const std::string blocked = trace + "/under_a_file.csv";
  const CliRun failed = runCli("run " + scene + " --trace " + blocked);
  EXPECT_EQ(failed.status, 2) << failed.out;
  EXPECT_NE(failed.out.find("--trace: cannot create the folder"), std::string::npos) << failed.out;
  EXPECT_EQ(failed.out.find("loaded"), std::string::npos) << "the scene was loaded first:\n" << failed.out;

  // An existing output file is not truncated by a run that fails later.
  const CliRun badScene = runCli("run /nonexistent/scene.json --trace " + trace);
  EXPECT_EQ(badScene.status, 2);
  EXPECT_GT(fs::file_size(trace), header.size() + 1) << "truncated by a failed run";
  // A folder given where a file is expected.
  const CliRun folder = runCli("run " + scene + " --trace " + dir.string());
  EXPECT_EQ(folder.status, 2);
  EXPECT_NE(folder.out.find("is a folder"), std::string::npos) << folder.out;
  // And a file where a folder is expected.
  const CliRun audio = runCli("run " + scene + " --audio-dir " + trace);
  EXPECT_EQ(audio.status, 2);
  EXPECT_NE(audio.out.find("--audio-dir: '" + trace + "' is a file, not a folder"), std::string::npos) << audio.out;
}

TEST(CliConventions, RunWithoutFramesRunsTwoSecondsOrToTheEndOfTheSpeech) {
  const std::string asset = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(asset);
  const CliRun plain = runCli("run " + robotScene());
  ASSERT_EQ(plain.status, 0) << plain.out;
  EXPECT_NEAR(sceneSeconds(plain.out), 2.0, 1e-6) << plain.out;
  const CliRun fixed = runCli("run " + robotScene() + " --frames 10 --fps 30");
  EXPECT_NEAR(sceneSeconds(fixed.out), 9.0 / 30.0, 1e-6) << fixed.out;  // frame 0 is t = 0
#ifdef MARIONETTE_CLI_HAS_BML
  // godette_speaks: a 3.1 s recorded line sent at 0.5 s. Before, it stopped at 2 s.
  const std::string godette = sharedAsset("characters/Godette_vrm_v4.vrm");
  MARIONETTE_REQUIRE_FILE(godette);
  const CliRun speaks = runCli("run " + sourceFile("assets/scenes/godette_speaks.json"));
  ASSERT_EQ(speaks.status, 0) << speaks.out;
  EXPECT_NE(speaks.out.find("speech: godette"), std::string::npos) << speaks.out;
  EXPECT_NE(speaks.out.find("(to the end of the BML blocks)"), std::string::npos) << speaks.out;
  const double seconds = sceneSeconds(speaks.out);
  EXPECT_GE(seconds, 0.5 + 3.09) << speaks.out;
  EXPECT_LT(seconds, 0.5 + 3.1 + 0.2) << "ran on past the end of the block:\n" << speaks.out;
#endif
}
