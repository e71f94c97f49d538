// Clips made in place (AnimationClip::inPlaceRoot): what the clip places beside
// the root-motion joint (detached IK feet, poles, props) loses the same travel
// and turn as the root, so it keeps its place relative to the body. Synthetic
// skeletons: Y-up with a plain root transform, and Z-up under a root transform
// that scales by 100 and turns the file to Y-up (as RobotExpressive's does).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "marionette/animation/clip_optimizer.hpp"
#include "marionette/animation/pose.hpp"
#include "marionette/animation/sampling.hpp"
#include "marionette/rig/rig.hpp"

using namespace marionette;

namespace {

enum Joint { kArmature, kBody, kLeg, kFoot, kPole, kIkRoot, kIkHand, kProp };

// armature (root) -> body (travels and turns) -> leg
//                 -> foot (translation keys at fewer times than the body's)
//                 -> pole (no track: held at rest by the clip)
//                 -> ik root (no track) -> ik hand (translation keys)
// prop (a second root, translation keys)
struct Synthetic {
  Skeleton skeleton;
  Clip clip;
};

Synthetic makeSynthetic(const glm::mat4& rootTransform) {
  Synthetic s;
  Skeleton& k = s.skeleton;
  k.rootTransform = rootTransform;
  const glm::mat4 toLocal = glm::inverse(rootTransform);
  // Places and directions given in the model frame (Y-up), stored in the file's.
  auto at = [&](float x, float y, float z) { return glm::vec3(toLocal * glm::vec4(x, y, z, 1.0f)); };
  auto along = [&](float x, float y, float z) { return glm::vec3(toLocal * glm::vec4(x, y, z, 0.0f)); };
  const glm::quat frame = decompose(rootTransform).rotation;
  auto yaw = [&](float degrees) {
    return glm::inverse(frame) * glm::angleAxis(glm::radians(degrees), glm::vec3(0, 1, 0)) * frame;
  };
  auto rest = [](const glm::vec3& t) {
    Transform r;
    r.translation = t;
    return r;
  };
  k.addJoint("armature", -1, Transform{});
  k.addJoint("body", kArmature, rest(at(0.0f, 1.0f, 0.0f)));
  k.addJoint("leg", kBody, rest(along(0.1f, -0.5f, 0.0f)));
  k.addJoint("foot", kArmature, rest(at(0.1f, 0.05f, 0.2f)));
  k.addJoint("pole", kArmature, rest(at(0.1f, 0.5f, 0.5f)));
  k.addJoint("ikRoot", kArmature, Transform{});
  k.addJoint("ikHand", kIkRoot, rest(at(0.3f, 1.2f, 0.3f)));
  k.addJoint("prop", -1, rest(at(1.0f, 0.0f, 0.0f)));

  Clip& c = s.clip;
  c.name = "travel";
  JointTrack body;
  body.joint = kBody;
  body.translation.times = {0.0f, 0.5f, 1.0f};
  body.translation.values = {at(0.0f, 1.0f, 0.0f), at(0.3f, 1.02f, 0.5f), at(0.6f, 1.0f, 1.2f)};
  body.rotation.times = {0.0f, 0.5f, 1.0f};
  body.rotation.values = {yaw(0.0f), yaw(20.0f), yaw(45.0f)};
  JointTrack leg;
  leg.joint = kLeg;
  leg.rotation.times = {0.0f, 1.0f};
  leg.rotation.values = {glm::quat(1, 0, 0, 0), glm::angleAxis(0.5f, glm::vec3(1, 0, 0))};
  JointTrack foot;
  foot.joint = kFoot;
  foot.translation.times = {0.0f, 1.0f};
  foot.translation.values = {at(0.1f, 0.05f, 0.2f), at(0.4f, 0.1f, 0.9f)};
  JointTrack hand;
  hand.joint = kIkHand;
  hand.translation.times = {0.0f, 1.0f};
  hand.translation.values = {along(0.3f, 1.2f, 0.3f), along(0.5f, 1.4f, 1.0f)};
  JointTrack prop;
  prop.joint = kProp;
  prop.translation.times = {0.0f, 1.0f};
  prop.translation.values = {at(1.0f, 0.0f, 0.0f), at(1.0f, 0.5f, 1.0f)};
  c.tracks = {body, leg, foot, hand, prop};
  c.updateDuration();
  return s;
}

struct Frames {
  std::vector<glm::mat4> authored, inPlace;
};

Frames sampleBoth(const Skeleton& k, const AnimationClip& ac, float t) {
  std::vector<Transform> pose(k.jointCount());
  Frames f{std::vector<glm::mat4>(k.jointCount()), std::vector<glm::mat4>(k.jointCount())};
  sampleClip(ac.clip, t, k.restPose, pose);
  localToModel(k, pose, f.authored);
  sampleClipTracks(ac.inPlaceRoot, t, pose);
  localToModel(k, pose, f.inPlace);
  return f;
}

// The joint's model transform seen from the body, without the file's scale.
glm::mat4 fromBody(const std::vector<glm::mat4>& model, int joint) {
  return glm::inverse(model[kBody]) * model[static_cast<std::size_t>(joint)];
}

const glm::mat4 kMetresYUp(1.0f);
const glm::mat4 kScaledZUp =
    glm::scale(glm::mat4(1.0f), glm::vec3(100.0f)) * glm::mat4_cast(glm::angleAxis(-1.5707963f, glm::vec3(1, 0, 0)));

}  // namespace

TEST(InPlaceClip, JointsBesideTheRootAreCarriedWithIt) {
  for (const glm::mat4& rootTransform : {kMetresYUp, kScaledZUp}) {
    SCOPED_TRACE(rootTransform == kMetresYUp ? "Y-up" : "Z-up, scaled by 100");
    const Synthetic s = makeSynthetic(rootTransform);
    ASSERT_EQ(s.skeleton.validate(), "");
    ASSERT_EQ(s.clip.validate(s.skeleton.jointCount()), "");
    const auto ac = makeAnimationClip(s.clip, s.skeleton);
    ASSERT_EQ(ac->rootMotion.joint, kBody);
    // The root's siblings, with or without tracks, and the other root; not the
    // armature (the root's parent), the leg (carried by the body) nor the hand
    // (carried by the ik root).
    EXPECT_EQ(ac->rootMotion.carried, (std::vector<int>{kFoot, kPole, kIkRoot, kProp}));
    std::vector<int> tracked;
    for (const JointTrack& t : ac->inPlaceRoot.tracks) tracked.push_back(t.joint);
    EXPECT_EQ(tracked, (std::vector<int>{kBody, kFoot, kPole, kIkRoot, kProp}));  // in joint order
    EXPECT_EQ(ac->clip.tracks.size(), s.clip.tracks.size());  // the clip itself is as authored

    const float unit = glm::length(glm::vec3(rootTransform[0]));  // metres per file unit
    const glm::quat upright = decompose(rootTransform).rotation;    // the body's heading at rest
    float worstPlace = 0.0f, worstTurn = 0.0f, worstRoot = 0.0f;
    for (int i = 0; i <= 200; ++i) {
      const float t = static_cast<float>(i) / 200.0f;
      const Frames f = sampleBoth(s.skeleton, *ac, t);
      // The body stays over its first key and keeps its heading.
      const glm::vec3 body(f.inPlace[kBody][3]);
      worstRoot = std::max({worstRoot, std::fabs(body.x), std::fabs(body.z)});
      worstTurn = std::max(worstTurn, rotationAngle(decompose(f.inPlace[kBody]).rotation, upright));
      // Everything keeps its place relative to the body (in metres).
      for (int j : {kLeg, kFoot, kPole, kIkRoot, kIkHand, kProp}) {
        const glm::mat4 a = fromBody(f.authored, j), b = fromBody(f.inPlace, j);
        worstPlace = std::max(worstPlace, glm::length(glm::vec3(a[3]) - glm::vec3(b[3])) * unit);
        worstTurn = std::max(worstTurn, rotationAngle(decompose(a).rotation, decompose(b).rotation));
      }
    }
    EXPECT_LT(worstRoot, 1e-5f);
    EXPECT_LT(worstPlace, 2e-4f);  // the carried tracks' tolerance, 0.1 mm, and rounding
    EXPECT_LT(worstTurn, 1e-3f);
  }
}

// A root that only bobs up and down is in place already: nothing is carried and
// the in-place clip is the root's track alone.
TEST(InPlaceClip, NothingIsCarriedWhenTheRootNeitherTravelsNorTurns) {
  Synthetic s = makeSynthetic(kMetresYUp);
  JointTrack& body = s.clip.tracks.front();
  ASSERT_EQ(body.joint, kBody);
  body.translation.values = {glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(0.0f, 1.1f, 0.0f), glm::vec3(0.0f, 1.0f, 0.0f)};
  body.rotation = {};
  const auto ac = makeAnimationClip(s.clip, s.skeleton);
  ASSERT_EQ(ac->rootMotion.joint, kBody);
  EXPECT_TRUE(ac->rootMotion.carried.empty());
  ASSERT_EQ(ac->inPlaceRoot.tracks.size(), 1u);
  EXPECT_EQ(ac->inPlaceRoot.tracks.front().joint, kBody);
}

// A joint held at rest while the root travels and turns follows a curve; the
// carried track gets keys between the root's wherever a straight line would
// stray more than 0.1 mm (here: one 0.9 m, 60-degree interval).
TEST(InPlaceClip, CarriedTracksFollowTheCurveBetweenTheRootsKeys) {
  Synthetic s = makeSynthetic(kMetresYUp);
  JointTrack& body = s.clip.tracks.front();
  body.translation.times = {0.0f, 1.0f};
  body.translation.values = {glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(0.0f, 1.0f, 0.9f)};
  body.rotation.times = {0.0f, 1.0f};
  body.rotation.values = {glm::quat(1, 0, 0, 0), glm::angleAxis(glm::radians(60.0f), glm::vec3(0, 1, 0))};
  const auto ac = makeAnimationClip(s.clip, s.skeleton);
  const auto pole = std::find_if(ac->inPlaceRoot.tracks.begin(), ac->inPlaceRoot.tracks.end(),
                                 [](const JointTrack& t) { return t.joint == kPole; });
  ASSERT_NE(pole, ac->inPlaceRoot.tracks.end());
  EXPECT_GT(pole->translation.times.size(), 2u);
  EXPECT_FALSE(pole->rotation.empty());  // the root turns, so the pole turns with it
  float worst = 0.0f;
  for (int i = 0; i <= 400; ++i) {
    const Frames f = sampleBoth(s.skeleton, *ac, static_cast<float>(i) / 400.0f);
    const glm::vec3 authored(fromBody(f.authored, kPole)[3]), inPlace(fromBody(f.inPlace, kPole)[3]);
    worst = std::max(worst, glm::length(authored - inPlace));
  }
  EXPECT_LT(worst, 2e-4f);
}
