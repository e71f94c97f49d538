// Two-bone IK on a synthetic leg: invalid limbs and targets first, then reach,
// bone lengths, the pole, the soft limit near full extension, weights, and the
// stiff cases (target at the hip, far away, straight chain, scaled and mirrored
// root spaces, a detached end joint).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "marionette/animation/pose.hpp"
#include "marionette/behavior/two_bone_ik.hpp"
#include "synthetic.hpp"
#include "synthetic_leg.hpp"

using namespace marionette;
using namespace marionette::test;

namespace {

std::vector<glm::vec3> modelPositions(const Skeleton& s, const std::vector<Transform>& pose) {
  std::vector<glm::mat4> model(pose.size());
  localToModel(s, pose, model);
  std::vector<glm::vec3> out;
  for (const auto& m : model) out.emplace_back(m[3]);
  return out;
}

bool samePose(const std::vector<Transform>& a, const std::vector<Transform>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Transform)) == 0;
}

bool finitePose(const std::vector<Transform>& pose) {
  for (const auto& t : pose)
    if (!finite(t)) return false;
  return true;
}

struct Fixture {
  SyntheticLeg leg;
  LimbIk limb;
  std::vector<Transform> rest;
  explicit Fixture(SyntheticLeg l) : leg(std::move(l)) {
    limb = makeLimbIk(leg.skeleton, {leg.thigh, leg.shin, leg.foot});
    rest = leg.skeleton.restPose;
  }
  [[nodiscard]] std::vector<glm::vec3> at(const std::vector<Transform>& pose) const {
    return modelPositions(leg.skeleton, pose);
  }
};

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

}  // namespace

// ---- invalid input ---------------------------------------------------------------

TEST(TwoBoneIk, UnusableLimbsAreRejected) {
  const SyntheticLeg leg = makeSyntheticLeg();
  const Skeleton& s = leg.skeleton;
  EXPECT_EQ(makeLimbIk(s, {-1, leg.shin, leg.foot}).upper, -1);
  EXPECT_EQ(makeLimbIk(s, {leg.thigh, leg.shin, -1}).upper, -1);
  EXPECT_EQ(makeLimbIk(s, {leg.thigh, leg.shin, 99}).upper, -1);
  EXPECT_EQ(makeLimbIk(s, {leg.shin, leg.thigh, leg.foot}).upper, -1);  // lower not below upper
  EXPECT_EQ(makeLimbIk(s, {leg.thigh, leg.shin, leg.shin}).upper, -1);
  EXPECT_EQ(makeLimbIk(s, {leg.thigh, leg.shin, leg.hips}).upper, -1);  // an "end" above the limb
  EXPECT_EQ(makeLimbIk(Skeleton{}, {0, 1, 2}).upper, -1);

  SyntheticLeg flat = makeSyntheticLeg();
  flat.skeleton.restPose[static_cast<std::size_t>(flat.foot)].translation = glm::vec3(0.0f);  // zero-length shin
  EXPECT_EQ(makeLimbIk(flat.skeleton, {flat.thigh, flat.shin, flat.foot}).upper, -1);

  const LimbIk good = makeLimbIk(s, {leg.thigh, leg.shin, leg.foot});
  ASSERT_EQ(good.upper, leg.thigh);
  EXPECT_EQ(good.lower, leg.shin);
  EXPECT_EQ(good.end, leg.foot);
  EXPECT_TRUE(good.endIsDescendant);

  // Nothing is done, and +infinity says so: an unusable limb, a pose that is too short.
  std::vector<Transform> pose = s.restPose;
  EXPECT_EQ(solveTwoBoneIk(s, pose, LimbIk{}, glm::vec3(0, 0.5f, 0), glm::vec3(0, 0.5f, 1), 1.0f), kInf);
  EXPECT_EQ(solveTwoBoneIk(s, std::span<Transform>(pose.data(), 2), good, glm::vec3(0, 0.5f, 0), glm::vec3(0, 0.5f, 1), 1.0f),
            kInf);
  EXPECT_TRUE(samePose(pose, s.restPose));
}

TEST(TwoBoneIk, NonFiniteTargetLeavesThePoseUnchanged) {
  Fixture f(makeSyntheticLeg());
  for (const glm::vec3& target : {glm::vec3(kNaN, 0, 0), glm::vec3(0, kInf, 0), glm::vec3(0, 0, -kInf)}) {
    std::vector<Transform> pose = f.rest;
    EXPECT_EQ(solveTwoBoneIk(f.leg.skeleton, pose, f.limb, target, glm::vec3(0, 0.5f, 1), 1.0f), kInf);
    EXPECT_TRUE(samePose(pose, f.rest));
  }
  // A bad pole or weight is not a reason to fail: the pole falls back, the weight counts as 0.
  std::vector<Transform> pose = f.rest;
  const glm::vec3 target(0.1f, 0.3f, 0.2f);
  EXPECT_LT(solveTwoBoneIk(f.leg.skeleton, pose, f.limb, target, glm::vec3(kNaN), 1.0f), 1e-4f);
  EXPECT_TRUE(finitePose(pose));
  pose = f.rest;
  EXPECT_TRUE(std::isfinite(solveTwoBoneIk(f.leg.skeleton, pose, f.limb, target, glm::vec3(0, 0.5f, 1), kNaN)));
  EXPECT_TRUE(samePose(pose, f.rest));
}

// ---- reach, lengths, pole ----------------------------------------------------------

TEST(TwoBoneIk, ReachableTargetsAreReachedAndBonesKeepTheirLength) {
  Fixture f(makeSyntheticLeg());
  const auto rest = f.at(f.rest);
  const glm::vec3 hip = rest[static_cast<std::size_t>(f.leg.thigh)];
  const float l1 = glm::distance(rest[1], rest[2]), l2 = glm::distance(rest[2], rest[3]);
  const float full = l1 + l2;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  int solved = 0;
  for (int i = 0; i < 500; ++i) {
    glm::vec3 dir(unit(rng), unit(rng), unit(rng));
    if (glm::length(dir) < 0.1f) continue;
    dir = glm::normalize(dir);
    // Between the folded limit and (1 - softness) of the length: reached exactly.
    const float r = std::fabs(l1 - l2) + 0.01f + (0.94f * full - std::fabs(l1 - l2) - 0.01f) * (unit(rng) * 0.5f + 0.5f);
    const glm::vec3 target = hip + dir * r;
    const glm::vec3 pole = hip + glm::vec3(unit(rng), unit(rng), unit(rng));
    std::vector<Transform> pose = f.rest;
    const float left = solveTwoBoneIk(f.leg.skeleton, pose, f.limb, target, pole, 1.0f);
    const auto p = f.at(pose);
    EXPECT_LT(glm::distance(p[3], target), 1e-4f) << "target " << i;
    EXPECT_NEAR(left, glm::distance(p[3], target), 1e-6f);
    EXPECT_NEAR(glm::distance(p[1], p[2]), l1, 1e-5f);
    EXPECT_NEAR(glm::distance(p[2], p[3]), l2, 1e-5f);
    EXPECT_NEAR(glm::distance(p[3], p[4]), glm::distance(rest[3], rest[4]), 1e-5f);  // the foot moves rigidly
    EXPECT_EQ(std::memcmp(&pose[0], &f.rest[0], sizeof(Transform)), 0);  // only thigh and shin turn
    EXPECT_EQ(std::memcmp(&pose[3], &f.rest[3], sizeof(Transform)), 0);
    EXPECT_EQ(pose[1].translation, f.rest[1].translation);
    ++solved;
  }
  EXPECT_GT(solved, 400);
}

TEST(TwoBoneIk, TheKneeBendsTowardThePole) {
  Fixture f(makeSyntheticLeg());
  const auto rest = f.at(f.rest);
  const glm::vec3 hip = rest[1];
  const glm::vec3 target = hip + glm::vec3(0.0f, -0.6f, 0.1f);
  const glm::vec3 line = glm::normalize(target - hip);
  for (const glm::vec3& toward : {glm::vec3(0, 0, 1), glm::vec3(0, 0, -1), glm::vec3(1, 0, 0), glm::vec3(-1, 0, 0),
                                  glm::vec3(0.6f, 0.0f, -0.8f)}) {
    std::vector<Transform> pose = f.rest;
    const glm::vec3 pole = hip + glm::vec3(0, -0.3f, 0) + toward;
    EXPECT_LT(solveTwoBoneIk(f.leg.skeleton, pose, f.limb, target, pole, 1.0f), 1e-4f);
    const glm::vec3 knee = f.at(pose)[2];
    auto across = [&](const glm::vec3& v) { return v - line * glm::dot(v, line); };
    const glm::vec3 kneeSide = across(knee - hip), poleSide = across(pole - hip);
    ASSERT_GT(glm::length(kneeSide), 0.1f);  // really bent: 0.6 m of a 0.9 m leg
    // In the plane of the hip, the target and the pole, on the pole's side.
    EXPECT_GT(glm::dot(glm::normalize(kneeSide), glm::normalize(poleSide)), 0.9999f)
        << toward.x << " " << toward.y << " " << toward.z;
  }
}

// ---- beyond reach: the soft limit ------------------------------------------------------

TEST(TwoBoneIk, UnreachableTargetsGiveTheStraightestChainPointingAtThem) {
  Fixture f(makeSyntheticLeg());
  const auto rest = f.at(f.rest);
  const glm::vec3 hip = rest[1];
  const float full = glm::distance(rest[1], rest[2]) + glm::distance(rest[2], rest[3]);
  const glm::vec3 dir = glm::normalize(glm::vec3(0.3f, -1.0f, 0.4f));
  for (const float far : {1.2f, 2.0f, 1e3f, 1e6f, 1e30f}) {
    for (const float softness : {0.0f, 0.05f}) {
      std::vector<Transform> pose = f.rest;
      const glm::vec3 target = hip + dir * (far * full);
      const float left = solveTwoBoneIk(f.leg.skeleton, pose, f.limb, target, hip + glm::vec3(0, 0, 1), 1.0f, {softness});
      ASSERT_TRUE(finitePose(pose)) << far;
      EXPECT_FALSE(std::isnan(left));
      const auto p = f.at(pose);
      const glm::vec3 reached = p[3] - hip;
      EXPECT_GT(glm::dot(glm::normalize(reached), dir), 1.0f - 1e-6f) << far << " " << softness;  // points at it
      // Hard limit: straight. Soft: within softness * full, e^-(far - 1 + s)/s of the way.
      const float expected = softness == 0.0f ? full : full - softness * full * std::exp(-((far - 1.0f) * full + softness * full) / (softness * full));
      EXPECT_NEAR(glm::length(reached), expected, 1e-5f) << far << " " << softness;
    }
  }
}

TEST(TwoBoneIk, ReachIsMonotoneAndContinuousAcrossFullExtension) {
  for (const float softness : {0.0f, 0.05f, 0.2f}) {
    Fixture f(makeSyntheticLeg());
    const auto rest = f.at(f.rest);
    const glm::vec3 hip = rest[1];
    const float full = glm::distance(rest[1], rest[2]) + glm::distance(rest[2], rest[3]);
    const glm::vec3 dir = glm::normalize(glm::vec3(0.1f, -1.0f, 0.2f));
    const int steps = 3000;
    const float from = 0.5f * full, to = 1.5f * full, step = (to - from) / steps;
    float previous = -1.0f, worstJump = 0.0f;
    for (int i = 0; i <= steps; ++i) {
      const float d = from + step * static_cast<float>(i);
      std::vector<Transform> pose = f.rest;  // from the same pose each time: no history
      solveTwoBoneIk(f.leg.skeleton, pose, f.limb, hip + dir * d, hip + glm::vec3(0, 0, 1), 1.0f, {softness});
      const float reach = glm::distance(f.at(pose)[3], hip);
      if (d <= (1.0f - softness) * full - 1e-4f) {
        EXPECT_NEAR(reach, d, 1e-4f) << softness;
      }
      EXPECT_LE(reach, full + 1e-5f);
      if (previous >= 0.0f) {
        EXPECT_GE(reach, previous - 2e-6f) << "not monotone at " << d << ", softness " << softness;
        worstJump = std::max(worstJump, reach - previous);
      }
      previous = reach;
    }
    // C0: the reach never moves faster than the target (slope <= 1), so no jump.
    EXPECT_LE(worstJump, step + 2e-6f) << softness;
  }
}

// ---- weight --------------------------------------------------------------------------

TEST(TwoBoneIk, WeightZeroLeavesThePoseBitIdenticalAndWeightsBlend) {
  Fixture f(makeSyntheticLeg());
  const glm::vec3 hip = f.at(f.rest)[1];
  const glm::vec3 target = hip + glm::vec3(0.1f, -0.5f, 0.3f), pole = hip + glm::vec3(0, 0, 1);
  std::vector<Transform> pose = f.rest;
  const float before = glm::distance(f.at(f.rest)[3], target);
  EXPECT_FLOAT_EQ(solveTwoBoneIk(f.leg.skeleton, pose, f.limb, target, pole, 0.0f), before);
  EXPECT_TRUE(samePose(pose, f.rest));
  EXPECT_FLOAT_EQ(solveTwoBoneIk(f.leg.skeleton, pose, f.limb, target, pole, -3.0f), before);  // clamped to 0
  EXPECT_TRUE(samePose(pose, f.rest));

  float last = before;
  for (const float w : {0.25f, 0.5f, 0.75f, 1.0f}) {
    pose = f.rest;
    const float left = solveTwoBoneIk(f.leg.skeleton, pose, f.limb, target, pole, w);
    EXPECT_LT(left, last) << w;  // closer with more weight
    last = left;
    const auto p = f.at(pose);
    EXPECT_NEAR(glm::distance(p[1], p[2]), glm::distance(f.at(f.rest)[1], f.at(f.rest)[2]), 1e-5f);
  }
  EXPECT_LT(last, 1e-4f);
}

// ---- stiff cases ----------------------------------------------------------------------

TEST(TwoBoneIk, TargetAtTheHipFoldsTheLegWithoutNaN) {
  Fixture f(makeSyntheticLeg());
  const auto rest = f.at(f.rest);
  const float l1 = glm::distance(rest[1], rest[2]), l2 = glm::distance(rest[2], rest[3]);
  std::vector<Transform> pose = f.rest;
  const float left = solveTwoBoneIk(f.leg.skeleton, pose, f.limb, rest[1], rest[1] + glm::vec3(0, 0, 1), 1.0f);
  ASSERT_TRUE(finitePose(pose));
  const auto p = f.at(pose);
  // As folded as it goes: the ends of the two bones apart by their difference (or 1e-3 of the length).
  EXPECT_NEAR(left, std::max(std::fabs(l1 - l2), 1e-3f * (l1 + l2)), 1e-4f);
  EXPECT_NEAR(glm::distance(p[1], p[2]), l1, 1e-5f);
  EXPECT_NEAR(glm::distance(p[2], p[3]), l2, 1e-5f);
  EXPECT_GT(p[2].z, rest[1].z);  // folded toward the pole (forward)
}

TEST(TwoBoneIk, StraightChainWithADegeneratePole) {
  Fixture f(makeSyntheticLeg(0.0f));  // rest pose fully straight
  const auto rest = f.at(f.rest);
  const glm::vec3 hip = rest[1];
  for (const glm::vec3& target : {hip + glm::vec3(0, -0.6f, 0), hip + glm::vec3(0.2f, -0.5f, 0.1f)}) {
    for (const glm::vec3& pole : {hip, hip + glm::vec3(0, -5.0f, 0), glm::vec3(kNaN)}) {  // on the line, or none
      std::vector<Transform> pose = f.rest;
      EXPECT_LT(solveTwoBoneIk(f.leg.skeleton, pose, f.limb, target, pole, 1.0f), 1e-4f);
      ASSERT_TRUE(finitePose(pose));
      const auto p = f.at(pose);
      EXPECT_NEAR(glm::distance(p[1], p[2]), 0.45f, 1e-5f);
      EXPECT_NEAR(glm::distance(p[2], p[3]), 0.45f, 1e-5f);
    }
  }
  // A bent chain and a pole on the line: the bend stays on the side it was (forward).
  Fixture bent(makeSyntheticLeg(0.05f));
  std::vector<Transform> pose = bent.rest;
  const glm::vec3 target = hip + glm::vec3(0, -0.6f, 0);
  EXPECT_LT(solveTwoBoneIk(bent.leg.skeleton, pose, bent.limb, target, hip + glm::vec3(0, -3, 0), 1.0f), 1e-4f);
  EXPECT_GT(bent.at(pose)[2].z, 0.05f);
}

TEST(TwoBoneIk, ZeroLengthBoneInThePoseLeavesItUnchanged) {
  Fixture f(makeSyntheticLeg());
  std::vector<Transform> pose = f.rest;
  pose[static_cast<std::size_t>(f.leg.shin)].scale = glm::vec3(0.0f);  // the shin shrunk to a point
  const std::vector<Transform> before = pose;
  const float left = solveTwoBoneIk(f.leg.skeleton, pose, f.limb, glm::vec3(0.1f, 0.5f, 0.2f), glm::vec3(0, 0.5f, 1), 1.0f);
  EXPECT_TRUE(std::isfinite(left));
  EXPECT_TRUE(samePose(pose, before));
}

TEST(TwoBoneIk, ScaledRotatedAndMirroredRootSpaces) {
  // A centimetre file read as metres (root-space scale 0.01 of the numbers * 100),
  // Z-up turned to Y-up, and a mirroring (negative scale) root: lengths in model space.
  const glm::mat4 zUpToYUp = glm::rotate(glm::mat4(1.0f), -1.5707964f, glm::vec3(1, 0, 0));
  for (const glm::mat4& root : {glm::mat4(1.0f), glm::scale(zUpToYUp, glm::vec3(0.01f)),
                                glm::scale(glm::mat4(1.0f), glm::vec3(-1.0f, 1.0f, 1.0f)),
                                glm::scale(glm::mat4(1.0f), glm::vec3(100.0f))}) {
    SyntheticLeg leg = makeSyntheticLeg();
    const float unit = std::cbrt(std::fabs(glm::determinant(glm::mat3(root))));
    for (auto& t : leg.skeleton.restPose) t.translation /= unit;  // same size in model space
    leg.skeleton.rootTransform = root;
    Fixture f(leg);
    ASSERT_GE(f.limb.upper, 0);
    const auto rest = f.at(f.rest);
    const glm::vec3 hip = rest[1];
    const float l1 = glm::distance(rest[1], rest[2]);
    EXPECT_NEAR(l1, std::sqrt(0.45f * 0.45f + 0.05f * 0.05f), 1e-4f);
    for (const glm::vec3& offset : {glm::vec3(0.1f, -0.6f, 0.2f), glm::vec3(-0.3f, 0.2f, 0.4f), glm::vec3(0, -0.3f, -0.6f)}) {
      std::vector<Transform> pose = f.rest;
      const glm::vec3 pole = hip + glm::vec3(0, 0, 1);
      EXPECT_LT(solveTwoBoneIk(f.leg.skeleton, pose, f.limb, hip + offset, pole, 1.0f), 1e-4f) << root[0][0];
      const auto p = f.at(pose);
      EXPECT_NEAR(glm::distance(p[1], p[2]), l1, 1e-5f);
      const glm::vec3 line = glm::normalize(offset);
      const glm::vec3 kneeSide = (p[2] - hip) - line * glm::dot(p[2] - hip, line);
      const glm::vec3 poleSide = (pole - hip) - line * glm::dot(pole - hip, line);
      EXPECT_GT(glm::dot(kneeSide, poleSide), 0.0f) << root[0][0];
    }
  }
}

TEST(TwoBoneIk, EndJointElsewhereUsesItsRestOffset) {
  // RobotExpressive's shape: the foot is an IK target under the root, beside the leg.
  SyntheticLeg leg = makeSyntheticLeg();
  Skeleton& s = leg.skeleton;
  Transform footRest;
  footRest.translation = glm::vec3(0.1f, -0.9f, 0.0f);  // where the ankle is, from the hips
  const int target = s.addJoint("Foot.L", leg.hips, footRest);
  const LimbIk limb = makeLimbIk(s, {leg.thigh, leg.shin, target});
  ASSERT_EQ(limb.upper, leg.thigh);
  EXPECT_FALSE(limb.endIsDescendant);
  EXPECT_NEAR(limb.endOffsetInLower.y, -0.45f, 1e-6f);  // the foot's rest offset from the shin
  EXPECT_NEAR(limb.endOffsetInLower.z, -0.05f, 1e-6f);

  std::vector<Transform> pose = s.restPose;
  const glm::vec3 hip = modelPositions(s, pose)[1];
  const glm::vec3 goal = hip + glm::vec3(0.05f, -0.7f, 0.25f);
  EXPECT_LT(solveTwoBoneIk(s, pose, limb, goal, hip + glm::vec3(0, 0, 1), 1.0f), 1e-4f);
  EXPECT_LT(glm::distance(limbEndModel(s, pose, limb), goal), 1e-4f);
  EXPECT_EQ(std::memcmp(&pose[static_cast<std::size_t>(target)], &s.restPose[static_cast<std::size_t>(target)],
                        sizeof(Transform)),
            0);  // the detached joint itself is the caller's to place
}
