#include <gtest/gtest.h>

#include <limits>
#include <vector>

#include "marionette/animation/sampling.hpp"
#include "synthetic.hpp"

using namespace marionette;
using namespace marionette::test;

namespace {
Clip oneTrackClip(JointTrack jt) {
  Clip c;
  c.name = "c";
  c.tracks.push_back(std::move(jt));
  c.updateDuration();
  return c;
}
glm::quat at(const Clip& c, float t, int joints = 1, SamplingCursor* cursor = nullptr) {
  std::vector<Transform> rest(joints), out(joints);
  sampleClip(c, t, rest, out, cursor);
  return out[c.tracks[0].joint].rotation;
}
}  // namespace

// Invalid input first (ozz style): out-of-range joints, empty and mismatched tracks.
TEST(Sampling, TrackForJointOutsidePoseIsIgnored) {
  Clip c = oneTrackClip(rotationTrack(5, {0, 1}, {0, 1}));
  std::vector<Transform> rest(2), out(2);
  sampleClip(c, 0.5f, rest, out);
  EXPECT_EQ(out[0].rotation, glm::quat(1, 0, 0, 0));
  EXPECT_EQ(out[1].rotation, glm::quat(1, 0, 0, 0));
}

TEST(Sampling, ValidateRejectsBadTracks) {
  Clip c = oneTrackClip(rotationTrack(0, {0, 1, 1}, {0, 1, 2}));
  EXPECT_NE(c.validate(1).find("strictly increasing"), std::string::npos);
  Clip d = oneTrackClip(rotationTrack(0, {0, 1}, {0}));
  EXPECT_NE(d.validate(1).find("values"), std::string::npos);
  Clip e = oneTrackClip(rotationTrack(3, {0, 1}, {0, 1}));
  EXPECT_NE(e.validate(2).find("outside"), std::string::npos);
  Clip ok = oneTrackClip(rotationTrack(0, {0, 1}, {0, 1}));
  EXPECT_EQ(ok.validate(1), "");
}

TEST(Sampling, ExactlyAtKeysBeforeFirstAndAfterLast) {
  Clip c = oneTrackClip(rotationTrack(0, {0.5f, 1.0f, 2.0f}, {0.1f, 0.4f, 1.0f}));
  EXPECT_NEAR(angleBetween(at(c, 0.5f), glm::angleAxis(0.1f, glm::vec3(0, 0, 1))), 0.0f, 1e-3f);
  EXPECT_NEAR(angleBetween(at(c, 1.0f), glm::angleAxis(0.4f, glm::vec3(0, 0, 1))), 0.0f, 1e-3f);
  EXPECT_NEAR(angleBetween(at(c, 2.0f), glm::angleAxis(1.0f, glm::vec3(0, 0, 1))), 0.0f, 1e-3f);
  EXPECT_NEAR(angleBetween(at(c, -3.0f), glm::angleAxis(0.1f, glm::vec3(0, 0, 1))), 0.0f, 1e-3f);
  EXPECT_NEAR(angleBetween(at(c, 99.0f), glm::angleAxis(1.0f, glm::vec3(0, 0, 1))), 0.0f, 1e-3f);
  // Midway between keys 1 and 2 (nlerp of a 0.6 rad arc: within 1e-3 rad of 0.7).
  EXPECT_NEAR(angleBetween(at(c, 1.5f), glm::angleAxis(0.7f, glm::vec3(0, 0, 1))), 0.0f, 2e-3f);
}

TEST(Sampling, OneKeyAndZeroLengthClips) {
  Clip c = oneTrackClip(rotationTrack(0, {0.0f}, {0.3f}));
  EXPECT_EQ(c.duration, 0.0f);
  for (float t : {-1.0f, 0.0f, 0.5f, 1e6f})
    EXPECT_NEAR(angleBetween(at(c, t), glm::angleAxis(0.3f, glm::vec3(0, 0, 1))), 0.0f, 1e-3f);
  EXPECT_EQ(wrapClipTime(123.0, 0.0f, WrapMode::Loop), 0.0f);
  EXPECT_EQ(wrapClipTime(123.0, 0.0f, WrapMode::Clamp), 0.0f);
  Clip empty;
  std::vector<Transform> rest(3), out(3);
  rest[1].translation = {1, 2, 3};
  sampleClip(empty, 0.5f, rest, out);
  EXPECT_EQ(out[1].translation, glm::vec3(1, 2, 3));
}

TEST(Sampling, StepHoldsTheKey) {
  Clip c = oneTrackClip(rotationTrack(0, {0, 1, 2}, {0.0f, 1.0f, 2.0f}, {0, 0, 1}, Interpolation::Step));
  EXPECT_NEAR(angleBetween(at(c, 0.99f), glm::quat(1, 0, 0, 0)), 0.0f, 1e-4f);
  EXPECT_NEAR(angleBetween(at(c, 1.0f), glm::angleAxis(1.0f, glm::vec3(0, 0, 1))), 0.0f, 1e-3f);
  EXPECT_NEAR(angleBetween(at(c, 1.5f), glm::angleAxis(1.0f, glm::vec3(0, 0, 1))), 0.0f, 1e-3f);
}

TEST(Sampling, CubicSplineMatchesHermite) {
  // x(t) with values 0 -> 1 over [0, 2], tangents 0 at both ends: smoothstep.
  JointTrack jt;
  jt.joint = 0;
  jt.translation.interpolation = Interpolation::CubicSpline;
  jt.translation.times = {0.0f, 2.0f};
  jt.translation.values = {glm::vec3(0), glm::vec3(0), glm::vec3(0), glm::vec3(0), glm::vec3(1, 0, 0), glm::vec3(0)};
  Clip c = oneTrackClip(jt);
  std::vector<Transform> rest(1), out(1);
  for (float t : {0.0f, 0.5f, 1.0f, 1.5f, 2.0f}) {
    sampleClip(c, t, rest, out);
    float u = t / 2.0f;
    EXPECT_NEAR(out[0].translation.x, u * u * (3 - 2 * u), 1e-5f) << "t=" << t;
  }
  // Nonzero out-tangent: slope at the start equals the tangent (1 per second).
  c.tracks[0].translation.values[2] = glm::vec3(1, 0, 0);
  sampleClip(c, 1e-3f, rest, out);
  EXPECT_NEAR(out[0].translation.x / 1e-3f, 1.0f, 1e-2f);
}

TEST(Sampling, CursorGivesTheSameResultAsBinarySearch) {
  std::vector<float> times, angles;
  for (int k = 0; k < 100; ++k) {
    times.push_back(static_cast<float>(k) * 0.1f);
    angles.push_back(std::sin(static_cast<float>(k) * 0.37f));
  }
  Clip c = oneTrackClip(rotationTrack(0, times, angles));
  SamplingCursor cursor;
  cursor.reset(c);
  // Forward, backward and jumping access.
  for (float t : {0.0f, 0.05f, 0.31f, 0.32f, 5.0f, 2.0f, 9.9f, 0.0f, 9.95f}) {
    glm::quat a = at(c, t, 1, &cursor), b = at(c, t);
    EXPECT_EQ(a, b) << t;
  }
  // A cursor made for another clip is not used (no out-of-bounds).
  Clip other = oneTrackClip(rotationTrack(0, {0, 1}, {0, 1}));
  glm::quat q = at(other, 0.5f, 1, &cursor);
  EXPECT_NEAR(angleBetween(q, glm::angleAxis(0.5f, glm::vec3(0, 0, 1))), 0.0f, 1e-3f);
}

TEST(Sampling, AntipodalKeysTakeTheShortArc) {
  // Key 1 is the negation of a rotation close to key 0: must not swing through 360°.
  JointTrack jt = rotationTrack(0, {0, 1}, {0.1f, 0.2f});
  jt.rotation.values[1] = -jt.rotation.values[1];
  Clip c = oneTrackClip(jt);
  EXPECT_NEAR(angleBetween(at(c, 0.5f), glm::angleAxis(0.15f, glm::vec3(0, 0, 1))), 0.0f, 1e-3f);
}

TEST(Sampling, WrapTimeInDoubleHasNoJitterAt1e7Seconds) {
  const float d = 1.3333f;
  for (double base : {0.0, 1.0e7}) {
    const double cycles = std::floor(base / d);
    const double t0 = cycles * d;
    for (double f : {0.1, 0.5, 1.0}) {
      float w = wrapClipTime(t0 + f, d, WrapMode::Loop);
      EXPECT_NEAR(w, f, 1e-5) << "base " << base;  // float time at 1e7 would be off by ~0.5 s
    }
  }
  EXPECT_NEAR(wrapClipTime(-0.25, 1.0f, WrapMode::Loop), 0.75f, 1e-6f);
  EXPECT_EQ(wrapClipTime(5.0, 1.0f, WrapMode::Clamp), 1.0f);
  EXPECT_EQ(wrapClipTime(NAN, 1.0f, WrapMode::Loop), 0.0f);
}

TEST(Sampling, MorphWeightsLinearStepCubic) {
  Clip c;
  MorphTrack m;
  m.targets = {1, 0};
  m.times = {0, 1};
  m.weights = {0.0f, 1.0f, 1.0f, 0.0f};  // key0: t1=0,t0=1 ; key1: t1=1,t0=0
  c.morphTracks.push_back(m);
  std::vector<float> w(3, -1.0f);
  sampleMorphWeights(c, 0.25f, w);
  EXPECT_NEAR(w[1], 0.25f, 1e-6f);
  EXPECT_NEAR(w[0], 0.75f, 1e-6f);
  EXPECT_EQ(w[2], -1.0f);  // untouched
  c.morphTracks[0].interpolation = Interpolation::Step;
  sampleMorphWeights(c, 0.9f, w);
  EXPECT_EQ(w[1], 0.0f);
}

// A time from an overflowed float (NaN, +-inf) must never become a key index: it holds the
// first key (NaN, -inf) or the last (+inf). Under AddressSanitizer a read past the key
// times fails this test (../shared/repro/README.md, the C API's dt of 1e39).
TEST(Sampling, NanAndInfiniteTimesHoldAnEndKey) {
  const std::vector<float> times = {0.0f, 0.5f, 1.0f, 2.0f};
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  for (std::uint32_t hint : {0u, 1u, 2u, 99u}) {
    EXPECT_EQ(findKeyInterval(times, nan, hint), 0u) << hint;
    EXPECT_EQ(findKeyInterval(times, -inf, hint), 0u) << hint;
    EXPECT_EQ(findKeyInterval(times, inf, hint), 2u) << hint;
  }
  Clip c = oneTrackClip(rotationTrack(0, {0, 0.5f, 1, 2}, {0, 1, 2, 3}));
  SamplingCursor cursor;
  const glm::quat first = at(c, 0.0f), last = at(c, 2.0f);
  for (int pass = 0; pass < 2; ++pass) {  // with and without a cursor
    SamplingCursor* cur = pass ? &cursor : nullptr;
    const glm::quat q = at(c, nan, 1, cur), hi = at(c, inf, 1, cur), lo = at(c, -inf, 1, cur);
    EXPECT_EQ(q, first);
    EXPECT_EQ(lo, first);
    EXPECT_EQ(hi, last);
  }
}
