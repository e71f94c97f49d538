// The span contract of animation/ (pose.hpp): with spans of different lengths, each
// per-frame function writes the joints all of its required spans have, leaves the rest of
// its output exactly as it was, and reads nothing past a span (ASan checks that part in the
// sanitizer build). A sentinel value marks "untouched".
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "marionette/animation/blending.hpp"
#include "marionette/animation/pose.hpp"
#include "marionette/animation/sampling.hpp"
#include "synthetic.hpp"

using namespace marionette;
using namespace marionette::test;

namespace {

const glm::mat4 kSentinelMatrix(7.0f);
const Transform kSentinel{{7.0f, 7.0f, 7.0f}, glm::quat(0.5f, 0.5f, 0.5f, 0.5f), {7.0f, 7.0f, 7.0f}};

bool same(const Transform& a, const Transform& b) {
  return a.translation == b.translation && a.rotation == b.rotation && a.scale == b.scale;
}

Clip turnEveryJoint(int joints) {
  Clip c;
  c.name = "turn";
  c.duration = 1.0f;
  for (int j = 0; j < joints; ++j) c.tracks.push_back(rotationTrack(j, {0.0f, 1.0f}, {0.0f, 1.0f}, {0, 0, 1}));
  return c;
}

}  // namespace

TEST(SpanContract, LocalToModelWritesTheJointsEverySpanHas) {
  const Skeleton s = makeChain(6);
  // A shorter local pose: 4 joints computed, the model's last 2 untouched.
  std::vector<glm::mat4> model(6, kSentinelMatrix);
  localToModel(s, std::span<const Transform>(s.restPose).first(4), model);
  EXPECT_NEAR(model[3][3].y, 3.0f, 1e-6f);
  EXPECT_EQ(model[4], kSentinelMatrix);
  EXPECT_EQ(model[5], kSentinelMatrix);
  // A shorter output: nothing written past it (the span ends there; the vector's tail stays).
  std::vector<glm::mat4> longer(8, kSentinelMatrix);
  localToModel(s, s.restPose, std::span<glm::mat4>(longer).first(3));
  EXPECT_NEAR(longer[2][3].y, 2.0f, 1e-6f);
  for (std::size_t i = 3; i < longer.size(); ++i) EXPECT_EQ(longer[i], kSentinelMatrix) << i;
  // A longer local pose than the skeleton: the skeleton's joints only.
  std::vector<Transform> local = s.restPose;
  local.resize(9, Transform{});
  std::vector<glm::mat4> model9(9, kSentinelMatrix);
  localToModel(s, local, model9);
  EXPECT_NEAR(model9[5][3].y, 5.0f, 1e-6f);
  for (std::size_t i = 6; i < 9; ++i) EXPECT_EQ(model9[i], kSentinelMatrix) << i;
  // modelMatrixOf a joint past the pose: identity-free answer, no read past the span.
  const glm::mat4 past = modelMatrixOf(s, std::span<const Transform>(s.restPose).first(2), 4);
  EXPECT_TRUE(std::isfinite(past[3].y));
}

TEST(SpanContract, SkinningPaletteStopsAtTheShortestSpan) {
  const Skeleton s = makeChain(5);
  std::vector<glm::mat4> model(5);
  localToModel(s, s.restPose, model);
  std::vector<glm::mat4> palette(5, kSentinelMatrix);
  skinningPalette(model, std::span<const glm::mat4>(s.inverseBind).first(2), palette);
  EXPECT_NEAR(palette[1][3].y, 0.0f, 1e-5f);  // rest pose: identity
  EXPECT_EQ(palette[2], kSentinelMatrix);
  EXPECT_EQ(palette[4], kSentinelMatrix);
}

TEST(SpanContract, SamplingWritesTheJointsRestAndOutputShare) {
  const Skeleton s = makeChain(5);
  const Clip clip = turnEveryJoint(5);  // tracks for joints the short output lacks
  std::vector<Transform> out(5, kSentinel);
  sampleClip(clip, 0.5f, std::span<const Transform>(s.restPose).first(3), out);
  EXPECT_FALSE(same(out[2], kSentinel));
  EXPECT_NEAR(glm::angle(out[2].rotation), 0.5f, 1e-4f);
  EXPECT_TRUE(same(out[3], kSentinel));
  EXPECT_TRUE(same(out[4], kSentinel));
  std::vector<Transform> tracksOnly(5, kSentinel);
  sampleClipTracks(clip, 0.5f, std::span<Transform>(tracksOnly).first(2));
  EXPECT_FALSE(same(tracksOnly[1], kSentinel));
  EXPECT_TRUE(same(tracksOnly[2], kSentinel));
  // Morph weights: targets past the span are skipped.
  Clip faces;
  MorphTrack m;
  m.targets = {0, 3};
  m.times = {0.0f};
  m.weights = {0.25f, 0.75f};
  faces.morphTracks.push_back(m);
  std::vector<float> weights(4, 7.0f);
  sampleMorphWeights(faces, 0.0f, std::span<float>(weights).first(2));
  EXPECT_EQ(weights[0], 0.25f);
  EXPECT_EQ(weights[3], 7.0f);
}

TEST(SpanContract, BlendingWritesTheSharedJointsAndShortInputsAddNothing) {
  const Skeleton s = makeChain(4);
  std::vector<Transform> turned = s.restPose;
  for (Transform& t : turned) t.rotation = glm::angleAxis(1.0f, glm::vec3(0, 0, 1));
  // A layer shorter than the output drives only its joints; the others get the rest pose.
  const BlendLayer layer{std::span<const Transform>(turned).first(2), 1.0f};
  std::vector<Transform> out(4, kSentinel);
  blendPoses(std::span<const BlendLayer>(&layer, 1), s.restPose, out);
  EXPECT_NEAR(glm::angle(out[1].rotation), 1.0f, 1e-5f);
  EXPECT_TRUE(same(out[2], s.restPose[2]));
  // An output longer than the rest pose: untouched past it.
  std::vector<Transform> longer(6, kSentinel);
  blendPoses(std::span<const BlendLayer>(&layer, 1), s.restPose, longer);
  EXPECT_TRUE(same(longer[4], kSentinel));
  // blendOver with a short mask: weight 0 where the mask has no value.
  std::vector<Transform> pose = s.restPose;
  const std::vector<float> mask{1.0f};
  blendOver(pose, turned, 1.0f, mask);
  EXPECT_NEAR(glm::angle(pose[0].rotation), 1.0f, 1e-5f);
  EXPECT_TRUE(same(pose[1], s.restPose[1]));
  // blendOver with a short layer: the pose past it is untouched.
  std::vector<Transform> pose2(4, kSentinel);
  blendOver(pose2, std::span<const Transform>(turned).first(1), 1.0f, {});
  EXPECT_FALSE(same(pose2[0], kSentinel));
  EXPECT_TRUE(same(pose2[1], kSentinel));
  // Additive delta and its application: the shortest span decides.
  std::vector<Transform> delta(4, kSentinel);
  makeAdditiveDelta(turned, std::span<const Transform>(s.restPose).first(3), delta);
  EXPECT_FALSE(same(delta[2], kSentinel));
  EXPECT_TRUE(same(delta[3], kSentinel));
  std::vector<Transform> base = s.restPose;
  applyAdditive(std::span<const Transform>(delta).first(1), 1.0f, {}, base);
  EXPECT_NEAR(glm::angle(base[0].rotation), 1.0f, 1e-5f);
  EXPECT_TRUE(same(base[1], s.restPose[1]));
}
