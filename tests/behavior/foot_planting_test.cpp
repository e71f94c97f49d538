// Foot planting on a hand-made pair of legs (thigh 0.4 m, shin 0.6 m: unequal,
// as most legs are), driven frame by frame through FootPlanter: the knee keeps
// its side while a planted leg straightens, and a detached foot held off the
// shin (RobotExpressive's) neither pulls the leg when it plants nor lets it jump
// back when the release fade ends. Both were seen in `marionette run --trace`
// of the walk-look-nod-smile scene at 240 fps (100 rad/s and 49 rad/s thigh
// turns in one frame; tests/cli/trace_measurements_test.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "marionette/animation/pose.hpp"
#include "marionette/behavior/foot_planting.hpp"

using namespace marionette;

namespace {

constexpr float kDeg = 3.14159265f / 180.0f;

struct Legs {
  Skeleton skeleton;
  RigJoints joints;
  int hips = 0, leftThigh = 1, leftShin = 2, rightThigh = 4, rightShin = 5;
  int leftFoot = 3, rightFoot = 6;  // the legs' end joints: the shins' children, or detached ones under the hips
  bool detached = false;
};

// Hips 1 m up, facing +Z; the knees bend forward about +X.
Legs makeLegs(bool detachedFeet) {
  Legs l;
  auto add = [&](const char* name, int parent, glm::vec3 offset) {
    Transform t;
    t.translation = offset;
    return l.skeleton.addJoint(name, parent, t);
  };
  add("Hips", -1, {0.0f, 1.0f, 0.0f});
  add("LeftUpLeg", 0, {0.1f, 0.0f, 0.0f});
  add("LeftLeg", 1, {0.0f, -0.4f, 0.0f});
  add("LeftFoot", 2, {0.0f, -0.6f, 0.0f});
  add("RightUpLeg", 0, {-0.1f, 0.0f, 0.0f});
  add("RightLeg", 4, {0.0f, -0.4f, 0.0f});
  add("RightFoot", 5, {0.0f, -0.6f, 0.0f});
  l.detached = detachedFeet;
  if (detachedFeet) {  // IK targets under the hips, at the shins' ends in the rest pose
    l.leftFoot = add("LeftFootIK", 0, {0.1f, -1.0f, 0.0f});
    l.rightFoot = add("RightFootIK", 0, {-0.1f, -1.0f, 0.0f});
  }
  l.joints.leftLeg = {l.leftThigh, l.leftShin, l.leftFoot};
  l.joints.rightLeg = {l.rightThigh, l.rightShin, l.rightFoot};
  return l;
}

glm::vec3 at(const Legs& l, const std::vector<Transform>& pose, int joint) {
  return glm::vec3(modelMatrixOf(l.skeleton, pose, joint)[3]);
}

glm::quat modelRotation(const Legs& l, const std::vector<Transform>& pose, int joint) {
  return glm::normalize(glm::quat_cast(glm::mat3(modelMatrixOf(l.skeleton, pose, joint))));
}

float angleBetween(const glm::quat& a, const glm::quat& b) {
  const glm::quat d = glm::inverse(a) * b;
  return 2.0f * std::atan2(glm::length(glm::vec3(d.x, d.y, d.z)), std::fabs(d.w));
}

// The animated pose: the left thigh turned back by `thigh` and its knee bent by
// `knee` (radians), the hips at the height that puts the left shin's end on the
// ground (y = 0); the right leg lifted (thigh 40 degrees forward, knee 100).
// A detached left foot sits `footOffset` from the left shin's end.
std::vector<Transform> animate(const Legs& l, float thigh, float knee, glm::vec3 footOffset = glm::vec3(0.0f)) {
  std::vector<Transform> pose = l.skeleton.restPose;
  const glm::vec3 x(1.0f, 0.0f, 0.0f);
  pose[static_cast<std::size_t>(l.leftThigh)].rotation = glm::angleAxis(thigh, x);
  pose[static_cast<std::size_t>(l.leftShin)].rotation = glm::angleAxis(knee, x);
  pose[static_cast<std::size_t>(l.rightThigh)].rotation = glm::angleAxis(-40.0f * kDeg, x);
  pose[static_cast<std::size_t>(l.rightShin)].rotation = glm::angleAxis(100.0f * kDeg, x);
  const glm::vec3 shinEnd = glm::vec3(modelMatrixOf(l.skeleton, pose, l.leftShin) * glm::vec4(0.0f, -0.6f, 0.0f, 1.0f));
  pose[static_cast<std::size_t>(l.hips)].translation.y -= shinEnd.y;
  if (l.detached) {  // place the IK targets relative to the hips
    const glm::vec3 hips = pose[static_cast<std::size_t>(l.hips)].translation;
    pose[static_cast<std::size_t>(l.leftFoot)].translation = shinEnd - glm::vec3(0.0f, shinEnd.y, 0.0f) - hips + footOffset;
    const glm::vec3 rightEnd =
        glm::vec3(modelMatrixOf(l.skeleton, pose, l.rightShin) * glm::vec4(0.0f, -0.6f, 0.0f, 1.0f));
    pose[static_cast<std::size_t>(l.rightFoot)].translation = rightEnd - hips;
  }
  return pose;
}

glm::mat4 placedAt(glm::vec3 p) {
  Transform t;
  t.translation = p;
  return t.matrix();
}

}  // namespace

// The leg planted, the body carried on over it so that the lock sits up to 15 cm
// from where the clip has the foot (a turn, a speed change), while the clip
// straightens the leg to 0.5 degrees: the knee stays in front and the thigh
// turns smoothly, whichever way the lock is off. A pole taken from the animated
// knee and ankle flipped the knee across the leg here. The lock is held however
// far beyond the straight leg's reach it gets (maxOverreach off), so that the
// knee is seen over the whole straightening (by default the foot would step away
// at frame 118 of the first direction, the lock 5 cm beyond the leg's length).
TEST(FootPlanting, KneeKeepsItsSideWhileAPlantedLegStraightens) {
  const Legs legs = makeLegs(false);
  const float floor[2] = {0.0f, 0.0f};
  const float dt = 1.0f / 240.0f;
  const int frames = 240;
  FootPlantSettings holdAlways;
  holdAlways.maxOverreach = INFINITY;
  for (int direction = 0; direction < 8; ++direction) {
    const float a = static_cast<float>(direction) * 45.0f * kDeg;
    const glm::vec3 mismatch = 0.15f * glm::vec3(std::sin(a), 0.0f, std::cos(a));
    FootPlanter planter(legs.skeleton, legs.joints);
    ASSERT_TRUE(planter.usable());
    glm::vec3 lockWorld(0.0f);
    glm::quat previousThigh(1.0f, 0.0f, 0.0f, 0.0f);
    float fastest = 0.0f, leastForward = 1.0f;
    for (int k = 0; k < frames; ++k) {
      const float s = static_cast<float>(k) / static_cast<float>(frames - 1);
      std::vector<Transform> pose = animate(legs, 20.0f * kDeg * s, (30.0f - 29.5f * s) * kDeg);
      const glm::vec3 animated = at(legs, pose, legs.leftFoot);
      if (k == 0) lockWorld = animated;  // placed at the origin on frame 0, where the foot locks
      // Place the body so that the lock is at animated + mismatch (ramped in over the first third).
      const glm::vec3 off = mismatch * std::min(1.0f, 3.0f * s);
      const glm::vec3 placement = lockWorld - animated - off;
      planter.apply(legs.skeleton, pose, placedAt({placement.x, 0.0f, placement.z}), floor, 1.0f, dt, holdAlways);
      ASSERT_TRUE(planter.planted(0)) << "frame " << k;
      ASSERT_FALSE(planter.planted(1)) << "frame " << k;
      const glm::vec3 hip = at(legs, pose, legs.leftThigh), knee = at(legs, pose, legs.leftShin);
      const glm::vec3 foot = at(legs, pose, legs.leftFoot);  // where the lock is, or as near as the leg reaches
      // The knee's offset across the hip-ankle line, along the character's forward (+Z).
      const glm::vec3 line = glm::normalize(foot - hip);
      const glm::vec3 across = (knee - hip) - line * glm::dot(knee - hip, line);
      leastForward = std::min(leastForward, glm::dot(glm::normalize(across), glm::vec3(0.0f, 0.0f, 1.0f)));
      const glm::quat thigh = modelRotation(legs, pose, legs.leftThigh);
      if (k > 0) fastest = std::max(fastest, angleBetween(previousThigh, thigh) / dt);
      previousThigh = thigh;
    }
    // The clip turns the thigh at 0.35 rad/s, the lock ramping in adds up to about 1 rad/s; a flip was 170.
    EXPECT_LT(fastest, 5.0f) << "direction " << direction << " (mismatch " << mismatch.x << ", " << mismatch.z << ")";
    EXPECT_GT(leastForward, 0.5f) << "direction " << direction;
  }
}

// RobotExpressive's feet are IK targets that its poses hold up to 5 cm off the
// shins' ends (19 cm while the gait blends over the idle). Planting moves the leg by the correction only: on the frame the
// foot locks (no correction yet) the pose stays the clip's; while locked the
// foot stays put; when it lifts, the release fades to the clip's pose without a
// jump at the end (the leg used to be pulled onto the foot while planted and
// dropped back to the clip's pose in one frame when the fade ended).
TEST(FootPlanting, DetachedFootOffTheShinMovesTheLegOnlyByTheCorrection) {
  const Legs legs = makeLegs(true);
  const float floor[2] = {0.0f, 0.0f};
  const float dt = 1.0f / 240.0f;
  const float thigh = -20.0f * kDeg, knee = 60.0f * kDeg;  // 13 cm short of straight: the lock stays in reach
  FootPlanter planter(legs.skeleton, legs.joints);
  ASSERT_TRUE(planter.usable());
  glm::vec3 lockWorld(0.0f);
  glm::quat previousThigh(1.0f, 0.0f, 0.0f, 0.0f);
  float fastest = 0.0f;
  for (int k = 0; k < 120; ++k) {
    // On the ground 8 cm ahead of the shin for 60 frames, the body moving on at
    // 0.4 m/s (10 cm of correction); then lifted 20 cm above the shin's end.
    const bool lifted = k >= 60;
    const std::vector<Transform> animated =
        animate(legs, thigh, knee, lifted ? glm::vec3(0.0f, 0.2f, 0.08f) : glm::vec3(0.0f, 0.0f, 0.08f));
    std::vector<Transform> pose = animated;
    const glm::vec3 body(0.0f, 0.0f, 0.4f * dt * static_cast<float>(std::min(k, 60)));
    planter.apply(legs.skeleton, pose, placedAt(body), floor, 1.0f, dt, {});
    const glm::vec3 foot = at(legs, pose, legs.leftFoot);
    if (k == 0) {
      ASSERT_TRUE(planter.planted(0));
      lockWorld = foot + body;
      for (int j : {legs.leftThigh, legs.leftShin})
        EXPECT_LT(angleBetween(pose[static_cast<std::size_t>(j)].rotation, animated[static_cast<std::size_t>(j)].rotation), 1e-3f)
            << "joint " << j << ": planting with no correction yet moved the leg";
      EXPECT_LT(glm::length(foot - at(legs, animated, legs.leftFoot)), 1e-5f);
    }
    if (!lifted) {
      EXPECT_TRUE(planter.planted(0)) << "frame " << k;
      EXPECT_LT(glm::length(glm::vec2(foot.x + body.x - lockWorld.x, foot.z + body.z - lockWorld.z)), 1e-3f)
          << "frame " << k << ": the planted foot moved";
    }
    if (k >= 60 + 40) {  // released 0.12 s after lift-off (29 frames): the clip's pose, untouched
      EXPECT_FALSE(planter.active());
      for (int j : {legs.leftThigh, legs.leftShin, legs.leftFoot})
        EXPECT_EQ(pose[static_cast<std::size_t>(j)].rotation, animated[static_cast<std::size_t>(j)].rotation);
      EXPECT_EQ(foot, at(legs, animated, legs.leftFoot));
    }
    const glm::quat q = modelRotation(legs, pose, legs.leftThigh);
    if (k > 0) fastest = std::max(fastest, angleBetween(previousThigh, q) / dt);
    previousThigh = q;
  }
  // 10 cm of correction fading out in 0.12 s on a 1 m leg: 1.8 rad/s; the jump was 120.
  EXPECT_LT(fastest, 3.0f);
}

// The body walks on at 1 m/s while the clip keeps the left foot on the ground
// under it (as the gait blending in over an idle stance, or out of it at a stop,
// does): the lock falls behind out of the leg's reach. A planted foot stays
// near its lock (short of it by the soft reach at most); once the lock is 5 cm
// beyond the leg's length (maxOverreach), the foot steps (lifts and comes down
// where the clip has it, in stepSeconds) and plants there, again and again, the
// thigh turning smoothly throughout. Before, the lock was held for ever: the
// straight leg dragged the foot after the body, up off the ground.
TEST(FootPlanting, AFootLeftOutOfReachStepsToTheAnimation) {
  const Legs legs = makeLegs(false);
  const float floor[2] = {0.0f, 0.0f};
  const float dt = 1.0f / 60.0f;
  const FootPlantSettings settings;
  FootPlanter planter(legs.skeleton, legs.joints);
  ASSERT_TRUE(planter.usable());
  glm::vec3 lockWorld(0.0f);
  bool wasPlanted = false, wasStepping = false;
  glm::vec3 previousFoot(0.0f);
  int stepFrames = 0, longestStep = 0;
  float worstMiss = 0.0f, highestStep = 0.0f, worstLanding = 0.0f, fastest = 0.0f;
  glm::quat previousThigh(1.0f, 0.0f, 0.0f, 0.0f);
  for (int k = 0; k < 180; ++k) {
    std::vector<Transform> pose = animate(legs, 0.0f, 30.0f * kDeg);
    const glm::vec3 animated = at(legs, pose, legs.leftFoot);
    const glm::vec3 body(0.0f, 0.0f, 1.0f * dt * static_cast<float>(k));
    planter.apply(legs.skeleton, pose, placedAt(body), floor, 1.0f, dt, settings);
    const glm::vec3 foot = at(legs, pose, legs.leftFoot) + body;  // world
    const bool planted = planter.planted(0), stepping = planter.stepping(0);
    ASSERT_FALSE(planted && stepping) << "frame " << k;
    ASSERT_TRUE(planted || stepping) << "frame " << k << ": the foot is on the ground in the clip";
    if (planted && !wasPlanted) {
      lockWorld = foot;
      // It comes down on the place it plants on, not sliding in.
      if (wasStepping)
        worstLanding = std::max(worstLanding, std::hypot(foot.x - previousFoot.x, foot.z - previousFoot.z));
    }
    if (planted) worstMiss = std::max(worstMiss, std::hypot(foot.x - lockWorld.x, foot.z - lockWorld.z));
    if (stepping) {
      ++stepFrames;
      longestStep = std::max(longestStep, stepFrames);
      highestStep = std::max(highestStep, foot.y - animated.y);
    } else {
      stepFrames = 0;
    }
    const glm::quat thigh = modelRotation(legs, pose, legs.leftThigh);
    if (k > 0) fastest = std::max(fastest, angleBetween(previousThigh, thigh) / dt);
    previousThigh = thigh;
    wasPlanted = planted;
    wasStepping = stepping;
    previousFoot = foot;
  }
  std::printf("%d steps in 3 s at 1 m/s; planted feet within %.3f m of their locks; steps up to %d frames, %.3f m "
              "high, moving %.4f m on the landing frame; thigh at most %.2f rad/s\n",
              planter.steps(), static_cast<double>(worstMiss), longestStep, static_cast<double>(highestStep),
              static_cast<double>(worstLanding), static_cast<double>(fastest));
  EXPECT_GE(planter.steps(), 3);  // the reach is about 0.45 m ahead of the lock at 1 m/s
  // A lock at most maxOverreach beyond the 1 m leg, where the soft reach (5 % of
  // the leg) leaves the foot 5.7 cm short of it (measured: 2.5 cm across the ground).
  EXPECT_LE(worstMiss, 0.057f);
  EXPECT_LE(longestStep, static_cast<int>(std::ceil(settings.stepSeconds / dt)) + 1);
  EXPECT_GT(highestStep, 0.05f);  // up off the ground while it moves
  EXPECT_LT(worstLanding, 0.5f * dt);  // slower than 0.5 m/s, the skating speed, as it plants
  EXPECT_LT(fastest, 20.0f);
}
