#include <gtest/gtest.h>

#include <cmath>

#include "marionette/scene_file/scene_file.hpp"
#include "marionette/speech/speech_backend.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::test;

namespace {
SceneLoadResult load(const std::string& json, Scene& scene) {
  return loadSceneText(json, "scene.json", ::marionette::test::sharedDir() + "/assets/characters", scene);
}
std::string errors(const SceneLoadResult& r) { return r.diagnostics.format(); }
}  // namespace

TEST(SceneFile, SyntaxErrorNamesLineAndColumn) {
  Scene scene;
  auto r = load("{\n  \"characters\": [\n    {\"name\": \"a\",, }\n  ]\n}", scene);
  ASSERT_FALSE(r.ok());
  ASSERT_EQ(r.diagnostics.items.size(), 1u);
  EXPECT_EQ(r.diagnostics.items[0].line, 3);
  EXPECT_GT(r.diagnostics.items[0].column, 10);
  EXPECT_NE(errors(r).find("scene.json:3:"), std::string::npos) << errors(r);
}

TEST(SceneFile, SemanticErrorsNameThePath) {
  Scene scene;
  auto r = load(R"({"characters": [{"name": "a"}, {"asset": "x.glb"}, {"name": "c", "asset": "RobotExpressive.glb", "position": [0, "up", 0]}]})", scene);
  ASSERT_FALSE(r.ok());
  const std::string e = errors(r);
  EXPECT_NE(e.find("/characters/0: missing \"asset\""), std::string::npos) << e;
  EXPECT_NE(e.find("/characters/1: missing \"name\""), std::string::npos) << e;
  EXPECT_NE(e.find("/characters/2/position/1: expected a number"), std::string::npos) << e;
  EXPECT_TRUE(scene.characters().empty());  // nothing added on error
  auto top = load("[1, 2]", scene);
  EXPECT_NE(errors(top).find("\"characters\" array"), std::string::npos);
}

TEST(SceneFile, MissingAssetAndUnknownClipAreErrors) {
  Scene scene;
  auto r = load(R"({"characters": [{"name": "a", "asset": "nope.glb"}]})", scene);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(errors(r).find("nope.glb"), std::string::npos);
  EXPECT_NE(errors(r).find("does not exist"), std::string::npos);
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  auto c = load(R"({"characters": [{"name": "a", "asset": "RobotExpressive.glb", "play": "Moonwalk"}]})", scene);
  ASSERT_FALSE(c.ok());
  EXPECT_NE(errors(c).find("no clip named 'Moonwalk'"), std::string::npos) << errors(c);
  EXPECT_NE(errors(c).find("Walking"), std::string::npos);  // lists what exists
  EXPECT_TRUE(scene.characters().empty());
}

TEST(SceneFile, MinimalFormDefaultsAndSharedAssets) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  Scene scene;
  auto r = load(R"({"characters": [
      {"name": "robot", "asset": "RobotExpressive.glb"},
      {"name": "twin", "asset": "RobotExpressive.glb", "position": [2, 0, 1], "heading": 90,
       "play": [{"clip": "Walking", "rootMotion": true}, {"clip": "Wave", "weight": 0.5, "layer": 1}]}]})",
                scene);
  ASSERT_TRUE(r.ok()) << errors(r);
  EXPECT_EQ(r.charactersAdded, 2);
  EXPECT_EQ(r.assetsLoaded, 1);  // loaded once, shared
  Character* robot = scene.findCharacter("robot");
  Character* twin = scene.findCharacter("twin");
  ASSERT_TRUE(robot && twin);
  EXPECT_EQ(&robot->rig(), &twin->rig());
  EXPECT_EQ(robot->position(), glm::vec3(0.0f));
  EXPECT_EQ(robot->heading(), 0.0f);
  EXPECT_EQ(robot->layerCount(), 1);  // plays its first clip
  EXPECT_EQ(twin->layerCount(), 2);
  EXPECT_NEAR(glm::degrees(twin->heading()), 90.0f, 1e-4f);
  for (int i = 0; i < 60; ++i) scene.update(1.0 / 60.0);
  // RobotExpressive's Walking is authored in place: root motion keeps the twin where it stands.
  EXPECT_NEAR(twin->position().x, 2.0f, 0.01f);
  EXPECT_NEAR(twin->position().z, 1.0f, 0.01f);
}

#ifdef MARIONETTE_HAS_ASSIMP  // Pab files are FBX
TEST(SceneFile, PabWalkWithRootMotionTravelsItsAuthoredDistance) {
  const std::string walk = sharedAsset("motions/fbx/pab_walk.fbx");
  MARIONETTE_REQUIRE_FILE(walk);
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/pab_arnaud.fbx"));
  Scene scene;
  auto r = load(R"({"characters": [{"name": "arnaud", "asset": "pab_arnaud.fbx", "heading": -90,
      "clips": [{"file": ")" + walk + R"(", "name": "walk"}], "play": [{"clip": "walk", "rootMotion": true}]}]})",
                scene);
  ASSERT_TRUE(r.ok()) << errors(r);
  Character* c = scene.findCharacter("arnaud");
  const double cycle = c->rig().findClip("walk")->clip.duration;
  EXPECT_NEAR(cycle, 1.3333, 0.002);
  // Ten cycles in 1/60 s steps; facing -X (heading -90°), the walk goes along -X.
  const int steps = static_cast<int>(std::lround(10.0 * cycle * 60.0));
  for (int i = 0; i < steps; ++i) scene.update(1.0 / 60.0);
  const double travelled = std::fabs(c->position().x);
  EXPECT_NEAR(travelled, 14.25, 0.3);  // 1.425 m per cycle, measured from the clip's hips
  EXPECT_LT(c->position().x, 0.0f);
  EXPECT_NEAR(c->position().z, 0.0f, 0.05f);
  // The hips stay over the character's origin (in place), within the sway.
  const glm::mat4& hips = c->transformBuffer().modelMatrices()[c->skeleton().findJoint("Hips")];
  EXPECT_LT(std::hypot(hips[3].x, hips[3].z), 0.15f);
}
#endif

// A character's "profile" (relative to the scene file) replaces the guessed one;
// a broken one is an error that names it.
TEST(SceneFile, CharacterProfileFromTheSceneFile) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  const std::string profile = sourceFile("assets/profiles/RobotExpressive.json");
  MARIONETTE_REQUIRE_FILE(profile);
  Scene scene;
  auto r = load(R"({"characters": [{"name": "robot", "asset": "RobotExpressive.glb", "profile": ")" + profile + R"("}]})",
                scene);
  ASSERT_TRUE(r.ok()) << errors(r);
  const Rig& rig = scene.findCharacter("robot")->rig();
  EXPECT_EQ(rig.profile().head, "Head");
  EXPECT_GE(rig.joints().head, 0);
  EXPECT_FALSE(rig.joints().face.empty());
  Scene other;
  auto bad = load(R"({"characters": [{"name": "robot", "asset": "RobotExpressive.glb", "profile": "nope.json"}]})", other);
  EXPECT_FALSE(bad.ok());
  EXPECT_NE(errors(bad).find("/characters/0/profile: could not load 'nope.json'"), std::string::npos) << errors(bad);
}

// "bmlDialect" (issue 24): the file's for every character, a character's own first; a name
// that is not a dialect is an error at its place. The middleware only checks and hands on.
TEST(SceneFile, BmlDialectPerFileAndPerCharacter) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  Scene scene;
  auto r = load(R"({"bmlDialect": "smartbody", "characters": [
      {"name": "a", "asset": "RobotExpressive.glb"},
      {"name": "b", "asset": "RobotExpressive.glb", "bmlDialect": "bml"}]})",
                scene);
  ASSERT_TRUE(r.ok()) << errors(r);
  using Pair = std::pair<std::string, std::string>;
  EXPECT_EQ(r.bmlDialects, (std::vector<Pair>{{"a", "smartbody"}, {"b", "bml"}}));
  Scene none;
  auto plain = load(R"({"characters": [{"name": "a", "asset": "RobotExpressive.glb"}]})", none);
  ASSERT_TRUE(plain.ok()) << errors(plain);
  EXPECT_TRUE(plain.bmlDialects.empty()) << "not given: the realizer's own";
  Scene bad;
  auto wrong = load(R"({"bmlDialect": "greta", "characters": [
      {"name": "a", "asset": "RobotExpressive.glb", "bmlDialect": 3}]})",
                    bad);
  EXPECT_FALSE(wrong.ok());
  EXPECT_NE(errors(wrong).find("scene.json:1:"), std::string::npos) << errors(wrong);
  EXPECT_NE(errors(wrong).find("/bmlDialect: \"greta\" is not a BML dialect (auto, bml or smartbody)"), std::string::npos)
      << errors(wrong);
  EXPECT_NE(errors(wrong).find("/characters/0/bmlDialect: expected a non-empty string"), std::string::npos) << errors(wrong);
  EXPECT_TRUE(bad.characters().empty());
}

// "objects": named places for targets (issue 24, 6), named at their place when wrong.
TEST(SceneFile, ObjectsAreNamedPlaces) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  Scene scene;
  auto r = load(R"({"characters": [{"name": "robot", "asset": "RobotExpressive.glb"}],
                   "objects": [{"name": "camera", "position": [0, 1.6, 3]}, {"name": "cup", "position": [0.5, 0.9, 0.2]}]})",
                scene);
  ASSERT_TRUE(r.ok()) << errors(r);
  ASSERT_TRUE(scene.findObject("camera"));
  EXPECT_EQ(*scene.findObject("cup"), glm::vec3(0.5f, 0.9f, 0.2f));
  Scene bad;
  auto wrong = load(R"({"characters": [{"name": "cup", "asset": "RobotExpressive.glb"}],
                       "objects": [{"name": "cup", "position": [0, 0, 0]}, {"name": "cup", "position": [1, 0, 0]},
                                   {"name": "lamp", "position": [0, "up", 0]}, {"place": "x"}]})",
                    bad);
  EXPECT_FALSE(wrong.ok());
  const std::string e = errors(wrong);
  EXPECT_NE(e.find("/objects/1/name: an object named 'cup' exists already in this file"), std::string::npos) << e;
  EXPECT_NE(e.find("/objects/2/position/1: expected a number"), std::string::npos) << e;
  EXPECT_NE(e.find("/objects/3: expected {\"name\": NAME, \"position\": [x, y, z]}"), std::string::npos) << e;
  EXPECT_NE(e.find("/characters/0/name: 'cup' names an object of this file too"), std::string::npos) << e;
  EXPECT_TRUE(bad.objects().empty());
  EXPECT_TRUE(bad.characters().empty());
}

// "speech": {"voices"}: other engines' voice names, given to the scene's speech service; bad
// entries are errors naming their path.
TEST(SceneFile, SpeechVoicesMapNamesAndBadOnesAreNamed) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  Scene scene;
  auto bad = load(R"({"characters": [], "speech": {"voices": {"openmary": 3, "": "de"}}})", scene);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(errors(bad).find("/speech/voices/openmary"), std::string::npos) << errors(bad);
  EXPECT_NE(errors(bad).find("/speech/voices/: expected a non-empty voice name"), std::string::npos) << errors(bad);
  auto notObject = load(R"({"characters": [], "speech": {"voices": "en-us"}})", scene);
  EXPECT_NE(errors(notObject).find("/speech/voices: expected an object"), std::string::npos) << errors(notObject);

  struct Recording : speech::SpeechBackend {
    std::string voice;
    std::string_view name() const noexcept override { return "recording"; }
    speech::SpeechResult synthesize(const speech::SpeechRequest& r) override {
      voice = r.voice;
      auto u = std::make_shared<speech::Utterance>();
      u->text = r.text;
      u->duration = 0.5;
      return {u, {}};
    }
  };
  auto recording = std::make_shared<Recording>();
  Scene voiced;
  voiced.speech().addBackend(recording);
  auto ok = load(R"({"characters": [], "speech": {"voices": {"OpenMary": "en-gb"}, "synthesizer": false}})", voiced);
  ASSERT_TRUE(ok.ok()) << errors(ok);
  speech::SpeechRequest r;
  r.text = "hello";
  r.voice = "openmary";
  ASSERT_TRUE(voiced.speech().speak(r).line);
  EXPECT_EQ(recording->voice, "en-gb");
}
