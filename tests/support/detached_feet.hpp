// RobotExpressive's feet are IK targets beside its legs, not their children: the
// tests that check they stay on the legs share this. The gap is the distance from
// the foot joint to the leg's end point (the lower leg's model transform applied
// to the foot's rest offset in its frame, as limbEndModel computes it).
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <span>
#include <vector>

#include "marionette/animation/pose.hpp"
#include "marionette/animation/sampling.hpp"
#include "marionette/behavior/two_bone_ik.hpp"
#include "real_rig.hpp"

namespace marionette::test {

struct RobotWithLegs {
  std::shared_ptr<Rig> rig;
  LimbIk legs[2];
};

// RobotExpressive with its shipped profile and both legs prepared for the gap;
// rig is null (with a test failure) when the file, the profile or a detached leg is missing.
inline RobotWithLegs robotWithDetachedFeet() {
  RobotWithLegs r;
  auto rig = loadRigWithProfile(sharedAsset("characters/RobotExpressive.glb"), "RobotExpressive.json");
  if (!rig) return r;
  r.legs[0] = makeLimbIk(rig->skeleton(), rig->joints().leftLeg);
  r.legs[1] = makeLimbIk(rig->skeleton(), rig->joints().rightLeg);
  for (const LimbIk& leg : r.legs) {
    EXPECT_GE(leg.upper, 0);
    EXPECT_FALSE(leg.endIsDescendant);  // the case these tests are about
    if (leg.upper < 0 || leg.endIsDescendant) return r;
  }
  r.rig = std::move(rig);
  return r;
}

inline float footGap(const Skeleton& s, std::span<const Transform> pose, const LimbIk& leg) {
  return glm::length(glm::vec3(modelMatrixOf(s, pose, leg.end)[3]) - limbEndModel(s, pose, leg));
}

// The same from a pose's model matrices.
inline float footGap(std::span<const glm::mat4> model, const LimbIk& leg) {
  const glm::vec3 end(model[static_cast<std::size_t>(leg.lower)] * glm::vec4(leg.endOffsetInLower, 1.0f));
  return glm::length(glm::vec3(model[static_cast<std::size_t>(leg.end)][3]) - end);
}

// The largest gap of either foot over `samples` + 1 poses of the clip as the file has it.
inline float authoredFootGap(const Skeleton& s, const Clip& clip, const LimbIk legs[2], int samples) {
  std::vector<Transform> pose(s.jointCount());
  float worst = 0.0f;
  for (int k = 0; k <= samples; ++k) {
    sampleClip(clip, clip.duration * static_cast<float>(k) / static_cast<float>(samples), s.restPose, pose);
    worst = std::max({worst, footGap(s, pose, legs[0]), footGap(s, pose, legs[1])});
  }
  return worst;
}

}  // namespace marionette::test
