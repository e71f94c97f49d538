// Compact clips' key reduction on a synthetic clip whose motion is piecewise linear (so
// interpolation recovers the keys between the corners exactly): the keys between the
// corners go, the track keeps the rest sparse with their frame numbers, the error stays
// within the budget everywhere (between keys too), and the four-wide decoder gives the
// bits of the track-by-track one. Sampling a sparse track outside its keys holds its ends.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "marionette/animation/animation_clip.hpp"
#include "marionette/animation/clip_error.hpp"
#include "marionette/animation/compact_clip.hpp"
#include "marionette/animation/pose.hpp"
#include "marionette/animation/sampling.hpp"

using namespace marionette;

namespace {

// A chain of `joints` joints 10 cm apart, keyed at 60 Hz for 2 s. Each joint slides
// through corners at 0, 0.5, 1.2 and 2 s (linear in between), and holds one rotation,
// then another, with one-frame ramps (frames 40 to 42 and 80 to 82) made by the
// sampler's own nlerp: interpolation recovers every key but the corners and ramp ends.
struct ChainClip {
  Skeleton skeleton;
  Clip clip;
};

ChainClip piecewiseLinearChain(int joints) {
  ChainClip c;
  for (int j = 0; j < joints; ++j) {
    Transform rest;
    rest.translation = {0.0f, j == 0 ? 0.0f : 0.1f, 0.0f};
    c.skeleton.addJoint("j" + std::to_string(j), j - 1, rest, glm::inverse(rest.matrix()), true);
  }
  const float corners[4][2] = {{0.0f, 0.0f}, {0.5f, 0.02f}, {1.2f, -0.03f}, {2.0f, 0.01f}};  // time, x offset
  for (int j = 0; j < joints; ++j) {
    JointTrack t;
    t.joint = j;
    const glm::vec3 axis = glm::normalize(glm::vec3(0.2f * static_cast<float>(j), 1.0f, 0.5f));
    const glm::quat held[3] = {glm::angleAxis(0.3f, axis), glm::angleAxis(-0.5f, axis), glm::angleAxis(0.9f, axis)};
    for (int k = 0; k <= 120; ++k) {
      const float time = static_cast<float>(k) / 60.0f;
      int s = 0;
      while (s < 2 && time > corners[s + 1][0]) ++s;
      const float u = (time - corners[s][0]) / (corners[s + 1][0] - corners[s][0]);
      t.translation.times.push_back(time);
      t.translation.values.push_back(glm::vec3(corners[s][1] + (corners[s + 1][1] - corners[s][1]) * u, j == 0 ? 0.0f : 0.1f, 0.0f));
      const int h = k <= 40 ? 0 : k <= 80 ? 1 : 2;
      const bool ramp = k == 41 || k == 81;
      t.rotation.times.push_back(time);
      t.rotation.values.push_back(ramp ? nlerpShortest(held[h - 1], held[h], 0.5f) : held[h]);
    }
    c.clip.tracks.push_back(t);
  }
  c.clip.duration = 2.0f;
  return c;
}

float worstError(const ChainClip& c, const CompactClip& compact) {
  const std::size_t n = c.skeleton.jointCount();
  std::vector<Transform> pa(n), pb(n);
  std::vector<glm::mat4> ma(n), mb(n);
  std::vector<float> perJoint(n);
  float worst = 0.0f;
  for (int k = 0; k <= 480; ++k) {  // every 1/240 s: between the keys too
    const float t = static_cast<float>(k) / 240.0f;
    sampleClip(c.clip, t, c.skeleton.restPose, pa);
    sampleCompactClip(compact, t, c.skeleton.restPose, pb);
    localToModel(c.skeleton, pa, ma);
    localToModel(c.skeleton, pb, mb);
    worst = std::max(worst, virtualVertexError(ma, mb, 0.03f, perJoint));
  }
  return worst;
}

}  // namespace

TEST(CompactClip, KeyReductionKeepsTheCornersSparseWithinTheBudget) {
  const ChainClip c = piecewiseLinearChain(9);  // two groups of four rotations and one more
  CompactClipStats reduced, full;
  const CompactClip withReduction = compactClip(c.clip, c.skeleton, {}, &reduced);
  CompactClipOptions off;
  off.keyReductionShare = 0.0f;
  const CompactClip without = compactClip(c.clip, c.skeleton, off, &full);
  ASSERT_TRUE(reduced.compacted) << reduced.reason;
  ASSERT_TRUE(full.compacted) << full.reason;
  EXPECT_EQ(reduced.tracksSparse, 18);  // every translation and rotation
  // Translations keep their 4 corners. Rotations keep the clip's ends, the ramps' ends and
  // the ramps' middle keys: over the two frames nlerp would pass the middle key at its time
  // but not at the pace the two one-frame halves go (the midpoint check).
  EXPECT_EQ(reduced.keysDropped, 9 * (121 - 4) + 9 * (121 - 8));
  EXPECT_FALSE(reduced.keyReductionUndone);
  EXPECT_EQ(full.tracksSparse, 0);
  EXPECT_EQ(full.keysDropped, 0);
  EXPECT_LT(withReduction.bytes() * 2, without.bytes());
  EXPECT_LE(worstError(c, withReduction), 1e-4f);
  EXPECT_LE(worstError(c, without), 1e-4f);
  // The four-wide decoder reads the sparse tracks' frame numbers as the scalar one does.
  std::vector<Transform> wide(9), scalar(9);
  for (const float t : {-1.0f, 0.0f, 0.01f, 0.5f, 0.51f, 1.19f, 1.2f, 1.999f, 2.0f, 3.0f, NAN}) {
    sampleCompactClipTracks(withReduction, t, wide);
    sampleCompactClipTracksScalar(withReduction, t, scalar);
    EXPECT_EQ(std::memcmp(wide.data(), scalar.data(), wide.size() * sizeof(Transform)), 0) << t;
    for (const Transform& x : wide) EXPECT_TRUE(std::isfinite(x.rotation.w)) << t;
  }
}

TEST(CompactClip, SparseTracksHoldTheirEndsOutsideTheClip) {
  const ChainClip c = piecewiseLinearChain(2);
  const CompactClip compact = compactClip(c.clip, c.skeleton);
  ASSERT_FALSE(compact.empty());
  std::vector<Transform> before(2), first(2), after(2), last(2);
  sampleCompactClip(compact, -5.0f, c.skeleton.restPose, before);
  sampleCompactClip(compact, 0.0f, c.skeleton.restPose, first);
  sampleCompactClip(compact, 50.0f, c.skeleton.restPose, after);
  sampleCompactClip(compact, 2.0f, c.skeleton.restPose, last);
  EXPECT_EQ(std::memcmp(before.data(), first.data(), sizeof(Transform) * 2), 0);
  for (int j = 0; j < 2; ++j) {  // the last key's time is start + 120 / rate, to a float's rounding
    EXPECT_NEAR(after[j].translation.x, last[j].translation.x, 1e-6f);
    EXPECT_NEAR(glm::dot(after[j].rotation, last[j].rotation), 1.0f, 1e-6f);
  }
}

// Hints (a SamplingCursor's keys) only speed the search: sampled forward frame by frame,
// jumping back, and with hints left by another clip, the bits are those without hints
// and those of the track-by-track definition. 9, 7 and 6 joints: the sparse tracks come
// in full groups of four, then alone, or in a group padded from three or two lanes.
TEST(CompactClip, HintsDoNotChangeTheResult) {
  for (const int joints : {9, 7, 6}) {
    const ChainClip c = piecewiseLinearChain(joints);
    const CompactClip compact = compactClip(c.clip, c.skeleton);
    ASSERT_FALSE(compact.empty());
    const auto n = static_cast<std::size_t>(joints);
    std::vector<std::uint32_t> hints(compact.tracks.size(), 0xFFFFFFFFu);  // garbage first
    std::vector<Transform> hinted(n), plain(n), scalar(n);
    const auto same = [&](float t) {
      sampleCompactClip(compact, t, c.skeleton.restPose, hinted, hints.data());
      sampleCompactClip(compact, t, c.skeleton.restPose, plain);
      std::copy(c.skeleton.restPose.begin(), c.skeleton.restPose.end(), scalar.begin());
      sampleCompactClipTracksScalar(compact, t, scalar);
      return std::memcmp(hinted.data(), plain.data(), n * sizeof(Transform)) == 0 &&
             std::memcmp(hinted.data(), scalar.data(), n * sizeof(Transform)) == 0;
    };
    const float times[] = {0.3f, 0.31f, 0.5f, 0.7f, 0.71f, 1.3f, 0.1f, 1.99f, 2.5f, 0.0f, 1.0f, -1.0f, 0.69f, 0.7f, NAN, 0.7f};
    for (int pass = 0; pass < 2; ++pass) {
      for (const float t : times) EXPECT_TRUE(same(t)) << joints << " joints at " << t;
      for (std::uint32_t& h : hints) h = 7;  // hints another clip left
    }
    for (int f = 0; f <= 480; ++f) {  // forward, as a player goes: between frames and on them
      const float t = static_cast<float>(f) / 240.0f;
      ASSERT_TRUE(same(t)) << joints << " joints at " << t;
    }
  }
}

// AnimationClip::pose holds the rest pose with the compact clip's constant tracks applied
// once at load: sampling over it gives the bits of sampling over the skeleton's rest
// pose, compact or float, and the constants are in it (a held scale and rotation).
TEST(CompactClip, SamplingOverTheClipsPoseGivesTheBitsOfTheRestPose) {
  ChainClip c = piecewiseLinearChain(9);
  c.clip.tracks[2].scale.times = {0.0f, 2.0f};
  c.clip.tracks[2].scale.values = {glm::vec3(1.5f), glm::vec3(1.5f)};
  c.clip.tracks[4].rotation.times = {0.0f, 1.0f, 2.0f};
  c.clip.tracks[4].rotation.values.assign(3, glm::angleAxis(0.4f, glm::vec3(0, 0, 1)));
  for (const bool compact : {true, false}) {
    AnimationClipOptions options;
    options.compactClips = compact;
    const auto ac = makeAnimationClip(c.clip, c.skeleton, options);
    ASSERT_EQ(ac->compact.empty(), !compact);
    ASSERT_EQ(ac->pose.size(), c.skeleton.jointCount());
    if (compact) {
      EXPECT_GE(ac->compact.constants, 2u);
      EXPECT_EQ(ac->pose[2].scale, glm::vec3(1.5f));
      EXPECT_NEAR(std::fabs(glm::dot(ac->pose[4].rotation, glm::angleAxis(0.4f, glm::vec3(0, 0, 1)))), 1.0f, 1e-6f);
    }
    std::vector<Transform> overPose(9), overRest(9);
    SamplingCursor a, b;  // with hints over the pose, without over the rest pose
    a.reset(ac->clip);
    for (int f = -2; f <= 130; ++f) {
      const float t = static_cast<float>(f) / 60.0f;
      sampleAnimationClip(*ac, t, true, overPose, &a);
      sampleAnimationClip(*ac, t, true, c.skeleton.restPose, overRest, &b);
      ASSERT_EQ(std::memcmp(overPose.data(), overRest.data(), overPose.size() * sizeof(Transform)), 0) << compact << " at " << t;
    }
  }
}
