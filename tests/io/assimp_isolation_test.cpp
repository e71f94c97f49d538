// A crash, hang or memory bomb inside Assimp becomes an error, not a dead process.
#include <gtest/gtest.h>

#include <csignal>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <thread>

#include "isolated_call.hpp"
#include "marionette/io/import.hpp"
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
  ImportResult r = importAsset(path);
  ASSERT_FALSE(r.ok());
  const std::string msg = r.diagnostics.format();
  EXPECT_NE(msg.find(path + ": error: Assimp's reader crashed"), std::string::npos) << msg;
  EXPECT_FALSE(r.asset.has_value());
}
