// Pointing on real characters through their shipped profiles: RobotExpressive
// (playing Idle; its arms have no hand joint, so the forearm ends at the palm)
// and Godette (VRM, no clips: the T-pose). Targets ahead, to each side, high,
// low, straight up, behind and far away: the forearm's line passes through the
// target, the arm on the target's side points, nothing is NaN, the other arm is
// left alone. Missing data fails, never skips.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "marionette/scene/scene.hpp"
#include "real_rig.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::test;

namespace {

struct Arm {
  const char *lower, *end;
};

struct Case {
  const char* asset;
  const char* profile;
  Arm left, right;
};

glm::vec3 worldOf(const Character& c, int joint) {
  return glm::vec3(c.transformBuffer().worldMatrix() * c.transformBuffer().modelMatrices()[static_cast<std::size_t>(joint)][3]);
}

void checkPointing(const Case& k) {
  MARIONETTE_REQUIRE_FILE(sharedAsset(k.asset));
  auto rig = loadRigWithProfile(sharedAsset(k.asset), k.profile);
  ASSERT_TRUE(rig);
  const Skeleton& s = rig->skeleton();
  const RigJoints& j = rig->joints();
  Scene probe;
  const Character* standing = probe.addCharacter("probe", rig);
  probe.update(0.0);
  const float height = worldOf(*standing, j.head).y;
  ASSERT_GT(height, 0.3f) << k.asset;
  // The character's own frame from its shoulders (RobotExpressive faces +Z, Godette -Z).
  glm::vec3 left = worldOf(*standing, j.leftArm.upper) - worldOf(*standing, j.rightArm.upper);
  left.y = 0.0f;
  left = glm::normalize(left);
  const glm::vec3 up(0.0f, 1.0f, 0.0f), forward = glm::cross(left, up);
  // Targets in the character's frame (x left, y up, z forward), scaled by its height.
  struct Target {
    glm::vec3 at;
    int side;  // 0 left, 1 right: the arm expected to point
  };
  const Target targets[] = {{{1.0f, 0.9f, 2.0f}, 0},  {{-1.0f, 0.6f, 2.0f}, 1}, {{0.8f, 0.2f, 1.0f}, 0},
                            {{-0.3f, 3.0f, 0.1f}, 1}, {{1.5f, 1.0f, -1.0f}, 0}, {{-200.0f, 50.0f, 500.0f}, 1}};
  float worst = 0.0f, micros = 0.0f;
  int frames = 0;
  for (const Target& t : targets) {
    Scene scene;
    scene.setStatsEnabled(true);
    Character* c = scene.addCharacter("c", rig);
    if (!rig->profile().idle.empty()) c->play(0, rig->profile().idle);
    const glm::vec3 target = (t.at.x * left + t.at.y * up + t.at.z * forward) * height;
    BehaviorRequest r;
    r.id = "point";
    r.kind = BehaviorKind::Pointing;
    r.syncs = {{"start", 0.0}, {"ready", 0.4}, {"relax", 9.0}, {"end", 10.0}};
    r.parameters = PointingParameters{BehaviorTarget::at(target)};
    const BehaviorResult added = c->addBehavior(r);
    ASSERT_TRUE(added.realized) << k.asset << ": " << added.message;
    EXPECT_EQ(added.message, "") << k.asset;
    const Arm& arm = t.side == 0 ? k.left : k.right;
    const Arm& idle = t.side == 0 ? k.right : k.left;
    const int lower = s.findJoint(arm.lower), end = s.findJoint(arm.end);
    const int idleEnd = s.findJoint(idle.end);
    ASSERT_GE(lower, 0);
    ASSERT_GE(end, 0);
    for (int f = 0; f < 90; ++f) {
      scene.update(1.0 / 60.0);
      for (const glm::mat4& m : c->transformBuffer().modelMatrices())
        ASSERT_TRUE(std::isfinite(m[3].x + m[3].y + m[3].z + m[0].x + m[1].y + m[2].z)) << k.asset;
      if (f >= 30) {  // from t = 0.5 s: full weight
        const glm::vec3 elbow = worldOf(*c, lower), wrist = worldOf(*c, end);
        const float e = std::acos(std::clamp(glm::dot(glm::normalize(wrist - elbow), glm::normalize(target - elbow)), -1.0f, 1.0f));
        worst = std::max(worst, e);
        micros += static_cast<float>(c->stats().micros(Controller::Pointing));
        ++frames;
      }
    }
    // The other arm plays what it played: compare with the same character not pointing.
    Scene plain;
    Character* p = plain.addCharacter("p", rig);
    if (!rig->profile().idle.empty()) p->play(0, rig->profile().idle);
    for (int f = 0; f < 90; ++f) plain.update(1.0 / 60.0);
    EXPECT_LT(glm::length(worldOf(*c, idleEnd) - worldOf(*p, idleEnd)), 1e-4f * height)
        << k.asset << ": the arm that does not point moved, target " << describeTarget(BehaviorTarget::at(target));
  }
  std::printf("%s: height %.2f m, worst pointing error %.3f deg over %d frames, pointing %.2f us per frame\n", k.asset,
              static_cast<double>(height), static_cast<double>(glm::degrees(worst)), frames,
              static_cast<double>(micros / static_cast<float>(frames)));
  EXPECT_LT(worst, glm::radians(0.5f)) << k.asset;
  (void)j;
}

}  // namespace

TEST(PointingOnRealCharacters, RobotExpressivePointsWithItsForearms) {
  checkPointing({"characters/RobotExpressive.glb", "RobotExpressive.json", {"LowerArm.L", "Palm2.L"},
                 {"LowerArm.R", "Palm2.R"}});
}

TEST(PointingOnRealCharacters, GodettePointsFromHerTPose) {
  checkPointing({"characters/Godette_vrm_v4.vrm", "Godette_vrm_v4.json", {"lowerarm.l_Armature", "hand.l_Armature"},
                 {"lowerarm.r_Armature", "hand.r_Armature"}});
}
