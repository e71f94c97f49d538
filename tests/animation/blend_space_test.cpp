// Blend spaces: invalid definitions first, then the weights (partition of unity, exact
// at samples, linear precision, continuity, outside the range or hull), the phase warp
// of clips whose foot contacts are known exactly (a synthetic walk and a copy of it
// shifted and sped up), and a character playing a space on a layer.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "marionette/animation/animation_clip.hpp"
#include "marionette/animation/blend_space.hpp"
#include "marionette/rig/rig.hpp"
#include "marionette/scene/character.hpp"
#include "synthetic_walk.hpp"

using namespace marionette;
using namespace marionette::test;

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// The synthetic walk resampled so that its phase p plays at phase p + shift and its cycle
// lasts `duration` s (linear keys at 240 per cycle: exact enough for the contacts).
Clip shiftedWalk(const SyntheticWalk& w, float shift, float duration, const char* name) {
  Clip out;
  out.name = name;
  const int n = 240;
  std::vector<Transform> pose(w.skeleton.jointCount());
  std::vector<JointTrack> tracks(w.skeleton.jointCount());
  for (std::size_t j = 0; j < tracks.size(); ++j) tracks[j].joint = static_cast<int>(j);
  for (int k = 0; k <= n; ++k) {
    const float p = static_cast<float>(k) / n;
    float q = p + shift;
    q -= std::floor(q);
    if (k == n) q = shift - std::floor(shift) == 0.0f ? 1.0f : q;
    sampleClip(w.clip, q * w.clip.duration, w.skeleton.restPose, pose);
    for (std::size_t j = 0; j < tracks.size(); ++j) {
      tracks[j].translation.times.push_back(p * duration);
      glm::vec3 v = pose[j].translation;
      if (j == 0) v.z = 0.0f;  // in place: the hips' travel would jump at the wrap
      tracks[j].translation.values.push_back(v);
    }
  }
  out.tracks = std::move(tracks);
  out.updateDuration();
  return out;
}

struct Walks {
  SyntheticWalk walk = makeSyntheticWalk(false);
  std::shared_ptr<const AnimationClip> slow, fast;
  BlendSpaceFeet feet;
  Walks() {
    RigSettings options;
    options.optimizeClips = false;
    slow = makeAnimationClip(shiftedWalk(walk, 0.0f, 1.0f, "slow"), walk.skeleton, options);
    fast = makeAnimationClip(shiftedWalk(walk, 0.25f, 0.6f, "fast"), walk.skeleton, options);
    feet.left = walk.leftFoot;
    feet.right = walk.rightFoot;
  }
};

float sum(std::span<const float> w) {
  float s = 0.0f;
  for (float v : w) s += v;
  return s;
}

void expectPartition(std::span<const float> w, const char* what) {
  int nonZero = 0;
  for (float v : w) {
    EXPECT_GE(v, 0.0f) << what;
    EXPECT_TRUE(std::isfinite(v)) << what;
    nonZero += v > 0.0f;
  }
  EXPECT_NEAR(sum(w), 1.0f, 1e-5f) << what;
  EXPECT_LE(nonZero, static_cast<int>(BlendSpace::kMaxActive)) << what;
}

std::shared_ptr<const BlendSpace> space2D(const Walks& w, std::vector<glm::vec2> points, std::string& error) {
  std::vector<BlendSpaceSample> samples;
  for (std::size_t i = 0; i < points.size(); ++i) samples.push_back({i % 2 ? w.fast : w.slow, points[i].x, points[i].y});
  return BlendSpace::make("grid", 2, samples, w.walk.skeleton, w.feet, false, error);
}

}  // namespace

TEST(BlendSpaceDefinition, InvalidOnesAreRefusedWithTheReason) {
  auto check = [](BlendSpaceDefinition d, const char* expected) {
    const std::string why = validateBlendSpaceDefinition(d);
    EXPECT_NE(why.find(expected), std::string::npos) << why;
  };
  check({"", 1, {{"a", 0}}, true}, "needs a name");
  check({"s", 3, {{"a", 0}}, true}, "3 dimensions");
  check({"s", 1, {}, true}, "0 samples");
  check({"s", 2, {{"a", 0, 0}, {"b", 1, 0}}, true}, "2 samples (expected 3");
  check({"s", 1, {{"a", 1}, {"b", 1}}, true}, "samples 0 ('a') and 1 ('b') are both at x = 1");
  check({"s", 2, {{"a", 0, 0}, {"b", 1, 0}, {"c", 0, 0}}, true}, "are both at (0, 0)");
  check({"s", 1, {{"a", kNaN}}, true}, "not a finite number");
  check({"s", 2, {{"a", 0, 0}, {"b", 1, INFINITY}, {"c", 0, 1}}, true}, "not a finite number");
  check({"s", 2, {{"a", 0, 0}, {"b", 1, 1}, {"c", 2, 2}, {"d", -3, -3}}, true}, "lie on one line");
  check({"s", 1, {{"", 0}}, true}, "names no clip");
  EXPECT_EQ(validateBlendSpaceDefinition({"s", 2, {{"a", 0, 0}, {"b", 1, 0}, {"c", 0, 1}}, true}), "");

  Walks w;
  std::string error;
  EXPECT_FALSE(BlendSpace::make("s", 1, {{nullptr, 0}}, w.walk.skeleton, w.feet, true, error));
  EXPECT_NE(error.find("sample 0 has no clip"), std::string::npos) << error;
  EXPECT_FALSE(BlendSpace::make("s", 1, {{w.slow, 0}, {w.fast, 0}}, w.walk.skeleton, w.feet, true, error));
  EXPECT_NE(error.find("both at x = 0"), std::string::npos) << error;

  // By name from a rig: an unknown clip is named, with the rig's clips.
  Asset asset;
  asset.skeleton = w.walk.skeleton;
  asset.clips = {shiftedWalk(w.walk, 0.0f, 1.0f, "slow")};
  Rig rig(asset);
  EXPECT_FALSE(rig.makeBlendSpace({"loco", 1, {{"slow", 1}, {"sprint", 3}}, true}, error));
  EXPECT_NE(error.find("names the clip 'sprint', which the rig has not (it has 'slow')"), std::string::npos) << error;
}

TEST(BlendSpaceWeights, OneDimensionIsPiecewiseLinearAndClamped) {
  Walks w;
  std::string error;
  // Out of order on purpose: the weights follow x, not the list.
  auto s = BlendSpace::make("speed", 1, {{w.fast, 3.0f}, {w.slow, 1.0f}, {w.slow, 2.0f}}, w.walk.skeleton, w.feet, true, error);
  ASSERT_TRUE(s) << error;
  std::vector<float> wt(3);
  const float xs[] = {1.0f, 2.0f, 3.0f};
  const int at[] = {1, 2, 0};
  for (int k = 0; k < 3; ++k) {  // exact at samples
    s->weights(xs[k], 0.0f, wt);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(wt[static_cast<std::size_t>(i)], i == at[k] ? 1.0f : 0.0f) << xs[k];
  }
  s->weights(2.25f, 0.0f, wt);
  EXPECT_FLOAT_EQ(wt[2], 0.75f);
  EXPECT_FLOAT_EQ(wt[0], 0.25f);
  EXPECT_EQ(wt[1], 0.0f);
  s->weights(-5.0f, 0.0f, wt);  // outside: the end samples
  EXPECT_EQ(wt[1], 1.0f);
  s->weights(50.0f, 0.0f, wt);
  EXPECT_EQ(wt[0], 1.0f);
  s->weights(kNaN, 0.0f, wt);  // the middle of the range
  expectPartition(wt, "NaN");
  EXPECT_FLOAT_EQ(wt[2], 1.0f);
  // Continuous: a sweep moves no weight by more than its step over the narrowest gap.
  std::vector<float> prev(3);
  s->weights(0.0f, 0.0f, prev);
  for (float x = 0.0f; x <= 4.0f; x += 0.001f) {
    s->weights(x, 0.0f, wt);
    expectPartition(wt, "sweep");
    for (int i = 0; i < 3; ++i) EXPECT_LE(std::fabs(wt[static_cast<std::size_t>(i)] - prev[static_cast<std::size_t>(i)]), 0.0011f) << x;
    prev = wt;
  }
  EXPECT_NEAR(s->cycleDuration(std::vector<float>{0.5f, 0.5f, 0.0f}), 0.5 * 0.6 + 0.5 * 1.0, 1e-7);
}

TEST(BlendSpaceWeights, TwoDimensionsAreBarycentricOverADelaunayTriangulation) {
  Walks w;
  std::string error;
  // A 3 x 3 grid with axes of different units (m/s, degrees), and an irregular layout.
  // (A sample nearly on the hull's edge makes a sliver triangle whose weights are continuous
  // but steep: a fixed step bound would not hold across it, so the layout keeps clear of that.)
  std::vector<glm::vec2> grid;
  for (float speed : {0.0f, 1.5f, 4.0f})
    for (float direction : {-90.0f, 0.0f, 90.0f}) grid.push_back({speed, direction});
  const std::vector<glm::vec2> irregular = {{0, 0}, {1, 0.1f}, {0.3f, 1.3f}, {1.4f, 1.2f}, {0.6f, 0.4f}, {-0.5f, 0.7f}};
  for (const auto& points : {grid, irregular}) {
    auto s = space2D(w, points, error);
    ASSERT_TRUE(s) << error;
    EXPECT_FALSE(s->triangles().empty());
    std::vector<float> wt(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {  // exact at samples
      s->weights(points[i].x, points[i].y, wt);
      for (std::size_t k = 0; k < points.size(); ++k) EXPECT_EQ(wt[k], k == i ? 1.0f : 0.0f);
    }
    float minX = INFINITY, maxX = -INFINITY, minY = INFINITY, maxY = -INFINITY;
    for (const auto& p : points)
      minX = std::min(minX, p.x), maxX = std::max(maxX, p.x), minY = std::min(minY, p.y), maxY = std::max(maxY, p.y);
    const float ex = maxX - minX, ey = maxY - minY;
    // A sweep over the layout and around it: a partition, continuous, linear inside.
    const int steps = 300;
    std::vector<float> prev;
    for (int r = 0; r <= steps; ++r) {
      prev.clear();
      for (int c = 0; c <= steps; ++c) {
        const float x = minX - 0.3f * ex + 1.6f * ex * static_cast<float>(c) / steps;
        const float y = minY - 0.3f * ey + 1.6f * ey * static_cast<float>(r) / steps;
        s->weights(x, y, wt);
        expectPartition(wt, "2D sweep");
        glm::vec2 mean(0.0f);
        for (std::size_t k = 0; k < points.size(); ++k) mean += wt[k] * points[k];
        // Linear precision: inside the hull the weights reproduce the point; outside they
        // give a point of the hull, never farther than the point itself from any sample.
        const bool insideBox = x >= minX && x <= maxX && y >= minY && y <= maxY;
        if (points.size() == 9 && insideBox) {
          EXPECT_NEAR(mean.x, x, 1e-4f * ex) << x << ", " << y;
          EXPECT_NEAR(mean.y, y, 1e-4f * ey) << x << ", " << y;
        }
        if (!prev.empty()) {  // a step of 1.6/300 of the extent moves a weight by at most a few steps' worth
          float jump = 0.0f;
          for (std::size_t k = 0; k < points.size(); ++k) jump = std::max(jump, std::fabs(wt[k] - prev[k]));
          EXPECT_LT(jump, 0.05f) << x << ", " << y;
        }
        prev = wt;
      }
    }
    // Far outside: the nearest part of the hull (the grid's corner at 4 m/s, 90 degrees).
    if (points.size() == 9) {
      s->weights(40.0f, 900.0f, wt);
      EXPECT_FLOAT_EQ(wt[8], 1.0f);
      s->weights(2.75f, 500.0f, wt);  // above the top edge, between its 2nd and 3rd samples
      EXPECT_NEAR(wt[5], 0.5f, 1e-5f);
      EXPECT_NEAR(wt[8], 0.5f, 1e-5f);
      s->weights(kNaN, kNaN, wt);
      expectPartition(wt, "NaN");
    }
  }
}

TEST(BlendSpacePhase, ContactsOfTheBlendedClipsCoincideInTheSharedPhase) {
  Walks w;
  std::string error;
  auto s = BlendSpace::make("walks", 1, {{w.slow, 1.0f}, {w.fast, 1.67f}}, w.walk.skeleton, w.feet, true, error);
  ASSERT_TRUE(s) << error;
  for (std::size_t i = 0; i < 2; ++i) {
    const BlendSpace::Sample& sample = s->samples()[i];
    ASSERT_EQ(sample.keys.size(), 2u) << i;
    ASSERT_EQ(sample.contacts[0].size(), 1u);
    ASSERT_EQ(sample.contacts[1].size(), 1u);
    // Each foot's touchdown is where the shared phase says: left at 0, right at 0.5.
    const double left = sample.contacts[0][0].begin, right = sample.contacts[1][0].begin;
    auto clipPhase = [&](double shared) {
      double p = s->clipTime(i, shared) / sample.duration;
      return p - std::floor(p);
    };
    auto near = [](double a, double b) { return std::min(std::fabs(a - b), 1.0 - std::fabs(a - b)); };
    EXPECT_LT(near(clipPhase(0.0), left), 1e-6) << i;
    EXPECT_LT(near(clipPhase(0.5), right), 1e-6) << i;
    EXPECT_LT(near(s->sharedPhase(i, left), 0.0), 1e-6) << i;
    EXPECT_LT(near(s->sharedPhase(i, right), 0.5), 1e-6) << i;
    // Monotone and continuous across cycles; the inverse round-trips.
    double prev = s->clipTime(i, -1.0);
    for (double p = -1.0; p <= 2.0; p += 0.001) {
      const double t = s->clipTime(i, p);
      EXPECT_GE(t, prev - 1e-9) << p;
      EXPECT_LT(t - prev, 0.01 * sample.duration) << p;
      prev = t;
      EXPECT_LT(near(s->sharedPhase(i, t / sample.duration), p - std::floor(p)), 1e-5) << p;
    }
  }
  // The synthetic clips: the slow one lands its left foot at phase 0, the fast one at 0.75
  // (its copy is shifted by a quarter): at shared phase 0 both are at their touchdown.
  auto around = [](float a, float b) { return std::min(std::fabs(a - b), 1.0f - std::fabs(a - b)); };
  EXPECT_LT(around(s->samples()[0].contacts[0][0].begin, 0.0f), 0.01f);
  EXPECT_LT(around(s->samples()[1].contacts[0][0].begin, 0.75f), 0.01f);

  // Without alignment, and for a clip without feet: plain normalized time.
  auto plain = BlendSpace::make("plain", 1, {{w.slow, 1.0f}, {w.fast, 2.0f}}, w.walk.skeleton, w.feet, false, error);
  ASSERT_TRUE(plain) << error;
  BlendSpaceFeet none;
  auto footless = BlendSpace::make("footless", 1, {{w.slow, 1.0f}, {w.fast, 2.0f}}, w.walk.skeleton, none, true, error);
  ASSERT_TRUE(footless) << error;
  for (const auto& space : {plain, footless})
    for (double p : {0.0, 0.3, 1.7}) EXPECT_NEAR(space->clipTime(1, p), p * 0.6, 1e-6) << space->name();
}

TEST(BlendSpaceOnACharacter, PlaysOnALayerAtTheWeightedCycle) {
  Walks w;
  std::string error;
  Asset asset;
  asset.skeleton = w.walk.skeleton;
  asset.clips = {shiftedWalk(w.walk, 0.0f, 1.0f, "slow"), shiftedWalk(w.walk, 0.25f, 0.6f, "fast")};
  auto rig = std::make_shared<Rig>(asset);
  auto space = BlendSpace::make("walks", 1, {{rig->findClip("slow"), 1.0f}, {rig->findClip("fast"), 2.0f}},
                                rig->skeleton(), w.feet, true, error);
  ASSERT_TRUE(space) << error;
  EXPECT_TRUE(rig->addBlendSpace(space));
  EXPECT_FALSE(rig->addBlendSpace(nullptr));
  Character c("walker", rig);
  EXPECT_FALSE(c.playBlend(-1, space));
  EXPECT_FALSE(c.playBlend(Character::kMaxLayers, space));
  EXPECT_FALSE(c.playBlend(0, std::shared_ptr<const BlendSpace>()));
  EXPECT_FALSE(c.playBlend(0, "no such space"));
  PlayOptions additive;
  additive.additive = true;
  EXPECT_FALSE(c.playBlend(0, space, additive));
  EXPECT_FALSE(c.setBlendParameter(0, 1.0f));  // nothing plays there
  EXPECT_EQ(c.layerCount(), 0);

  ASSERT_TRUE(c.playBlend(0, "walks", {}, 1.5f));
  EXPECT_EQ(c.layerCount(), 1);
  EXPECT_EQ(c.layerBlendSpace(0), space.get());
  ASSERT_EQ(c.layerBlendWeights(0).size(), 2u);
  EXPECT_FLOAT_EQ(c.layerBlendWeights(0)[0], 0.5f);
  EXPECT_FALSE(c.setBlendParameter(0, kNaN));
  EXPECT_FLOAT_EQ(c.layerBlendWeights(0)[1], 0.5f);  // kept
  // The phase advances by dt / (0.5 * 1 s + 0.5 * 0.6 s).
  for (int i = 0; i < 40; ++i) c.update(0.01);
  EXPECT_NEAR(c.layerTime(0), 0.4 / 0.8, 1e-6);
  ASSERT_TRUE(c.setBlendParameter(0, 2.0f));
  for (int i = 0; i < 30; ++i) c.update(0.01);
  EXPECT_NEAR(c.layerTime(0), 0.5 + 0.3 / 0.6, 1e-6);
  for (const Transform& t : c.localPose()) EXPECT_TRUE(std::isfinite(t.translation.x) && std::isfinite(t.rotation.w));
  // At weight 1 on the fast clip, the pose is that clip's at its warped time.
  std::vector<Transform> expected(rig->skeleton().jointCount());
  sampleAnimationClip(*rig->findClip("fast"), wrapClipTime(space->clipTime(1, c.layerTime(0)), 0.6f, WrapMode::Loop),
                      false, expected);
  for (std::size_t j = 0; j < expected.size(); ++j)
    EXPECT_NEAR(glm::distance(c.localPose()[j].translation, expected[j].translation), 0.0f, 1e-5f) << j;
  // A clip on the layer replaces the space; stop frees it.
  ASSERT_TRUE(c.play(0, "slow"));
  EXPECT_EQ(c.layerBlendSpace(0), nullptr);
  ASSERT_TRUE(c.playBlend(1, space, {}, 1.0f));
  c.stop(1, 0.0f);
  EXPECT_EQ(c.layerBlendSpace(1), nullptr);
  EXPECT_EQ(c.layerCount(), 1);
}
