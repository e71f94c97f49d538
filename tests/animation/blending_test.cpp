#include <gtest/gtest.h>

#include <string>

#include "marionette/animation/blending.hpp"
#include "marionette/animation/pose.hpp"
#include "synthetic.hpp"

using namespace marionette;
using namespace marionette::test;

namespace {
std::vector<Transform> poseWith(glm::quat q, glm::vec3 t = {0, 0, 0}, int n = 1) {
  std::vector<Transform> p(n);
  for (auto& x : p) {
    x.rotation = q;
    x.translation = t;
  }
  return p;
}
}  // namespace

TEST(Blending, NegativeAndNaNWeightsCountAsZero) {
  auto rest = poseWith(glm::quat(1, 0, 0, 0));
  auto a = poseWith(glm::angleAxis(1.0f, glm::vec3(0, 1, 0)));
  std::vector<Transform> out(1);
  BlendLayer layers[] = {{a, -2.0f}, {a, NAN}};
  blendPoses(layers, rest, out);
  EXPECT_TRUE(finite(out[0]));
  EXPECT_NEAR(angleBetween(out[0].rotation, rest[0].rotation), 0.0f, 1e-6f);
}

TEST(Blending, ZeroTotalWeightGivesRestPose) {
  std::vector<Transform> rest = poseWith(glm::angleAxis(0.3f, glm::vec3(1, 0, 0)), {1, 2, 3});
  auto a = poseWith(glm::angleAxis(1.0f, glm::vec3(0, 1, 0)), {5, 5, 5});
  std::vector<Transform> out(1);
  BlendLayer layers[] = {{a, 0.0f}};
  blendPoses(layers, rest, out);
  EXPECT_EQ(out[0].translation, rest[0].translation);
  EXPECT_NEAR(angleBetween(out[0].rotation, rest[0].rotation), 0.0f, 1e-6f);
  blendPoses({}, rest, out);
  EXPECT_EQ(out[0].translation, rest[0].translation);
}

TEST(Blending, QAndMinusQBlendToTheSameRotation) {
  auto rest = poseWith(glm::quat(1, 0, 0, 0));
  glm::quat q = glm::angleAxis(2.5f, glm::normalize(glm::vec3(1, 1, 0)));
  auto a = poseWith(q), b = poseWith(-q);
  std::vector<Transform> out(1);
  BlendLayer layers[] = {{a, 0.5f}, {b, 0.5f}};
  blendPoses(layers, rest, out);
  EXPECT_TRUE(finite(out[0]));
  EXPECT_NEAR(angleBetween(out[0].rotation, q), 0.0f, 1e-3f);
}

TEST(Blending, NearlyEqualRotationsStayUnit) {
  auto rest = poseWith(glm::quat(1, 0, 0, 0));
  glm::quat q = glm::angleAxis(1.0f, glm::vec3(0, 0, 1));
  glm::quat r = glm::angleAxis(1.0f + 1e-7f, glm::vec3(0, 0, 1));
  auto a = poseWith(q), b = poseWith(r);
  std::vector<Transform> out(1);
  BlendLayer layers[] = {{a, 0.3f}, {b, 0.7f}};
  blendPoses(layers, rest, out);
  EXPECT_NEAR(glm::length(glm::vec4(out[0].rotation.x, out[0].rotation.y, out[0].rotation.z, out[0].rotation.w)), 1.0f, 1e-6f);
  EXPECT_NEAR(angleBetween(out[0].rotation, q), 0.0f, 1e-3f);
  EXPECT_NEAR(angleBetween(slerpShortest(q, r, 0.5f), q), 0.0f, 1e-3f);
  EXPECT_TRUE(std::isfinite(slerpShortest(q, q, 0.5f).w));
}

TEST(Blending, OppositeRotationsThatCancelFallBackToRest) {
  // 0.5 * q + 0.5 * (a rotation whose quaternion is orthogonal) is fine; the
  // degenerate case is exact cancellation after sign alignment, which can only
  // happen with zero-length input; a zero quaternion input must not give NaN.
  auto rest = poseWith(glm::quat(1, 0, 0, 0));
  auto zero = poseWith(glm::quat(0, 0, 0, 0));
  std::vector<Transform> out(1);
  BlendLayer layers[] = {{zero, 1.0f}};
  blendPoses(layers, rest, out);
  EXPECT_TRUE(finite(out[0]));
}

TEST(Blending, WeightsAreRelativeAboveOneAndRestFillsBelow) {
  auto rest = poseWith(glm::quat(1, 0, 0, 0), {0, 0, 0});
  auto a = poseWith(glm::quat(1, 0, 0, 0), {1, 0, 0});
  auto b = poseWith(glm::quat(1, 0, 0, 0), {3, 0, 0});
  std::vector<Transform> out(1);
  BlendLayer both[] = {{a, 2.0f}, {b, 2.0f}};
  blendPoses(both, rest, out);
  EXPECT_NEAR(out[0].translation.x, 2.0f, 1e-6f);
  BlendLayer half[] = {{a, 0.5f}};
  blendPoses(half, rest, out);
  EXPECT_NEAR(out[0].translation.x, 0.5f, 1e-6f);
}

TEST(Blending, MaskLimitsALayerToSomeJoints) {
  auto rest = poseWith(glm::quat(1, 0, 0, 0), {0, 0, 0}, 3);
  auto a = poseWith(glm::quat(1, 0, 0, 0), {1, 0, 0}, 3);
  auto b = poseWith(glm::quat(1, 0, 0, 0), {5, 0, 0}, 3);
  std::vector<float> upper = {0.0f, 1.0f, 1.0f};
  std::vector<Transform> out(3);
  BlendLayer layers[] = {{a, 1.0f}, {b, 1.0f, upper}};
  blendPoses(layers, rest, out);
  EXPECT_NEAR(out[0].translation.x, 1.0f, 1e-6f);
  EXPECT_NEAR(out[1].translation.x, 3.0f, 1e-6f);
  // A short mask counts missing joints as 0.
  std::vector<float> shortMask = {1.0f};
  BlendLayer masked[] = {{b, 1.0f, shortMask}};
  blendPoses(masked, rest, out);
  EXPECT_NEAR(out[0].translation.x, 5.0f, 1e-6f);
  EXPECT_NEAR(out[2].translation.x, 0.0f, 1e-6f);
}

TEST(Blending, AdditiveRoundTrip) {
  auto ref = poseWith(glm::angleAxis(0.2f, glm::vec3(0, 1, 0)), {1, 0, 0});
  auto pose = poseWith(glm::angleAxis(0.9f, glm::vec3(0, 1, 0)), {1, 2, 0});
  pose[0].scale = {2, 2, 2};
  std::vector<Transform> delta(1), out(1);
  makeAdditiveDelta(pose, ref, delta);
  BlendLayer layers[] = {{ref, 1.0f}, {delta, 1.0f, {}, true}};
  blendPoses(layers, ref, out);
  EXPECT_NEAR(angleBetween(out[0].rotation, pose[0].rotation), 0.0f, 1e-4f);
  EXPECT_NEAR(glm::length(out[0].translation - pose[0].translation), 0.0f, 1e-5f);
  EXPECT_NEAR(out[0].scale.x, 2.0f, 1e-5f);
  // Half weight: half the rotation delta.
  BlendLayer halfLayers[] = {{ref, 1.0f}, {delta, 0.5f, {}, true}};
  blendPoses(halfLayers, ref, out);
  EXPECT_NEAR(angleBetween(out[0].rotation, glm::angleAxis(0.55f, glm::vec3(0, 1, 0))), 0.0f, 1e-4f);
}

TEST(Blending, AccumulatorMatchesBlendPoses) {
  // The runtime's layer-at-a-time blend gives exactly what blendPoses gives.
  std::vector<Transform> rest(3), a(3), b(3), d(3), out1(3), out2(3);
  for (int j = 0; j < 3; ++j) {
    const float f = static_cast<float>(j + 1);
    rest[j].rotation = glm::angleAxis(0.1f * f, glm::vec3(0, 1, 0));
    a[j] = {{f, 0, 0}, glm::angleAxis(0.5f * f, glm::vec3(1, 0, 0)), {1, 1, 1}};
    b[j] = {{0, f, 0}, -glm::angleAxis(-0.7f * f, glm::vec3(0, 0, 1)), {2, 1, 1}};
    d[j] = {{0, 0, 0.1f}, glm::angleAxis(0.2f, glm::vec3(0, 1, 0)), {1, 1, 1}};
  }
  std::vector<float> mask = {1.0f, 0.5f, 0.0f};
  BlendLayer layers[] = {{a, 0.4f}, {b, 0.3f, mask}, {d, 0.8f, {}, true}};
  blendPoses(layers, rest, out1);
  // Exactly on the builds that keep the baseline's bits; within the FMA build's bound on it (pose.hpp).
  for (const SimdPath path : {SimdPath::Portable, SimdPath::Auto}) {
    setSimdPath(path);
    const bool exact = std::string(activeSimdPath()) != "avx2+fma";
    BlendAccumulator acc;
    acc.reset(3);
    acc.addNormal(a, 0.4f, {}, rest);
    acc.addNormal(b, 0.3f, mask, rest);
    acc.finish(rest, out2);
    applyAdditive(d, 0.8f, {}, out2);
    for (int j = 0; j < 3; ++j) {
      const float* x = &out1[j].translation.x;
      const float* y = &out2[j].translation.x;
      for (int i = 0; i < 10; ++i) {
        if (exact)
          EXPECT_EQ(x[i], y[i]) << "joint " << j << " float " << i << ", " << activeSimdPath();
        else
          EXPECT_NEAR(x[i], y[i], 1e-6f * std::max(1.0f, std::abs(x[i]))) << "joint " << j << " float " << i;
      }
    }
  }
  setSimdPath(SimdPath::Auto);
}
