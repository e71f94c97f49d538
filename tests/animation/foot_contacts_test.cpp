// Foot contacts of clips: invalid input first, then a synthetic walk whose
// contacts are known exactly (travelling and in place), the noise filters, and
// the per-frame queries inContact and contactWeight.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "marionette/animation/foot_contacts.hpp"
#include "marionette/rig/rig.hpp"
#include "synthetic_walk.hpp"

using namespace marionette;
using namespace marionette::test;

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

AnimationClip prepare(const SyntheticWalk& w) {
  RigSettings options;
  options.optimizeClips = false;
  return *makeAnimationClip(w.clip, w.skeleton, options);
}

// Distance between two phases around the cycle.
float phaseGap(float a, float b) {
  const float d = std::fabs(a - b);
  return std::min(d, 1.0f - d);
}

std::string describe(const std::vector<ContactInterval>& v) {
  std::string out;
  for (const auto& c : v) out += "[" + std::to_string(c.begin) + ", " + std::to_string(c.end) + ") ";
  return out;
}

void expectFinite(const std::vector<ContactInterval>& v) {
  for (const auto& c : v) {
    EXPECT_TRUE(c.begin >= 0.0f && c.begin < 1.0f) << c.begin;
    EXPECT_TRUE(c.end >= 0.0f && c.end <= 1.0f) << c.end;
  }
}

}  // namespace

// ---- invalid input ---------------------------------------------------------------

TEST(FootContacts, InvalidInputGivesNoContacts) {
  SyntheticWalk w = makeSyntheticWalk();
  const AnimationClip clip = prepare(w);
  EXPECT_TRUE(detectFootContacts(clip, w.skeleton, -1).empty());
  EXPECT_TRUE(detectFootContacts(clip, w.skeleton, 3).empty());
  EXPECT_TRUE(detectFootContacts(clip, Skeleton{}, 0).empty());

  AnimationClip still;  // zero duration: one key per track, or none
  still.clip.tracks.push_back(w.clip.tracks[1]);
  still.clip.tracks[0].translation.times = {0.0f};
  still.clip.tracks[0].translation.values = {{0.1f, -0.9f, 0.0f}};
  still.clip.updateDuration();
  ASSERT_EQ(still.clip.duration, 0.0f);
  EXPECT_TRUE(detectFootContacts(still, w.skeleton, w.leftFoot).empty());
  EXPECT_TRUE(detectFootContacts(AnimationClip{}, w.skeleton, w.leftFoot).empty());
  still.clip.duration = kNaN;
  EXPECT_TRUE(detectFootContacts(still, w.skeleton, w.leftFoot).empty());
}

TEST(FootContacts, NaNKeysGiveNoNaN) {
  SyntheticWalk w = makeSyntheticWalk();
  w.clip.tracks[1].translation.values[2] = glm::vec3(kNaN);  // the left swing's top
  AnimationClip clip = prepare(w);
  const auto left = detectFootContacts(clip, w.skeleton, w.leftFoot);
  expectFinite(left);
  ASSERT_EQ(left.size(), 1u) << describe(left);  // the stance is still found
  EXPECT_LT(phaseGap(left[0].begin, 0.0f), 1.5f / 240.0f) << describe(left);

  for (auto& v : w.clip.tracks[1].translation.values) v = glm::vec3(kNaN);  // no usable sample at all
  clip = prepare(w);
  EXPECT_TRUE(detectFootContacts(clip, w.skeleton, w.leftFoot).empty());
  clip.clip.tracks[0].translation.values[1] = glm::vec3(kNaN);  // and a NaN root
  const auto right = detectFootContacts(clip, w.skeleton, w.rightFoot);
  expectFinite(right);
}

// ---- a walk with known contacts -------------------------------------------------------

TEST(FootContacts, SyntheticWalkTravellingAndInPlace) {
  for (const int variant : {0, 1, 2}) {  // travelling; in place; in place without a root track
    SyntheticWalk w = makeSyntheticWalk(variant == 0);
    if (variant == 2) w.clip.tracks.erase(w.clip.tracks.begin());
    AnimationClip clip = prepare(w);
    if (variant == 2) clip.rootMotion = RootMotion{};  // (else the rig would take a foot's track for the root's)
    ASSERT_EQ(clip.rootMotion.empty(), variant == 2);
    const FootContactOptions settings;
    const float tolerance = 1.0f / static_cast<float>(settings.samplesPerSecond);  // one sample of the 1 s cycle
    const auto left = detectFootContacts(clip, w.skeleton, w.leftFoot, settings);
    const auto right = detectFootContacts(clip, w.skeleton, w.rightFoot, settings);
    std::printf("synthetic walk %-28s left %s right %s\n",
                variant == 0 ? "(travelling)" : variant == 1 ? "(in place)" : "(in place, no root track)",
                describe(left).c_str(), describe(right).c_str());
    ASSERT_EQ(left.size(), 1u) << variant << ": " << describe(left);
    ASSERT_EQ(right.size(), 1u) << variant << ": " << describe(right);
    EXPECT_LT(phaseGap(left[0].begin, 0.0f), tolerance) << variant;
    EXPECT_LT(phaseGap(left[0].end, 0.6f), tolerance) << variant;
    EXPECT_LT(phaseGap(right[0].begin, 0.5f), tolerance) << variant;
    EXPECT_LT(phaseGap(right[0].end, 0.1f), tolerance) << variant;
    EXPECT_GT(right[0].begin, right[0].end);  // wraps across the loop point
    for (int i = 2; i <= 98; ++i) {  // away from the ends, where the sampling decides
      const float p = static_cast<float>(i) / 100.0f;
      if (i < 59 || i > 61) {
        EXPECT_EQ(inContact(left, p), i < 60) << p;
      }
      if ((i < 49 || i > 51) && (i < 9 || i > 11)) {
        EXPECT_EQ(inContact(right, p), i > 50 || i < 10) << p;
      }
    }
  }
}

TEST(FootContacts, ShortDipsAndGapsAreNoise) {
  SyntheticWalk w = makeSyntheticWalk();
  // The left foot scuffs the ground for 30 ms in mid-swing (at rest in the
  // ground frame: its local z follows the hips), and the right one lifts 8 cm
  // for 20 ms in mid-stance.
  JointTrack& left = w.clip.tracks[1];
  left.translation.times = {0.0f, 0.6f, 0.7f, 0.85f, 0.88f, 0.95f, 1.0f};
  left.translation.values = {{0.1f, -0.9f, 0.0f},   {0.1f, -0.9f, -0.6f},  {0.1f, -0.75f, -0.45f},
                             {0.1f, -0.9f, -0.25f}, {0.1f, -0.9f, -0.28f}, {0.1f, -0.75f, -0.1f},
                             {0.1f, -0.9f, 0.0f}};
  JointTrack& right = w.clip.tracks[2];
  right.translation.times = {0.0f, 0.1f, 0.3f, 0.5f, 0.7f, 0.71f, 0.72f, 1.0f};
  right.translation.values = {{-0.1f, -0.9f, -0.5f}, {-0.1f, -0.9f, -0.6f}, {-0.1f, -0.75f, -0.3f},
                              {-0.1f, -0.9f, 0.0f},  {-0.1f, -0.9f, -0.2f}, {-0.1f, -0.82f, -0.21f},
                              {-0.1f, -0.9f, -0.22f}, {-0.1f, -0.9f, -0.5f}};
  const AnimationClip clip = prepare(w);
  const auto l = detectFootContacts(clip, w.skeleton, w.leftFoot);
  const auto r = detectFootContacts(clip, w.skeleton, w.rightFoot);
  EXPECT_EQ(l.size(), 1u) << describe(l);  // the scuff is dropped
  EXPECT_EQ(r.size(), 1u) << describe(r);  // the lift is closed
  EXPECT_FALSE(inContact(l, 0.865f));
  EXPECT_TRUE(inContact(r, 0.71f));

  // With no minimum duration, both show.
  FootContactOptions raw;
  raw.minDuration = 0.0f;
  raw.heightAboveLowest = 0.02f;
  EXPECT_EQ(detectFootContacts(clip, w.skeleton, w.leftFoot, raw).size(), 2u);
  EXPECT_EQ(detectFootContacts(clip, w.skeleton, w.rightFoot, raw).size(), 2u);
}

TEST(FootContacts, AFootThatNeverLiftsIsInContactAllCycle) {
  SyntheticWalk w = makeSyntheticWalk(false);  // in place: the hips stay
  w.clip.tracks[1].translation.times = {0.0f, 1.0f};
  w.clip.tracks[1].translation.values = {{0.1f, -0.9f, 0.0f}, {0.1f, -0.9f, 0.0f}};
  const auto contacts = detectFootContacts(prepare(w), w.skeleton, w.leftFoot);
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_EQ(contacts[0].begin, 0.0f);
  EXPECT_EQ(contacts[0].end, 1.0f);
  for (float p : {0.0f, 0.3f, 0.999f, 1.0f, 7.5f, -0.25f}) EXPECT_TRUE(inContact(contacts, p)) << p;
  EXPECT_EQ(contactWeight(contacts, 0.42f, 0.1f), 1.0f);
}

// ---- per-frame queries ------------------------------------------------------------------

TEST(FootContacts, InContactWrapsPhases) {
  const std::vector<ContactInterval> c = {{0.2f, 0.4f}, {0.8f, 0.1f}};
  EXPECT_TRUE(inContact(c, 0.2f));
  EXPECT_TRUE(inContact(c, 0.3f));
  EXPECT_FALSE(inContact(c, 0.4f));  // half-open
  EXPECT_FALSE(inContact(c, 0.5f));
  EXPECT_TRUE(inContact(c, 0.9f));
  EXPECT_TRUE(inContact(c, 0.05f));
  EXPECT_TRUE(inContact(c, 1.05f));   // the next cycle
  EXPECT_TRUE(inContact(c, -0.15f));  // 0.85
  EXPECT_FALSE(inContact(c, 0.15f));
  EXPECT_FALSE(inContact(c, kNaN));
  EXPECT_FALSE(inContact(c, std::numeric_limits<float>::infinity()));
  EXPECT_FALSE(inContact({}, 0.3f));
}

TEST(FootContacts, ContactWeightRampsSmoothlyOutside) {
  const std::vector<ContactInterval> c = {{0.2f, 0.4f}, {0.9f, 0.05f}};
  const float blend = 0.1f;
  EXPECT_EQ(contactWeight(c, 0.3f, blend), 1.0f);
  EXPECT_EQ(contactWeight(c, 0.4f, blend), 1.0f);
  EXPECT_NEAR(contactWeight(c, 0.45f, blend), 0.5f, 1e-5f);  // half-way down the ramp after the end
  EXPECT_NEAR(contactWeight(c, 0.15f, blend), 0.5f, 1e-5f);  // and before the begin
  EXPECT_EQ(contactWeight(c, 0.6f, blend), 0.0f);
  EXPECT_EQ(contactWeight(c, 0.97f, blend), 1.0f);            // inside the wrapping one
  EXPECT_NEAR(contactWeight(c, 0.1f, blend), 0.5f, 1e-5f);   // after its end, across the loop point
  EXPECT_NEAR(contactWeight(c, 0.85f, blend), 0.5f, 1e-5f);
  // Continuous and monotone on each ramp.
  float previous = contactWeight(c, 0.4f, blend);
  for (float p = 0.4f; p <= 0.55f; p += 0.001f) {
    const float w = contactWeight(c, p, blend);
    EXPECT_LE(w, previous + 1e-6f) << p;
    EXPECT_LE(previous - w, 0.016f) << p;  // slope at most 1.5 / blend
    previous = w;
  }
  // No blend: a step; NaN: 0.
  EXPECT_EQ(contactWeight(c, 0.45f, 0.0f), 0.0f);
  EXPECT_EQ(contactWeight(c, 0.3f, 0.0f), 1.0f);
  EXPECT_EQ(contactWeight(c, kNaN, blend), 0.0f);
  EXPECT_EQ(contactWeight(c, 0.45f, kNaN), 0.0f);
  EXPECT_EQ(contactWeight({}, 0.3f, blend), 0.0f);
}

TEST(FootContacts, SettingsScaleWithTheLeg) {
  const FootContactOptions human;
  const FootContactOptions robot = footContactOptionsForLeg(1.8f);  // twice a human leg
  EXPECT_FLOAT_EQ(robot.heightAboveLowest, 2.0f * human.heightAboveLowest);
  EXPECT_FLOAT_EQ(robot.maxSpeed, 2.0f * human.maxSpeed);
  EXPECT_EQ(robot.minDuration, human.minDuration);  // times do not scale
  for (const float bad : {0.0f, -1.0f, kNaN, std::numeric_limits<float>::infinity()})
    EXPECT_EQ(footContactOptionsForLeg(bad).maxSpeed, human.maxSpeed) << bad;
}
