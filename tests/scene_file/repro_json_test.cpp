// Regression tests for the JSON reproducers of ../shared/repro (its README says how each
// was read): scene files, character profiles and joint maps with a NUL byte after valid
// content hung in the walk that places JSON pointers (json_places.hpp); a number too
// large for a double aborted the process. Each must now end at once with an error that
// names the file and the place.
#include <gtest/gtest.h>

#include <regex>
#include <string>

#include "marionette/io/import.hpp"
#include "marionette/rig/joint_map.hpp"
#include "marionette/rig/character_profile.hpp"
#include "marionette/scene/scene.hpp"
#include "marionette/scene_file/scene_file.hpp"
#include "marionette/rig/detail/json_places.hpp"
#include "test_data.hpp"

namespace marionette::test {
namespace {

std::string repro(const std::string& name) { return ::marionette::test::sharedDir() + "/repro/" + name; }

// The first error's text, or "" when there is none.
std::string firstError(const Diagnostics& d) {
  for (const Diagnostic& item : d.items)
    if (item.severity == Severity::Error) return d.format();
  return "";
}

TEST(ReproJson, SceneFilesWithANulByteAreErrorsNamingThePlace) {
  for (const char* name : {"hang_scene_nul_then_brace.json", "scene_fuzz_timeout_1.json", "scene_fuzz_timeout_2.json"}) {
    const std::string path = repro(name);
    MARIONETTE_REQUIRE_FILE(path);
    Scene scene;
    const SceneLoadResult r = loadSceneFile(path, scene);
    SCOPED_TRACE(name);
    EXPECT_FALSE(r.ok());
    const std::string error = firstError(r.diagnostics);
    EXPECT_NE(error.find(name), std::string::npos) << error;
    EXPECT_NE(error.find("NUL byte"), std::string::npos) << error;
    EXPECT_TRUE(std::regex_search(error, std::regex(std::string(name) + R"(:\d+:\d+: error)"))) << error;
    EXPECT_TRUE(scene.characters().empty());
  }
  // The place: line 1, column 19 (the byte after `{"characters": []}`).
  Scene scene;
  const SceneLoadResult r = loadSceneFile(repro("hang_scene_nul_then_brace.json"), scene);
  EXPECT_NE(r.diagnostics.format().find("hang_scene_nul_then_brace.json:1:19: error"), std::string::npos)
      << r.diagnostics.format();
}

TEST(ReproJson, NumberTooLargeForADoubleIsAnErrorNotAnAbort) {
  const std::string path = repro("scene_number_overflow_uncaught_out_of_range.json");
  MARIONETTE_REQUIRE_FILE(path);
  Scene scene;
  const SceneLoadResult r = loadSceneFile(path, scene);
  EXPECT_FALSE(r.ok());
  const std::string error = r.diagnostics.format();
  EXPECT_NE(error.find("scene_number_overflow_uncaught_out_of_range.json:1:"), std::string::npos) << error;
  EXPECT_NE(error.find("1e999"), std::string::npos) << error;
}

TEST(ReproJson, ProfileAndJointMapWithANulByteAreErrors) {
  const std::string robot = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(robot);
  const ImportResult imported = importAsset(robot);
  ASSERT_TRUE(imported.ok()) << imported.diagnostics.format();
  {
    const std::string path = repro("hang_profile_nul_then_comma.json");
    MARIONETTE_REQUIRE_FILE(path);
    const CharacterProfileResult r = loadCharacterProfile(path, *imported.asset);
    const std::string text = r.diagnostics.format();
    EXPECT_NE(text.find("hang_profile_nul_then_comma.json:1:3: error: a NUL byte"), std::string::npos) << text;
  }
  for (const char* name : {"hang_jointmap_nul_then_bracket.json", "jointmap_fuzz_timeout_1.json"}) {
    const std::string path = repro(name);
    MARIONETTE_REQUIRE_FILE(path);
    const retarget::JointMapResult r = retarget::loadJointMap(path, *imported.asset);
    SCOPED_TRACE(name);
    EXPECT_FALSE(r.diagnostics.ok());
    const std::string text = r.diagnostics.format();
    EXPECT_NE(text.find(std::string(name) + ":"), std::string::npos) << text;
    EXPECT_NE(text.find("NUL byte"), std::string::npos) << text;
  }
}

TEST(ReproJson, PlacesWalkEndsOnTextItDoesNotExpect) {
  // The walk runs only on text nlohmann accepted, but it must end on anything: stray
  // closing brackets and commas where a value starts, at the top level and nested.
  for (const std::string& text : {std::string("{}\0}", 4), std::string("{}\0,", 4), std::string("{}\0]", 4),
                                 std::string("}"), std::string("]]]"), std::string(",,,"), std::string("[1}"),
                                 std::string("{\"a\": ]}"), std::string("[[[[[[[[[[}"), std::string("{\"a\"")}) {
    const json_detail::JsonPlaces places(text);  // returns: the test would time out otherwise
    EXPECT_GE(places.value(""), -1);
  }
  const json_detail::JsonPlaces good(R"({"a": [1, {"b": 2}]})");
  EXPECT_EQ(good.value("/a/1/b"), 16);
  EXPECT_EQ(good.key("/a"), 1);
}

}  // namespace
}  // namespace marionette::test
