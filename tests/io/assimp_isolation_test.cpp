// A crash, hang or memory bomb inside Assimp becomes an error, not a dead process.
#include <gtest/gtest.h>

#include <pthread.h>

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <sstream>
#include <thread>

#include "isolated_call.hpp"
#include "marionette/io/import.hpp"
#include "marionette/scene/scene.hpp"
#include "marionette/scene_file/scene_file.hpp"
#include "test_data.hpp"

using namespace marionette;
using marionette::detail::IsolatedOutcome;

TEST(AssimpIsolation, RunIsolatedReportsCrashTimeoutAndExitCode) {
  auto crash = detail::runIsolated([] { std::raise(SIGSEGV); return 0; }, 10.0, 0);
  EXPECT_EQ(crash.kind, IsolatedOutcome::Kind::Crashed);
  EXPECT_EQ(crash.signal, SIGSEGV);
  auto exited = detail::runIsolated([]() -> int { std::_Exit(1); }, 10.0, 0);  // as a sanitizer report ends
  EXPECT_EQ(exited.kind, IsolatedOutcome::Kind::Crashed);
  EXPECT_NE(exited.describe(1.0).find("exit code 1"), std::string::npos);
  auto hang = detail::runIsolated([] { for (;;) std::this_thread::sleep_for(std::chrono::seconds(1)); return 0; }, 0.3, 0);
  EXPECT_EQ(hang.kind, IsolatedOutcome::Kind::TimedOut);
  EXPECT_NE(hang.describe(0.3).find("did not finish"), std::string::npos);
  auto done = detail::runIsolated([] { return 7; }, 10.0, 0);
  EXPECT_EQ(done.kind, IsolatedOutcome::Kind::Completed);
  EXPECT_EQ(done.exitCode, 7);
  auto thrown = detail::runIsolated([]() -> int { throw 1; }, 10.0, 0);
  EXPECT_EQ(thrown.exitCode, 4);
}

TEST(AssimpIsolation, XFileThatCrashesAssimpIsAnErrorNamingTheFile) {
  // Found by tests/fuzz: Assimp 5.2.5's X reader segfaults when a MeshMaterialList
  // lacks its `Material {` keyword. Built here from Debian's test.x.
  const std::string seed = test::assimpModel("X/test.x");
  MARIONETTE_REQUIRE_FILE(seed);
  std::ifstream in(seed, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  const auto at = text.find("Material {");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 10, "          ");
  const std::string path = ::testing::TempDir() + "assimp_crash.x";
  std::ofstream(path, std::ios::binary) << text;
  ImportResult r = importAsset(path, {.isolateThirdPartyParsers = true});  // in-process it would kill the test
  ASSERT_FALSE(r.ok());
  const std::string msg = r.diagnostics.format();
  EXPECT_NE(msg.find(path + ": error: Assimp's reader crashed"), std::string::npos) << msg;
  EXPECT_FALSE(r.asset.has_value());
}

namespace {
std::atomic<int> g_forks{0};  // fork() calls in this process, counted by pthread_atfork
void countFork() { g_forks.fetch_add(1); }
int forksDuring(const std::function<void()>& work) {
  static const bool registered = pthread_atfork(&countFork, nullptr, nullptr) == 0;
  EXPECT_TRUE(registered);
  const int before = g_forks.load();
  work();
  return g_forks.load() - before;
}
}  // namespace

// A library must not fork the process that embeds it: by default Assimp's formats (BVH,
// FBX) are read in-process; only a tool that asks for isolation forks (shown to count).
TEST(AssimpIsolation, DefaultImportForksNoProcess) {
  const std::string bvh = test::sharedAsset("motions/bvh/cmu_01_01_mbfriendly.bvh");
  const std::string fbx = test::sharedAsset("characters/pab_arnaud.fbx");
  MARIONETTE_REQUIRE_FILE(bvh);
  MARIONETTE_REQUIRE_FILE(fbx);
  EXPECT_EQ(forksDuring([&] {
              EXPECT_TRUE(importAsset(bvh).ok());
              EXPECT_TRUE(importAsset(fbx, {.loadMeshes = false}).ok());
            }),
            0);
  EXPECT_GE(forksDuring([&] { EXPECT_TRUE(importAsset(bvh, {.isolateThirdPartyParsers = true}).ok()); }), 1);
}

// Scene files too: a scene of an FBX character with a BVH clip loads without a fork,
// and with SceneLoadOptions::isolateThirdPartyParsers (what the tools set) forks once per file.
TEST(AssimpIsolation, DefaultSceneLoadForksNoProcess) {
  const std::string bvh = test::sharedAsset("motions/bvh/cmu_01_01_mbfriendly.bvh");
  const std::string fbx = test::sharedAsset("characters/pab_arnaud.fbx");
  MARIONETTE_REQUIRE_FILE(bvh);
  MARIONETTE_REQUIRE_FILE(fbx);
  const std::string text = R"({"characters": [{"name": "pab", "asset": ")" + fbx + R"(",
                                "clips": [{"name": "walk", "file": ")" + bvh + R"(", "retarget": true}]}]})";
  for (const bool isolate : {false, true}) {
    Scene scene;
    SceneLoadResult loaded;
    const int forks = forksDuring([&] {
      loaded = loadSceneText(text, "fork_check.json", ".", scene, {.isolateThirdPartyParsers = isolate});
    });
    EXPECT_TRUE(loaded.ok()) << loaded.diagnostics.format();
    if (isolate) EXPECT_GE(forks, 2) << "one isolated parse per Assimp file";
    else EXPECT_EQ(forks, 0);
  }
}
