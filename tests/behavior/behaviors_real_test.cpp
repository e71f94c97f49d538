// Head movements and face expressions on the real characters in ../shared/assets,
// through their shipped profiles.
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <cstdio>

#include "marionette/io/import.hpp"
#include "gaze_hold.hpp"
#include "joint_rotation.hpp"
#include "marionette/scene/scene.hpp"
#include "real_rig.hpp"
#include "test_data.hpp"

using namespace marionette;
using marionette::test::modelRotation;
using marionette::test::preciseAngleBetween;
using namespace marionette::test;

namespace {

BehaviorRequest nod(double start) {
  BehaviorRequest r;
  r.id = "nod";
  r.kind = BehaviorKind::Head;
  r.parameters = HeadParameters{HeadLexeme::Nod, 1.0f};
  for (auto [name, at] : std::initializer_list<std::pair<const char*, double>>{
           {"start", 0}, {"ready", .1}, {"strokeStart", .2}, {"stroke", .3}, {"strokeEnd", .5}, {"relax", .8}, {"end", 1}})
    r.syncs.push_back({name, start + at});
  return r;
}

// A NECK gaze at a world point, blending in over 0.3 s and out from `relax` to `end`.
BehaviorRequest gazeAt(const glm::vec3& target, double relax, double end) {
  BehaviorRequest g;
  g.id = "look";
  g.kind = BehaviorKind::Gaze;
  g.parameters = GazeParameters{BehaviorTarget::at(target), GazeInfluence::Neck};
  g.syncs = {{"start", 0.0}, {"ready", 0.3}, {"relax", relax}, {"end", end}};
  return g;
}
}  // namespace

// RobotExpressive playing Idle: at the stroke the head has turned 25 degrees about
// the character's lateral axis relative to the same Idle frame without the nod.
TEST(BehaviorsOnRealCharacters, RobotNodsOverItsIdle) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  auto rig = loadRigWithProfile(sharedAsset("characters/RobotExpressive.glb"), "RobotExpressive.json");
  ASSERT_TRUE(rig);
  const int head = rig->joints().head;
  ASSERT_GE(head, 0);
  Scene with, without;
  Character* a = with.addCharacter("a", rig);
  Character* b = without.addCharacter("b", rig);
  ASSERT_TRUE(a->play(0, "Idle"));
  ASSERT_TRUE(b->play(0, "Idle"));
  ASSERT_TRUE(a->addBehavior(nod(0.0)).realized);
  with.update(0.3);
  without.update(0.3);
  const glm::quat delta = modelRotation(*a, head) * glm::inverse(modelRotation(*b, head));
  EXPECT_LT(preciseAngleBetween(delta, glm::angleAxis(glm::radians(25.0f), glm::vec3(1, 0, 0))), glm::radians(0.5f));
  with.update(0.5);
  without.update(0.5);
  EXPECT_LT(preciseAngleBetween(modelRotation(*a, head), modelRotation(*b, head)), 1e-4f);  // the nod is over
}

// Godette (VRM): SMILE maps to its joy expression through the shipped profile.
TEST(BehaviorsOnRealCharacters, GodetteSmiles) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/Godette_vrm_v4.vrm"));
  auto rig = loadRigWithProfile(sharedAsset("characters/Godette_vrm_v4.vrm"), "Godette_vrm_v4.json");
  ASSERT_TRUE(rig);
  auto it = rig->joints().face.find("SMILE");
  ASSERT_NE(it, rig->joints().face.end());
  Scene scene;
  Character* g = scene.addCharacter("g", rig);
  BehaviorRequest smile;
  smile.id = "smile";
  smile.kind = BehaviorKind::FaceLexeme;
  smile.parameters = FaceParameters{"SMILE"};
  smile.syncs = {{"start", 0.0}, {"attackPeak", 0.3}, {"relax", 1.2}, {"end", 1.5}};
  ASSERT_TRUE(g->addBehavior(smile).realized);
  scene.update(0.6);
  for (const auto& [morph, amount] : it->second)
    EXPECT_NEAR(g->transformBuffer().morphWeights()[static_cast<std::size_t>(morph)], amount, 1e-6);
  scene.update(1.0);
  for (const auto& [morph, amount] : it->second)
    EXPECT_EQ(g->transformBuffer().morphWeights()[static_cast<std::size_t>(morph)], 0.0f);
}

// Godette has no AU morphs: a WINK goes through FACS (AU46_L) to VRM's Blink_L, whose morphs
// reach their full weight on the left eye only, and RAISE_BROWS (AU1 + AU2) to her brow joints.
TEST(BehaviorsOnRealCharacters, GodetteWinksAndRaisesHerBrowsThroughFacs) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/Godette_vrm_v4.vrm"));
  auto rig = loadRigWithProfile(sharedAsset("characters/Godette_vrm_v4.vrm"), "Godette_vrm_v4.json");
  ASSERT_TRUE(rig);
  const auto left = rig->joints().facs.find("AU46_L");
  ASSERT_NE(left, rig->joints().facs.end());
  EXPECT_NE(left->second.source.find("VRM expression"), std::string::npos) << left->second.source;
  for (const std::string& note : rig->profile().notes)  // the figure controllers.md gives
    if (note.starts_with("facs:")) std::printf("Godette %s\n", note.c_str());
  ASSERT_FALSE(left->second.morphs.empty());
  Scene scene;
  Character* g = scene.addCharacter("g", rig);
  BehaviorRequest wink;
  wink.id = "wink";
  wink.kind = BehaviorKind::FaceLexeme;
  wink.parameters = FaceParameters{"WINK"};
  wink.syncs = {{"start", 0.0}, {"attackPeak", 0.1}, {"relax", 0.3}, {"end", 0.4}};
  BehaviorResult r = g->addBehavior(wink);
  ASSERT_TRUE(r.realized) << r.message;
  EXPECT_NE(r.message.find("face 'WINK' is shown through FACS: AU46_L by VRM expression"), std::string::npos) << r.message;
  BehaviorRequest brows = wink;
  brows.id = "brows";
  brows.parameters = FaceParameters{"RAISE_BROWS"};
  r = g->addBehavior(brows);
  ASSERT_TRUE(r.realized) << r.message;
  EXPECT_NE(r.message.find("brow joints"), std::string::npos) << r.message;
  const int brow = rig->skeleton().findJoint("brow1.l_Armature");
  ASSERT_GE(brow, 0);
  scene.update(0.0);
  const glm::vec3 rest(g->transformBuffer().modelMatrices()[static_cast<std::size_t>(brow)][3]);
  scene.update(0.2);
  for (const auto& [morph, amount] : left->second.morphs)
    EXPECT_NEAR(g->transformBuffer().morphWeights()[static_cast<std::size_t>(morph)], amount, 1e-6);
  // The right eye stays open: no morph of Blink_R moves unless Blink_L shares it.
  if (const auto right = rig->joints().facs.find("AU46_R"); right != rig->joints().facs.end())
    for (const auto& [morph, amount] : right->second.morphs) {
      const bool shared = std::any_of(left->second.morphs.begin(), left->second.morphs.end(),
                                      [&](const auto& m) { return m.first == morph; });
      if (!shared) EXPECT_EQ(g->transformBuffer().morphWeights()[static_cast<std::size_t>(morph)], 0.0f);
    }
  const glm::vec3 raised(g->transformBuffer().modelMatrices()[static_cast<std::size_t>(brow)][3]);
  EXPECT_NEAR(raised.y - rest.y, 2 * 0.006f * rig->joints().eyeHeight, 1e-4f);  // AU1 and AU2 each lift it
  scene.update(0.3);
  for (const auto& [morph, amount] : left->second.morphs)
    EXPECT_EQ(g->transformBuffer().morphWeights()[static_cast<std::size_t>(morph)], 0.0f);
}

// RobotExpressive looks at a point 40 degrees to its left and a little below, at
// NECK influence: once settled, its head faces the point within 3 degrees.
TEST(BehaviorsOnRealCharacters, RobotGazesAtAPoint) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  auto rig = loadRigWithProfile(sharedAsset("characters/RobotExpressive.glb"), "RobotExpressive.json");
  ASSERT_TRUE(rig);
  const int head = rig->joints().head;
  Scene scene;
  Character* robot = scene.addCharacter("robot", rig);
  robot->setPosition({1, 0, -2});
  robot->setHeading(0.5f);
  scene.update(0.0);
  const glm::quat rest = modelRotation(*robot, head);
  const glm::vec3 headWorld = glm::vec3(robot->worldMatrix() * robot->transformBuffer().modelMatrices()[head][3]);
  const float yaw = 0.5f + glm::radians(40.0f), pitch = glm::radians(10.0f);
  const glm::vec3 dir(std::sin(yaw) * std::cos(pitch), -std::sin(pitch), std::cos(yaw) * std::cos(pitch));
  const glm::vec3 target = headWorld + 3.0f * dir;
  BehaviorResult r = robot->addBehavior(gazeAt(target, 9.0, 10.0));
  ASSERT_TRUE(r.realized) << r.message;
  for (int f = 0; f < 120; ++f) scene.update(1.0 / 60.0);
  // The head's rest forward is the character's +Z; carried into the world.
  const glm::quat worldTurn = glm::angleAxis(robot->heading(), glm::vec3(0, 1, 0));
  const glm::vec3 forward = worldTurn * ((modelRotation(*robot, head) * glm::inverse(rest)) * glm::vec3(0, 0, 1));
  const glm::vec3 headNow = glm::vec3(robot->worldMatrix() * robot->transformBuffer().modelMatrices()[head][3]);
  const float error = glm::degrees(std::acos(std::clamp(glm::dot(glm::normalize(forward), glm::normalize(target - headNow)), -1.0f, 1.0f)));
  EXPECT_LT(error, 3.0f);
  RecordProperty("head_forward_error_degrees", std::to_string(error));
}

namespace {
// Gazes (NECK) at `target` from 0 to 4 s over `clip` on layer 0 and returns the worst
// head-forward error over the hold, from 1 s (the gaze has settled: 4 time constants
// after its ready) to the relax at 3.7 s, printing it.
float worstGazeOverClip(const std::shared_ptr<Rig>& rig, std::shared_ptr<const AnimationClip> clip, const glm::vec3& target,
                        const char* what) {
  const int head = rig->joints().head;
  Scene scene;
  Character* c = scene.addCharacter("c", rig);
  // The head's rest facing, from the rest pose (before the clip moves it).
  scene.update(0.0);
  const glm::quat rest = modelRotation(*c, head);
  EXPECT_TRUE(c->play(0, std::move(clip)));
  const BehaviorResult r = c->addBehavior(gazeAt(target, 3.7, 4.0));
  EXPECT_TRUE(r.realized) << r.message;
  float worst = 0.0f, worstAt = 0.0f;
  for (int f = 1; f <= 222; ++f) {  // to 3.7 s, the relax: the whole hold
    scene.update(1.0 / 60.0);
    if (scene.time() < 1.0) continue;
    const float e = gazeErrorDegrees(*c, head, rest, gazeOriginWorld(*c), target);
    if (e > worst) worst = e, worstAt = static_cast<float>(scene.time());
  }
  std::printf("%s: worst head-forward error over the hold %.2f deg (at %.2f s)\n", what, static_cast<double>(worst),
              static_cast<double>(worstAt));
  return worst;
}
}  // namespace

// RobotExpressive's Idle turns its head right round between 2.1 and 2.5 s: the gaze holds.
TEST(BehaviorsOnRealCharacters, RobotGazeHoldsOverItsIdle) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  auto rig = loadRigWithProfile(sharedAsset("characters/RobotExpressive.glb"), "RobotExpressive.json");
  ASSERT_TRUE(rig);
  auto idle = rig->findClip("Idle");
  ASSERT_TRUE(idle);
  const float worst = worstGazeOverClip(rig, idle, {1.5f, 1.0f, 3.0f}, "RobotExpressive over Idle");
  EXPECT_LE(worst, 3.0f);  // goal
  // regression: docs/accuracy.md ("Gaze holding") publishes 0.87 degrees; 1.5x.
  EXPECT_LE(worst, 1.3f);
  RecordProperty("worst_head_forward_error_degrees", std::to_string(worst));
}

// Godette under a clip that turns her head 150 degrees and back.
TEST(BehaviorsOnRealCharacters, GodetteGazeHoldsOverAHeadTurn) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/Godette_vrm_v4.vrm"));
  auto rig = loadRigWithProfile(sharedAsset("characters/Godette_vrm_v4.vrm"), "Godette_vrm_v4.json");
  ASSERT_TRUE(rig);
  ASSERT_GE(rig->joints().head, 0);
  const float worst = worstGazeOverClip(rig, headTurnClip(rig->skeleton(), rig->joints().head, 150.0f, 4.0f),
                                        {-1.0f, 1.2f, 2.5f}, "Godette over a 150-degree head turn");
  EXPECT_LE(worst, 3.0f);  // goal
  // regression: docs/accuracy.md ("Gaze holding") publishes 0.35 degrees; 1.5x.
  EXPECT_LE(worst, 0.53f);
  RecordProperty("worst_head_forward_error_degrees", std::to_string(worst));
}
