#include <gtest/gtest.h>

#include "marionette/animation/clip_optimizer.hpp"
#include "marionette/animation/sampling.hpp"
#include "synthetic.hpp"

using namespace marionette;
using namespace marionette::test;

TEST(ClipOptimizer, IgnoresTracksOutsideTheSkeletonAndEmptyClips) {
  Skeleton s = makeChain(2);
  Clip empty;
  ClipOptimizeStats st = optimizeClip(empty, s);
  EXPECT_EQ(st.keysBefore, 0u);
  Clip c;
  c.tracks.push_back(rotationTrack(7, {0, 1}, {0, 0}));
  optimizeClip(c, s);
  EXPECT_EQ(c.tracks.size(), 1u);  // left alone, not read out of bounds
}

TEST(ClipOptimizer, RemovesRestTracksKeepsMovingOnesAndMakesHeldOnesOneKey) {
  Skeleton s = makeChain(3);
  Clip c;
  c.name = "c";
  JointTrack atRest;  // translation equal to rest within 1 µm, rotation identity
  atRest.joint = 1;
  atRest.translation.times = {0, 1, 2};
  atRest.translation.values = {{0, 1, 0}, {0, 1.000001f, 0}, {0, 1, 0}};
  atRest.rotation.times = {0, 2};
  atRest.rotation.values = {glm::quat(1, 0, 0, 0), glm::quat(1, 0, 0, 0)};
  c.tracks.push_back(atRest);
  JointTrack held = rotationTrack(2, {0, 1, 2}, {0.5f, 0.5f, 0.5f});
  c.tracks.push_back(held);
  c.tracks.push_back(rotationTrack(0, {0, 1, 2}, {0.0f, 0.3f, 0.0f}));
  std::sort(c.tracks.begin(), c.tracks.end(), [](auto& a, auto& b) { return a.joint < b.joint; });
  c.updateDuration();
  Clip original = c;
  ClipOptimizeStats st = optimizeClip(c, s);
  EXPECT_EQ(st.tracksRemoved, 2);
  EXPECT_EQ(st.tracksMadeConstant, 1);
  EXPECT_EQ(c.tracks.size(), 2u);  // joint 1 had only rest tracks: gone
  EXPECT_EQ(c.duration, original.duration);  // duration kept
  EXPECT_NEAR(st.maxTranslationError, 1e-6f, 2e-7f);
  EXPECT_EQ(c.validate(3), "");
  // Same poses before and after, within the reported error.
  std::vector<Transform> a(3), b(3);
  for (float t = 0.0f; t <= 2.0f; t += 0.05f) {
    sampleClip(original, t, s.restPose, a);
    sampleClip(c, t, s.restPose, b);
    for (int j = 0; j < 3; ++j) {
      EXPECT_LE(glm::length(a[j].translation - b[j].translation), 2e-6f);
      EXPECT_LE(rotationAngle(a[j].rotation, b[j].rotation), 1e-5f);
    }
  }
}

TEST(ClipOptimizer, KeepsCubicTracksWithTangents) {
  Skeleton s = makeChain(1);
  Clip c;
  JointTrack jt;
  jt.joint = 0;
  jt.translation.interpolation = Interpolation::CubicSpline;
  jt.translation.times = {0, 1};
  // Equal key values but a nonzero tangent: the curve moves between keys.
  jt.translation.values = {glm::vec3(0), glm::vec3(0), glm::vec3(1, 0, 0), glm::vec3(0), glm::vec3(0), glm::vec3(0)};
  c.tracks.push_back(jt);
  ClipOptimizeStats st = optimizeClip(c, s);
  EXPECT_EQ(st.tracksRemoved + st.tracksMadeConstant, 0);
  EXPECT_EQ(c.tracks[0].translation.keyCount(), 2u);
}

TEST(ClipOptimizer, RotationAngleIsAccurateForTinyAndAntipodal) {
  const glm::quat q = glm::angleAxis(0.7f, glm::normalize(glm::vec3(1, 2, 3)));
  const glm::quat r = q * glm::angleAxis(1e-6f, glm::vec3(0, 1, 0));
  EXPECT_NEAR(rotationAngle(q, r), 1e-6f, 2e-7f);  // acos(dot) would give 0 or 3e-4 here
  EXPECT_NEAR(rotationAngle(q, -q), 0.0f, 1e-6f);
  EXPECT_NEAR(rotationAngle(glm::quat(1, 0, 0, 0), glm::angleAxis(3.14159265f, glm::vec3(0, 0, 1))), 3.14159265f, 1e-5f);
}
