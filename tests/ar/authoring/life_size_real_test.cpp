// Life size on the real characters, the way authoring measures them (startAuthoring's
// sceneCatalogue, examples/ar/app/scene_catalogue.cpp) and places them (AuthoringSession):
// RobotExpressive's file is 4.46 m tall, so a click places it at 1.7 m with a note unless its
// profile's "lifeHeight" says otherwise; BCN_Epileptic's 1.81 m file keeps scale 1 exactly, as the
// demo's saved augmentations and replays expect. GL-free: no window, no tracker.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>

#include <unistd.h>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "marionette/scene/scene.hpp"
#include "marionette/scene_file/scene_file.hpp"
#include "marionette_ar/authoring/authoring_session.hpp"
#include "scene_catalogue.hpp"
#include "test_data.hpp"

namespace marionette::ar {
namespace {

namespace fs = std::filesystem;
using test::sharedAsset;
using test::sourceFile;

AuthoringView view() {  // 3 m back and 2 m up, looking at the origin
  AuthoringView v;
  v.width = 640;
  v.height = 480;
  v.tracked = true;
  v.view = glm::lookAt(glm::vec3(0, 2, 3), glm::vec3(0), glm::vec3(0, 1, 0));
  v.projection = glm::perspective(glm::radians(60.0f), 640.0f / 480.0f, 0.05f, 100.0f);
  return v;
}

struct Authored {
  std::vector<CatalogueEntry> catalogue;
  Diagnostics measured;                 // sceneCatalogue's warnings and notes
  std::map<std::string, float> height;  // each character's height when a click places it
};

// The scene's characters measured as startAuthoring measures them, each picked and placed once.
Authored author(const nlohmann::json& characters) {
  Authored out;
  Scene scene;
  const std::string text = nlohmann::json{{"characters", characters}}.dump();
  const SceneLoadResult loaded = loadSceneText(text, "life_size_scene.json", sourceFile("assets/scenes"), scene,
                                               {.loadMeshes = true});
  EXPECT_TRUE(loaded.ok()) << loaded.diagnostics.format();
  if (!loaded.ok()) return out;
  out.catalogue = sceneCatalogue(scene, loaded, out.measured);
  AuthoringSession s({}, out.catalogue);
  for (const CatalogueEntry& e : out.catalogue) {
    Diagnostics d;
    EXPECT_TRUE(s.apply({.kind = ActionKind::PickCharacter, .name = e.name}, view(), d)) << d.format();
    EXPECT_TRUE(s.apply({.kind = ActionKind::Place, .pixel = {320, 300}}, view(), d)) << d.format();
    const int i = s.pickedCharacter();
    if (i >= 0) out.height[e.name] = e.heightMetres * s.augmentation().characters[static_cast<std::size_t>(i)].placement.scale;
  }
  return out;
}

const Diagnostic* noteAbout(const Diagnostics& d, const std::string& text) {
  for (const Diagnostic& i : d.items)
    if (i.severity == Severity::Note && i.message.find(text) != std::string::npos) return &i;
  return nullptr;
}

TEST(LifeSizeReal, RobotExpressiveStandsAtAPersonsHeightWithANoteBcnAtItsOwn) {
  const std::string robot = sharedAsset("characters/RobotExpressive.glb"), bcn = test::assimpModel("X/BCN_Epileptic.X");
  MARIONETTE_REQUIRE_FILE(robot);
  MARIONETTE_REQUIRE_FILE(bcn);
  // As the shipped profiles are (RobotExpressive.json has no "lifeHeight"), and with none.
  const Authored a = author({{{"name", "RobotExpressive"}, {"asset", robot}},
                             {{"name", "robot"}, {"asset", robot}, {"profile", "../profiles/RobotExpressive.json"}},
                             {{"name", "bcn"}, {"asset", bcn}}});
  ASSERT_EQ(a.catalogue.size(), 3u);
  EXPECT_NEAR(a.catalogue[0].heightMetres, 4.46f, 0.01f);  // its file's own height
  EXPECT_FALSE(a.catalogue[1].profileLifeHeight.has_value());
  for (const char* name : {"RobotExpressive", "robot"}) {
    SCOPED_TRACE(name);
    EXPECT_NEAR(a.height.at(name), 1.7f, 1e-5f);
    const Diagnostic* note = noteAbout(a.measured, std::string(name) + ": its file RobotExpressive.glb is 4.46 m tall");
    ASSERT_NE(note, nullptr) << a.measured.format();
    EXPECT_TRUE(fs::equivalent(note->file, robot)) << note->file;  // names the character's file
    EXPECT_NE(note->message.find("placed at 1.7 m (set \"lifeHeight\" in its profile)"), std::string::npos);
  }
  EXPECT_EQ(a.catalogue[0].lifeSize().note, noteAbout(a.measured, "RobotExpressive:")->message);
  // BCN: its file is a person's height, so life size is scale 1, exactly, and nothing is said.
  EXPECT_NEAR(a.catalogue[2].heightMetres, 1.81f, 0.01f);
  EXPECT_EQ(a.height.at("bcn"), a.catalogue[2].heightMetres);
  EXPECT_EQ(noteAbout(a.measured, "bcn:"), nullptr) << a.measured.format();
}

TEST(LifeSizeReal, RobotExpressiveStandsAtItsProfilesLifeHeight) {
  const std::string robot = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(robot);
  // The shipped profile with a "lifeHeight" (its joint map made absolute: the copy is elsewhere).
  nlohmann::json profile = nlohmann::json::parse(test::readFile(sourceFile("assets/profiles/RobotExpressive.json")));
  profile["jointMap"] = sourceFile("assets/jointmaps/RobotExpressive.json");
  profile["lifeHeight"] = 1.2;
  const fs::path dir = fs::temp_directory_path() / ("marionette_life_size_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "RobotExpressive.json") << profile.dump(2);
  const Authored a = author({{{"name", "robot"}, {"asset", robot}, {"profile", (dir / "RobotExpressive.json").string()}}});
  fs::remove_all(dir);
  ASSERT_EQ(a.catalogue.size(), 1u);
  ASSERT_TRUE(a.catalogue[0].profileLifeHeight.has_value());
  EXPECT_NEAR(a.height.at("robot"), 1.2f, 1e-5f);
  EXPECT_TRUE(a.catalogue[0].lifeSize().note.empty());
  EXPECT_EQ(noteAbout(a.measured, "robot:"), nullptr) << a.measured.format();
}

}  // namespace
}  // namespace marionette::ar
