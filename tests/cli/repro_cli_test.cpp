// The reproducers of ../shared/repro read as its README says (through `marionette`),
// each under `timeout` so that a hang fails in seconds, not at ctest's limit: every one
// ends with exit 2 and an error naming the file, none aborts or takes the machine's
// memory. Also endless inputs (/dev/zero) named where a text file belongs.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_run.hpp"
#include "test_data.hpp"

using namespace marionette::test;

namespace {

std::string repro(const std::string& name) { return ::marionette::test::sharedDir() + "/repro/" + name; }

// `marionette ARGS` killed after 30 s (exit 124 from timeout(1): a hang).
CliRun runBounded(const std::string& args) { return runCommand("timeout 30 " + ::marionette::test::programPath("marionette") + " " + args); }

// The largest resident size of any child this process has waited for, in MiB.
double largestChildMiB() {
  rusage usage{};
  getrusage(RUSAGE_CHILDREN, &usage);
  return double(usage.ru_maxrss) / 1024.0;  // kilobytes on Linux
}

void expectCleanError(const CliRun& r, const std::string& file, const std::string& words) {
  EXPECT_EQ(r.status, 2) << "(124: it hung; -1: it crashed) " << r.out;
  EXPECT_NE(r.out.find(file), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(words), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("terminate called"), std::string::npos) << r.out;
}

}  // namespace

TEST(ReproCli, SceneFilesWithANulByteEndWithAnError) {
  for (const char* name : {"hang_scene_nul_then_brace.json", "scene_fuzz_timeout_1.json", "scene_fuzz_timeout_2.json"}) {
    MARIONETTE_REQUIRE_FILE(repro(name));
    SCOPED_TRACE(name);
    expectCleanError(runBounded("run " + repro(name) + " --frames 1"), name, "NUL byte");
  }
}

TEST(ReproCli, NumberTooLargeForADoubleEndsWithAnError) {
  const std::string name = "scene_number_overflow_uncaught_out_of_range.json";
  MARIONETTE_REQUIRE_FILE(repro(name));
  const CliRun r = runBounded("run " + repro(name) + " --frames 1");
  expectCleanError(r, name + ":1:", "1e999");
}

TEST(ReproCli, AProfileWithANulByteIsNamed) {
  const std::string robot = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(robot);
  const std::string scene = ::testing::TempDir() + "repro_profile_scene.json";
  std::ofstream(scene) << R"({"characters": [{"name": "r", "asset": ")" << robot << R"(", "profile": ")"
                       << repro("hang_profile_nul_then_comma.json") << R"("}]})";
  const CliRun r = runBounded("run " + scene + " --frames 1");
  EXPECT_NE(r.status, 124) << "it hung: " << r.out;
  EXPECT_NE(r.status, -1) << r.out;
  EXPECT_NE(r.out.find("hang_profile_nul_then_comma.json:1:3: error: a NUL byte"), std::string::npos) << r.out;
}

TEST(ReproCli, EndlessStreamsWhereATextFileBelongsAreRefused) {
  const std::string robot = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(robot);
  // As the scene file itself, and as a character profile.
  expectCleanError(runBounded("run /dev/zero --frames 1"), "/dev/zero", "not a regular file");
  const std::string scene = ::testing::TempDir() + "repro_devzero_scene.json";
  std::ofstream(scene) << R"({"characters": [{"name": "r", "asset": ")" << robot << R"(", "profile": "/dev/zero"}]})";
  CliRun r = runBounded("run " + scene + " --frames 1");
  EXPECT_NE(r.status, 124) << "it hung: " << r.out;
  EXPECT_NE(r.out.find("/dev/zero"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("not a regular file"), std::string::npos) << r.out;
  EXPECT_LT(largestChildMiB(), 1024.0) << "an endless stream was read into memory";
#ifdef MARIONETTE_CLI_HAS_BML
  // As a scene's BML file (read when its time comes) and through --bml.
  std::ofstream(scene) << R"({"characters": [{"name": "r", "asset": ")" << robot
                       << R"("}], "bml": [{"file": "/dev/zero", "time": 0}]})";
  r = runBounded("run " + scene + " --frames 3");
  EXPECT_NE(r.status, 124) << "it hung: " << r.out;
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find("/dev/zero: error: cannot read the BML file: is not a regular file"), std::string::npos) << r.out;
  r = runBounded("bml-check /dev/zero");
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find("/dev/zero: error: cannot read the file: is not a regular file"), std::string::npos) << r.out;
#endif
  EXPECT_LT(largestChildMiB(), 1024.0) << "an endless stream was read into memory";
}

#ifdef MARIONETTE_CLI_HAS_PRT
TEST(ReproCli, HdrHeadersDeclaringHugeImagesAreRefusedBeforeAllocating) {
  for (const char* name : {"envmap_80000x40000_uncaught_bad_alloc.hdr", "envmap_8000x16000_1.6GB_rss.hdr"}) {
    MARIONETTE_REQUIRE_FILE(repro(name));
    SCOPED_TRACE(name);
    expectCleanError(runBounded("prt lighting-error --env " + repro(name)), name, "limits::kMaxImagePixels");
  }
  // Measured: 140 MiB in Release (the program and its libraries), ~240 MiB under ASan;
  // reading the 8000 x 16000 header's pixels took 1.6 GB.
  EXPECT_LT(largestChildMiB(), 700.0) << "the declared pixels were allocated";
}
#endif

#ifdef MARIONETTE_CLI_HAS_ASSIMP
TEST(ReproCli, FilesThatCrashAssimpStayCleanErrors) {
  const std::string dir = repro("assimp_child_crashes");
  MARIONETTE_REQUIRE_FILE(dir);
  int files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    ++files;
    const std::string name = e.path().filename().string();
    SCOPED_TRACE(name);
    const CliRun r = runBounded("inspect " + e.path().string());
    EXPECT_EQ(r.status, 2) << r.out;
    EXPECT_NE(r.out.find(name), std::string::npos) << r.out;
  }
  EXPECT_EQ(files, 3);
}
#endif
