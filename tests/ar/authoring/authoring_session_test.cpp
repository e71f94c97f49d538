// The authoring session (marionette_ar/authoring/authoring_session.hpp) and its action files:
// bad files first, then the time model, the click on the floor and each action's effect.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "marionette_ar/authoring/authoring_session.hpp"

namespace marionette::ar {
namespace {

std::string wrap(const std::string& actions) {
  return R"({"format": "marionette-actions", "version": 1, "actions": [)" + actions + "]}";
}

std::string parseError(const std::string& text) {
  Diagnostics d;
  const auto a = parseActions(text, "acts.json", d);
  EXPECT_FALSE(a.has_value()) << text;
  return d.format();
}

TEST(ActionFiles, BadFilesNameTheFileTheActionAndTheKey) {
  EXPECT_NE(parseError("{").find("acts.json: error: not JSON"), std::string::npos);
  EXPECT_NE(parseError("[]").find("a JSON object"), std::string::npos);
  EXPECT_NE(parseError(R"({"format": "marionette-augmentation", "version": 1, "actions": []})").find("'format'"),
            std::string::npos);
  EXPECT_NE(parseError(R"({"format": "marionette-actions", "version": 2, "actions": []})").find("newer marionette"),
            std::string::npos);
  EXPECT_NE(parseError(R"({"format": "marionette-actions", "version": 1})").find("'actions': missing"),
            std::string::npos);
  EXPECT_NE(parseError(wrap(R"({"do": "jump"})")).find("'actions[0].do': \"jump\" is not an action"),
            std::string::npos);
  EXPECT_NE(parseError(wrap(R"({"do": "undo"}, {"do": "place"})")).find("'actions[1].pixel': missing"),
            std::string::npos);
  EXPECT_NE(parseError(wrap(R"({"do": "place", "pixel": [1, "a"]})")).find("'actions[0].pixel'"), std::string::npos);
  EXPECT_NE(parseError(wrap(R"({"do": "rotate", "axes": "local", "plane": "x", "degrees": 10})"))
                .find("'actions[0].plane': expected \"e23\""),
            std::string::npos);
  EXPECT_NE(parseError(wrap(R"({"do": "rotate", "axes": "euler", "plane": "e12", "degrees": 10})"))
                .find("'actions[0].axes'"),
            std::string::npos);
  EXPECT_NE(parseError(wrap(R"({"do": "rotate", "axes": "local", "plane": "e12", "degrees": 1e9})"))
                .find("'actions[0].degrees'"),
            std::string::npos);
  EXPECT_NE(parseError(wrap(R"({"do": "height", "metres": 0})")).find("'actions[0].metres'"), std::string::npos);
  EXPECT_NE(parseError(wrap(R"({"do": "exposure", "ev": 1e999})")).find("not JSON"), std::string::npos);
  EXPECT_NE(parseError(wrap(R"({"do": "save", "frame": 2.5})")).find("'actions[0].frame': expected a whole"),
            std::string::npos);
  EXPECT_NE(parseError(wrap(R"({"do": "pick-character"})")).find("'actions[0].name': missing"), std::string::npos);
  // An unknown key is said, and the action still reads.
  Diagnostics d;
  const auto a = parseActions(wrap(R"({"do": "undo", "colour": 3})"), "acts.json", d);
  ASSERT_TRUE(a.has_value());
  EXPECT_NE(d.format().find("'actions[0].colour': unknown key"), std::string::npos);
}

TEST(ActionFiles, EveryActionRoundTripsThroughTheFile) {
  const std::string text = wrap(R"(
    {"do": "pick-character", "name": "bcn"}, {"do": "pick-bml", "file": "/abs/wave.xml"},
    {"do": "place", "pixel": [330.5, 410], "frame": 12}, {"do": "drag", "from": [330, 410], "to": [300, 380]},
    {"do": "rotate", "axes": "local", "plane": "e23", "degrees": -45}, {"do": "height", "metres": 1.75},
    {"do": "exposure", "ev": -0.5}, {"do": "undo"}, {"do": "save"})");
  Diagnostics d;
  const auto a = parseActions(text, "/dir/acts.json", d);
  ASSERT_TRUE(a.has_value()) << d.format();
  ASSERT_EQ(a->size(), 9u);
  EXPECT_EQ((*a)[2].frame, 12);
  EXPECT_EQ((*a)[2].pixel, glm::vec2(330.5f, 410.0f));
  EXPECT_EQ((*a)[4].axes, ga::Axes::Local);
  EXPECT_EQ((*a)[4].plane, RotationPlane::E23);
  const auto b = parseActions(formatActions(*a), "/dir/acts.json", d);
  ASSERT_TRUE(b.has_value()) << d.format();
  ASSERT_EQ(b->size(), a->size());
  for (std::size_t i = 0; i < a->size(); ++i) {
    EXPECT_EQ((*b)[i].kind, (*a)[i].kind);
    EXPECT_EQ((*b)[i].name, (*a)[i].name);
    EXPECT_EQ((*b)[i].pixel, (*a)[i].pixel);
    EXPECT_EQ((*b)[i].to, (*a)[i].to);
    EXPECT_EQ((*b)[i].value, (*a)[i].value);
    EXPECT_EQ((*b)[i].axes, (*a)[i].axes);
    EXPECT_EQ((*b)[i].plane, (*a)[i].plane);
    EXPECT_EQ((*b)[i].frame, (*a)[i].frame);
  }
  // A relative BML file resolves against the action file's folder.
  const auto c = parseActions(wrap(R"({"do": "pick-bml", "file": "bml/wave.xml"})"), "/dir/acts.json", d);
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ((*c)[0].name, "/dir/bml/wave.xml");
}

TEST(ActionTimeModel, KeystrokeLevelOperators) {
  Action place{.kind = ActionKind::Place};
  EXPECT_NEAR(modelledSeconds(place, nullptr), 1.35 + 1.1 + 0.2, 1e-12);
  Action drag{.kind = ActionKind::Drag};
  EXPECT_NEAR(modelledSeconds(drag, nullptr), 1.35 + 2.2 + 0.2, 1e-12);
  Action slider{.kind = ActionKind::Height, .value = 1.7f};
  EXPECT_NEAR(modelledSeconds(slider, nullptr), modelledSeconds(drag, nullptr), 1e-12);
  Action steps{.kind = ActionKind::Rotate, .axes = ga::Axes::Global, .plane = RotationPlane::E31, .value = -30.0f};
  EXPECT_NEAR(modelledSeconds(steps, nullptr), 1.35 + 2 * 0.28, 1e-12);  // two key presses
  EXPECT_NEAR(modelledSeconds(steps, &steps), 2 * 0.28, 1e-12);          // the same key again: no new decision
  Action other = steps;
  other.axes = ga::Axes::Local;
  EXPECT_NEAR(modelledSeconds(other, &steps), 1.35 + 2 * 0.28, 1e-12);
  Action free = steps;
  free.value = 7.0f;  // not a whole number of 15-degree steps: dragged
  EXPECT_NEAR(modelledSeconds(free, nullptr), modelledSeconds(drag, nullptr), 1e-12);
  Action undo{.kind = ActionKind::Undo};
  EXPECT_NEAR(modelledSeconds(undo, nullptr), 1.35 + 0.56, 1e-12);
}

// A 640x480 camera at (0, 1.5, 3) looking at the origin, 45 degrees vertical field of view.
AuthoringView testView() {
  AuthoringView v;
  v.width = 640;
  v.height = 480;
  v.view = glm::lookAt(glm::vec3(0, 1.5f, 3), glm::vec3(0), glm::vec3(0, 1, 0));
  v.projection = glm::perspective(glm::radians(45.0f), 640.0f / 480.0f, 0.05f, 100.0f);
  v.tracked = true;
  return v;
}

glm::vec2 project(const AuthoringView& v, const glm::vec3& p) {
  const glm::vec4 c = v.projection * v.view * glm::vec4(p, 1.0f);
  const glm::vec2 ndc(c.x / c.w, c.y / c.w);
  return {(ndc.x + 1.0f) * 0.5f * static_cast<float>(v.width) - 0.5f, (1.0f - ndc.y) * 0.5f * static_cast<float>(v.height) - 0.5f};
}

TEST(FloorClick, TheRayMeetsTheTrackedFloorWhereThePointIs) {
  const AuthoringView v = testView();
  for (const glm::vec3 p : {glm::vec3(0), glm::vec3(0.5f, 0, -0.3f), glm::vec3(-1.2f, 0, 0.8f)}) {
    const auto hit = floorPoint(v, project(v, p));
    ASSERT_TRUE(hit.has_value());
    EXPECT_NEAR(glm::distance(*hit, p), 0.0f, 1e-4f);
    EXPECT_EQ(hit->y, 0.0f);
  }
  AuthoringView level = v;  // looking nearly level: the top of the image is sky
  level.view = glm::lookAt(glm::vec3(0, 1.5f, 3), glm::vec3(0, 1.4f, 0), glm::vec3(0, 1, 0));
  EXPECT_FALSE(floorPoint(level, {320, 10}).has_value());  // above the horizon
  EXPECT_TRUE(floorPoint(level, {320, 470}).has_value());
  EXPECT_FALSE(floorPoint(v, {320, 10}, 5.0f).has_value());  // 21 m away: past the limit
  AuthoringView lost = v;
  lost.tracked = false;
  EXPECT_FALSE(floorPoint(lost, {320, 240}).has_value());
  AuthoringView empty = v;
  empty.width = 0;
  EXPECT_FALSE(floorPoint(empty, {320, 240}).has_value());
}

std::vector<CatalogueEntry> catalogue() {
  return {{"bcn", "/assets/bcn.x", 1.70f, glm::vec3(0.01f, -0.99f, 0.02f)}, {"godette", "/assets/godette.vrm", 1.5f, {}}};
}

// AuthoringSession::apply, its refusal's reason in `error` (left as it was when it succeeds).
bool apply(AuthoringSession& s, const Action& action, const AuthoringView& view, std::string& error) {
  Diagnostics d;
  if (s.apply(action, view, d)) return true;
  error = d.items.empty() ? "" : d.items.back().message;
  return false;
}

TEST(AuthoringSession, FailedActionsChangeNothingAndSayWhy) {
  AuthoringSession s({}, catalogue());
  const AuthoringView v = testView();
  std::string error;
  EXPECT_FALSE(apply(s, {.kind = ActionKind::Place, .pixel = {320, 300}}, v, error));
  EXPECT_NE(error.find("pick a character"), std::string::npos);
  EXPECT_FALSE(apply(s, {.kind = ActionKind::PickCharacter, .name = "robot"}, v, error));
  EXPECT_NE(error.find("(it has: bcn, godette)"), std::string::npos);
  ASSERT_TRUE(apply(s, {.kind = ActionKind::PickCharacter, .name = "bcn"}, v, error));
  for (ActionKind k : {ActionKind::Drag, ActionKind::Rotate, ActionKind::Height}) {
    EXPECT_FALSE(apply(s, {.kind = k, .value = 15.0f}, v, error));
    EXPECT_NE(error.find("place the picked character first"), std::string::npos);
  }
  AuthoringView level = v;
  level.view = glm::lookAt(glm::vec3(0, 1.5f, 3), glm::vec3(0, 1.4f, 0), glm::vec3(0, 1, 0));
  EXPECT_FALSE(apply(s, {.kind = ActionKind::Place, .pixel = {320, 5}}, level, error));
  EXPECT_NE(error.find("does not meet the tracked floor"), std::string::npos);
  AuthoringView lost = v;
  lost.tracked = false;
  EXPECT_FALSE(apply(s, {.kind = ActionKind::Place, .pixel = {320, 300}}, lost, error));
  EXPECT_NE(error.find("the camera is lost"), std::string::npos);
  EXPECT_TRUE(s.augmentation().characters.empty());
  EXPECT_EQ(s.undoDepth(), 1u);  // the one pick that worked
  ASSERT_TRUE(apply(s, {.kind = ActionKind::Undo}, v, error));
  EXPECT_EQ(s.pickedEntry(), -1);
  EXPECT_FALSE(apply(s, {.kind = ActionKind::Undo}, v, error));
  EXPECT_EQ(error, "nothing to undo");
}

TEST(AuthoringSession, PlaceFacesTheUserLifeSizeThenMoveTurnSizeUndo) {
  AuthoringSession s({}, catalogue());
  const AuthoringView v = testView();
  std::string error;
  const glm::vec3 spot(0.6f, 0, -0.4f), there(-0.3f, 0, 0.2f);
  ASSERT_TRUE(apply(s, {.kind = ActionKind::PickBml, .name = "/bml/wave.xml"}, v, error)) << error;
  ASSERT_TRUE(apply(s, {.kind = ActionKind::PickCharacter, .name = "bcn"}, v, error)) << error;
  ASSERT_TRUE(apply(s, {.kind = ActionKind::Place, .pixel = project(v, spot)}, v, error)) << error;
  ASSERT_EQ(s.augmentation().characters.size(), 1u);
  const PlacedCharacter& c = s.augmentation().characters[0];
  EXPECT_EQ(c.name, "bcn");
  EXPECT_EQ(c.asset, "/assets/bcn.x");
  EXPECT_EQ(c.bml, "/bml/wave.xml");
  EXPECT_NEAR(glm::distance(c.placement.position, spot), 0.0f, 1e-4f);
  EXPECT_EQ(c.placement.scale, 1.0f);  // its own height: life size
  EXPECT_EQ(c.placement.pivot, catalogue()[0].pivot);
  // Facing the camera: its front (+Z) points at the camera across the floor.
  const ga::Vector<float> front = c.placement.rotation.apply(ga::Vector<float>{0, 0, 1});
  const glm::vec2 toCamera = glm::normalize(glm::vec2(0 - spot.x, 3 - spot.z));
  EXPECT_NEAR(front.x, toCamera.x, 1e-5f);
  EXPECT_NEAR(front.z, toCamera.y, 1e-5f);
  EXPECT_NEAR(front.y, 0.0f, 1e-6f);
  // The pivot (the middle of its feet) stands on the clicked spot.
  const glm::vec4 feet = placementMatrix(c.placement) * glm::vec4(c.placement.pivot, 1.0f);
  EXPECT_NEAR(glm::distance(glm::vec3(feet), spot), 0.0f, 1e-5f);

  // A drag moves it by the floor distance between the two pixels.
  ASSERT_TRUE(apply(s, {.kind = ActionKind::Drag, .pixel = project(v, glm::vec3(0)), .to = project(v, there)}, v, error));
  EXPECT_NEAR(glm::distance(s.augmentation().characters[0].placement.position, spot + there), 0.0f, 1e-4f);
  // Placing the picked character again moves it, turned as it was; no second copy.
  const ga::Rotor turned = s.augmentation().characters[0].placement.rotation;
  ASSERT_TRUE(apply(s, {.kind = ActionKind::Place, .pixel = project(v, there)}, v, error));
  ASSERT_EQ(s.augmentation().characters.size(), 1u);
  EXPECT_NEAR(glm::distance(s.augmentation().characters[0].placement.position, there), 0.0f, 1e-4f);
  EXPECT_EQ(s.augmentation().characters[0].placement.rotation.s, turned.s);

  // Turns: global about +Y, then local about its own x, each the rotor library's step.
  ASSERT_TRUE(apply(s, {.kind = ActionKind::Rotate, .axes = ga::Axes::Global, .plane = RotationPlane::E31, .value = 30},
                      v, error));
  const ga::Rotor expectGlobal = ga::turn(turned, ga::Axes::Global, ga::kPlaneY<float>, glm::radians(30.0f));
  EXPECT_EQ(s.augmentation().characters[0].placement.rotation.s, expectGlobal.s);
  EXPECT_EQ(s.augmentation().characters[0].placement.rotation.b31, expectGlobal.b31);
  ASSERT_TRUE(apply(s, {.kind = ActionKind::Rotate, .axes = ga::Axes::Local, .plane = RotationPlane::E23, .value = -15},
                      v, error));
  const ga::Rotor expectLocal = ga::turn(expectGlobal, ga::Axes::Local, ga::kPlaneX<float>, glm::radians(-15.0f));
  EXPECT_EQ(s.augmentation().characters[0].placement.rotation.b23, expectLocal.b23);
  // Its height: scale = metres / its own height.
  ASSERT_TRUE(apply(s, {.kind = ActionKind::Height, .value = 1.87f}, v, error));
  EXPECT_NEAR(s.augmentation().characters[0].placement.scale, 1.1f, 1e-6f);
  ASSERT_TRUE(apply(s, {.kind = ActionKind::Exposure, .value = -0.5f}, v, error));
  EXPECT_EQ(s.augmentation().exposureEv, -0.5f);

  // Undo walks back one action at a time: exposure, height, the local turn.
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(apply(s, {.kind = ActionKind::Undo}, v, error));
  EXPECT_EQ(s.augmentation().exposureEv, 0.0f);
  EXPECT_EQ(s.augmentation().characters[0].placement.scale, 1.0f);
  EXPECT_EQ(s.augmentation().characters[0].placement.rotation.b23, expectGlobal.b23);
  // A save is counted, changes nothing and is not undone.
  const std::size_t depth = s.undoDepth();
  ASSERT_TRUE(apply(s, {.kind = ActionKind::Save}, v, error));
  EXPECT_EQ(s.saves(), 1);
  EXPECT_EQ(s.undoDepth(), depth);
  // A second character, picked, gets the BML picked last unless another is picked for it.
  ASSERT_TRUE(apply(s, {.kind = ActionKind::PickCharacter, .name = "godette"}, v, error));
  ASSERT_TRUE(apply(s, {.kind = ActionKind::Place, .pixel = project(v, spot)}, v, error));
  ASSERT_TRUE(apply(s, {.kind = ActionKind::PickBml, .name = "/bml/nod.xml"}, v, error));
  ASSERT_EQ(s.augmentation().characters.size(), 2u);
  EXPECT_EQ(s.augmentation().characters[1].bml, "/bml/nod.xml");
  EXPECT_EQ(s.augmentation().characters[0].bml, "/bml/wave.xml");
}

TEST(AuthoringSession, PlacementMatrixPivotsAtTheFeet) {
  Placement p;
  p.position = {1, 0, 2};
  p.pivot = {0.1f, -0.9f, 0};
  p.scale = 2.0f;
  p.rotation = ga::rotation(ga::kPlaneY<float>, glm::radians(90.0f));
  const glm::mat4 m = placementMatrix(p);
  EXPECT_NEAR(glm::distance(glm::vec3(m * glm::vec4(p.pivot, 1)), p.position), 0.0f, 1e-6f);
  // One metre above the pivot is two metres above the spot; +X of the model turns to -Z.
  EXPECT_NEAR(glm::distance(glm::vec3(m * glm::vec4(p.pivot + glm::vec3(0, 1, 0), 1)), p.position + glm::vec3(0, 2, 0)),
              0.0f, 1e-6f);
  EXPECT_NEAR(glm::distance(glm::vec3(m * glm::vec4(p.pivot + glm::vec3(1, 0, 0), 1)), p.position + glm::vec3(0, 0, -2)),
              0.0f, 1e-5f);
  EXPECT_EQ(m[3][3], 1.0f);
}

}  // namespace
}  // namespace marionette::ar
