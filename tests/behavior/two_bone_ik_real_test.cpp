// Two-bone IK on real legs through the shipped profiles: RobotExpressive, whose
// feet are IK targets beside the legs (the end point is the foot's rest offset
// from the lower leg), and Pab, whose feet hang from the shins. Poses from their
// walk clips. Missing data fails, never skips.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "marionette/animation/pose.hpp"
#include "marionette/animation/sampling.hpp"
#include "marionette/behavior/two_bone_ik.hpp"
#include "marionette/io/import.hpp"
#include "marionette/rig/rig.hpp"
#include "real_rig.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::test;

namespace {


glm::vec3 modelPosition(const Skeleton& s, const std::vector<Transform>& pose, int joint) {
  std::vector<glm::mat4> model(pose.size());
  localToModel(s, pose, model);
  return glm::vec3(model[static_cast<std::size_t>(joint)][3]);
}

// For each of `frames` poses of the clip and each leg: targets around the
// current end point, all within reach, are reached; bones keep their length;
// the knee goes the pole's way; weight 0 changes nothing.
void checkLegs(const Rig& rig, const Clip& clip, const char* who) {
  const Skeleton& s = rig.skeleton();
  const RigJoints& j = rig.joints();
  float worst = 0.0f;
  int solved = 0;
  for (const RigJoints::LimbJoints& leg : {j.leftLeg, j.rightLeg}) {
    const LimbIk limb = makeLimbIk(s, leg);
    ASSERT_GE(limb.upper, 0) << who;
    for (int f = 0; f < 12; ++f) {
      std::vector<Transform> pose(s.jointCount());
      sampleClip(clip, clip.duration * static_cast<float>(f) / 12.0f, s.restPose, pose);
      const glm::vec3 hip = modelPosition(s, pose, limb.upper), knee = modelPosition(s, pose, limb.lower);
      const glm::vec3 end = limbEndModel(s, pose, limb);
      const float l1 = glm::distance(hip, knee), l2 = glm::distance(knee, end), full = l1 + l2;
      const glm::vec3 forward(0, 0, 1);  // both characters face +Z (their profiles' sides notes)
      // Lift the foot, step it forward, sideways, back: kept within 0.9 of the length.
      for (const glm::vec3& move : {glm::vec3(0, 0.15f, 0), glm::vec3(0, 0.05f, 0.2f), glm::vec3(0.1f, 0.1f, 0),
                                    glm::vec3(0, 0.2f, -0.15f)}) {
        glm::vec3 target = end + move * full;
        const glm::vec3 d = target - hip;
        if (glm::length(d) > 0.9f * full) target = hip + d * (0.9f * full / glm::length(d));
        const glm::vec3 pole = knee + forward * full;
        std::vector<Transform> solvedPose = pose;
        const float left = solveTwoBoneIk(s, solvedPose, limb, target, pole, 1.0f);
        EXPECT_LT(left, 1e-4f) << who << " frame " << f;
        worst = std::max(worst, left);
        const glm::vec3 h = modelPosition(s, solvedPose, limb.upper), k = modelPosition(s, solvedPose, limb.lower);
        const glm::vec3 e = limbEndModel(s, solvedPose, limb);
        EXPECT_NEAR(glm::distance(h, k), l1, 1e-5f * std::max(1.0f, full)) << who;
        EXPECT_NEAR(glm::distance(k, e), l2, 1e-5f * std::max(1.0f, full)) << who;
        const glm::vec3 line = glm::normalize(target - h);
        const glm::vec3 kneeSide = (k - h) - line * glm::dot(k - h, line);
        const glm::vec3 poleSide = (pole - h) - line * glm::dot(pole - h, line);
        EXPECT_GT(glm::dot(kneeSide, poleSide), 0.0f) << who << " frame " << f;
        ++solved;
      }
      // Out of reach, straight down through the floor: the straightest leg, aimed at it.
      std::vector<Transform> straight = pose;
      const glm::vec3 below = hip - glm::vec3(0, 3.0f * full, 0);
      solveTwoBoneIk(s, straight, limb, below, knee + forward * full, 1.0f, {0.0f});
      EXPECT_NEAR(glm::distance(hip, limbEndModel(s, straight, limb)), full, 1e-4f * std::max(1.0f, full)) << who;
      EXPECT_GT(glm::dot(glm::normalize(limbEndModel(s, straight, limb) - hip), glm::vec3(0, -1, 0)), 1.0f - 1e-5f);
      // Weight 0: bit-identical.
      std::vector<Transform> untouched = pose;
      solveTwoBoneIk(s, untouched, limb, below, knee + forward, 0.0f);
      EXPECT_EQ(std::memcmp(untouched.data(), pose.data(), pose.size() * sizeof(Transform)), 0) << who;
    }
  }
  std::printf("%s: %d leg targets, worst remaining distance %.2e m\n", who, solved, static_cast<double>(worst));
}

}  // namespace

TEST(TwoBoneIkOnRealCharacters, RobotExpressiveLegsWithDetachedFeet) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  auto rig = loadRigWithProfile(sharedAsset("characters/RobotExpressive.glb"), "RobotExpressive.json");
  ASSERT_TRUE(rig);
  const Skeleton& s = rig->skeleton();
  const LimbIk left = makeLimbIk(s, rig->joints().leftLeg);
  ASSERT_GE(left.upper, 0);
  EXPECT_FALSE(left.endIsDescendant);  // Foot.L hangs from the root "Bone"
  // In the rest pose the end point is the foot joint itself.
  EXPECT_LT(glm::distance(limbEndModel(s, s.restPose, left), modelPosition(s, s.restPose, rig->joints().leftLeg.end)),
            1e-5f);
  auto walk = rig->findClip("Walking");
  ASSERT_TRUE(walk);
  checkLegs(*rig, walk->clip, "RobotExpressive Walking");

  // How far the animated foot joint strays from the lower leg's end point during
  // the clip (the exporter baked Blender's leg IK; a figure, loosely bounded).
  float stray = 0.0f, legLength = 0.0f;
  for (int f = 0; f < 24; ++f) {
    std::vector<Transform> pose(s.jointCount());
    sampleClip(walk->clip, walk->clip.duration * static_cast<float>(f) / 24.0f, s.restPose, pose);
    const glm::vec3 foot = modelPosition(s, pose, rig->joints().leftLeg.end);
    stray = std::max(stray, glm::distance(foot, limbEndModel(s, pose, left)));
    legLength = glm::distance(modelPosition(s, pose, left.upper), modelPosition(s, pose, left.lower)) +
                glm::distance(modelPosition(s, pose, left.lower), limbEndModel(s, pose, left));
  }
  std::printf("RobotExpressive Walking: Foot.L is at most %.3f m from the lower leg's end point (leg %.3f m)\n",
              static_cast<double>(stray), static_cast<double>(legLength));
  EXPECT_LT(stray, 0.1f * legLength);
}

#ifdef MARIONETTE_HAS_ASSIMP
TEST(TwoBoneIkOnRealCharacters, PabLegsOnItsWalk) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/pab_arnaud.fbx"));
  MARIONETTE_REQUIRE_FILE(sharedAsset("motions/fbx/pab_walk.fbx"));
  auto rig = loadRigWithProfile(sharedAsset("characters/pab_arnaud.fbx"), "pab_arnaud.json");
  ASSERT_TRUE(rig);
  ImportOptions motionOnly;
  motionOnly.loadMeshes = false;
  ImportResult m = importAsset(sharedAsset("motions/fbx/pab_walk.fbx"), motionOnly);
  ASSERT_TRUE(m.ok() && !m.asset->clips.empty()) << m.diagnostics.format();
  rig->addClip(m.asset->clips.front(), m.asset->skeleton, "walk");
  const LimbIk left = makeLimbIk(rig->skeleton(), rig->joints().leftLeg);
  ASSERT_GE(left.upper, 0);
  EXPECT_TRUE(left.endIsDescendant);
  checkLegs(*rig, rig->findClip("walk")->clip, "Pab walk");
}
#endif
