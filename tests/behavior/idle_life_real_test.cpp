// Idle life on the two real characters (issue 45, 5): Godette blinks with her VRM blink morphs
// and both breathe, the chest pitching toward each one's own back (Godette faces -Z,
// RobotExpressive +Z) by the asked amplitude; RobotExpressive cannot blink and says why.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "joint_rotation.hpp"
#include "marionette/scene/scene.hpp"
#include "real_rig.hpp"

using namespace marionette;

namespace {

BehaviorRequest emitter(const char* id, BehaviorKind kind, BehaviorParameters parameters) {
  BehaviorRequest r{.id = id, .kind = kind, .syncs = {{"start", 0.0}, {"end", 0.0}}, .parameters = std::move(parameters)};
  r.persistent = true;
  return r;
}

struct Measured {
  float blink = 0.0f, chest = 0.0f;
  bool backward = true;
};

Measured breatheAndBlink(const std::shared_ptr<Rig>& rig, bool blinks) {
  Scene scene;
  Character* c = scene.addCharacter("c", rig);
  const RigJoints& j = c->rig().joints();
  const int chest = j.spine.back();
  scene.update(0.0);
  const glm::quat rest = test::modelRotation(*c, chest);
  // The character's forward at rest: its left crossed with up.
  const glm::vec3 forward = glm::normalize(glm::cross(j.leftAxis, glm::vec3(0.0f, 1.0f, 0.0f)));
  const BehaviorResult b = c->addBehavior(emitter("blink", BehaviorKind::BlinkEmitter, BlinkParameters{.meanIntervalSeconds = 1.0f}));
  EXPECT_EQ(b.realized, blinks) << b.message;
  EXPECT_TRUE(c->addBehavior(emitter("breath", BehaviorKind::BreathingEmitter,
                                     BreathingParameters{.breathsPerMinute = 20.0f, .amplitudeDegrees = 2.0f})).realized);
  int morph = -1;
  if (auto it = j.face.find("CLOSE_EYES"); it != j.face.end()) morph = it->second.front().first;
  Measured m;
  for (int f = 0; f < 10 * 60; ++f) {
    scene.update(1.0 / 60.0);
    if (morph >= 0) m.blink = std::max(m.blink, c->transformBuffer().morphWeights()[static_cast<std::size_t>(morph)]);
    const glm::quat now = test::modelRotation(*c, chest);
    const float a = test::preciseAngleBetween(rest, now) * 57.2957795f;
    m.chest = std::max(m.chest, a);
    // Pitched back: the chest's up moves against the character's forward.
    const glm::vec3 up = now * glm::inverse(rest) * glm::vec3(0.0f, 1.0f, 0.0f);
    if (a > 0.2f && glm::dot(up, forward) >= 0.0f) m.backward = false;
  }
  return m;
}

}  // namespace

TEST(IdleLifeOnRealCharacters, GodetteBlinksAndBothBreatheTowardTheirBacks) {
  auto godette = test::loadRigWithProfile(test::sharedAsset("characters/Godette_vrm_v4.vrm"), "Godette_vrm_v4.json");
  auto robot = test::loadRigWithProfile(test::sharedAsset("characters/RobotExpressive.glb"), "RobotExpressive.json");
  ASSERT_TRUE(godette && robot);
  const Measured g = breatheAndBlink(godette, true), r = breatheAndBlink(robot, false);
  std::printf("Godette: blink morph peak %.3f, chest %.3f degrees; RobotExpressive: chest %.3f degrees (2 asked)\n",
              static_cast<double>(g.blink), static_cast<double>(g.chest), static_cast<double>(r.chest));
  EXPECT_GE(g.blink, 0.99f);
  EXPECT_NEAR(g.chest, 2.0f, 0.05f);
  EXPECT_NEAR(r.chest, 2.0f, 0.05f);
  EXPECT_TRUE(g.backward);
  EXPECT_TRUE(r.backward);
}
