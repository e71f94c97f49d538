// RobotExpressive's feet (Foot.L/R) and knee poles are IK targets beside its
// root-motion joint (Body), all children of the root `Bone`. A clip played in
// place takes Body's travel and turn out; the feet must lose the same, or they
// stay where the clip put them while the legs go with the body (before the fix
// the feet left the shins by 0.665 m sitting, 0.46 m punching, 1.01 m dying).
// Both ways of playing in place are measured: a clip behavior (always in place)
// and a clip layer with root motion.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "marionette/animation/pose.hpp"
#include "marionette/animation/sampling.hpp"
#include "marionette/behavior/two_bone_ik.hpp"
#include "marionette/scene/scene.hpp"
#include "detached_feet.hpp"
#include "real_rig.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::test;

namespace {

constexpr int kSamples = 240;  // poses per cycle

struct InPlaceGaps {
  float worst = 0.0f;       // largest gap played in place
  float difference = 0.0f;  // largest change of a foot's gap from the clip's at the same clip time
};

// Steps the scene over two cycles of the clip; `clipTime` says where in the clip
// the character is after each step.
template <class ClipTime>
InPlaceGaps measure(Scene& scene, const Character& c, const Clip& clip, const LimbIk legs[2], ClipTime clipTime) {
  const Skeleton& s = c.rig().skeleton();
  std::vector<Transform> authored(s.jointCount());
  InPlaceGaps g;
  for (int k = 0; k < 2 * kSamples; ++k) {
    scene.update(static_cast<double>(clip.duration) / kSamples);
    sampleClip(clip, clipTime(), s.restPose, authored);
    for (int f = 0; f < 2; ++f) {
      const float gap = footGap(s, c.localPose(), legs[f]);
      g.worst = std::max(g.worst, gap);
      g.difference = std::max(g.difference, std::fabs(gap - footGap(s, authored, legs[f])));
    }
  }
  return g;
}

// The clip as a looping posture behavior, at its own speed and at full weight
// from 1 ms on.
InPlaceGaps behaviorGaps(const std::shared_ptr<Rig>& rig, const Clip& clip, const LimbIk legs[2]) {
  Scene scene;
  Character* c = scene.addCharacter("robot", rig);
  BehaviorRequest r;
  r.id = "clip";
  r.kind = BehaviorKind::Clip;
  r.clip = clip.name;
  r.loop = true;
  r.persistent = true;
  r.syncs = {{"start", 0.0}, {"ready", 0.001}, {"end", 100.0}};
  EXPECT_TRUE(c->addBehavior(r).realized) << clip.name;
  scene.update(0.001);
  return measure(scene, *c, clip, legs, [&] { return wrapClipTime(c->time(), clip.duration, WrapMode::Loop); });
}

// The clip on a layer that moves the character by its root motion.
InPlaceGaps layerGaps(const std::shared_ptr<Rig>& rig, const Clip& clip, const LimbIk legs[2]) {
  Scene scene;
  Character* c = scene.addCharacter("robot", rig);
  PlayOptions o;
  o.rootMotion = true;
  EXPECT_TRUE(c->play(0, clip.name, o)) << clip.name;
  return measure(scene, *c, clip, legs, [&] { return wrapClipTime(c->layerTime(0), clip.duration, WrapMode::Loop); });
}

}  // namespace

TEST(ClipBehaviorsOnRealCharacters, RobotFeetStayOnItsLegsInPlace) {
  const std::string file = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(file);
  const RobotWithLegs robot = robotWithDetachedFeet();
  ASSERT_TRUE(robot.rig);
  const auto& rig = robot.rig;
  const LimbIk* legs = robot.legs;
  // The clip's own gap is large where its foot target is out of the leg's reach
  // (Punch's right foot, 0.57 m; both feet in Jump, 0.25 m): each foot's gap is
  // therefore also compared with the clip's at the same clip time.
  for (const char* name : {"Sitting", "Standing", "Punch", "Death", "Dance", "Jump", "WalkJump", "Wave"}) {
    const auto ac = rig->findClip(name);
    ASSERT_TRUE(ac) << "RobotExpressive has no clip " << name;
    ASSERT_GT(ac->clip.duration, 0.0f) << name;
    const float authored = authoredFootGap(rig->skeleton(), ac->clip, legs, kSamples);
    const InPlaceGaps behavior = behaviorGaps(rig, ac->clip, legs);
    const InPlaceGaps layer = layerGaps(rig, ac->clip, legs);
    std::printf("%-9s feet off the shins' ends: clip %.3f m, behavior %.3f m, root-motion layer %.3f m "
                "(each foot's gap at most %.4f / %.4f m off the clip's at the same time)\n",
                name, static_cast<double>(authored), static_cast<double>(behavior.worst),
                static_cast<double>(layer.worst), static_cast<double>(behavior.difference),
                static_cast<double>(layer.difference));
    EXPECT_LE(behavior.worst, authored + 0.01f) << name << " as a behavior";
    EXPECT_LE(layer.worst, authored + 0.01f) << name << " on a root-motion layer";
    // Between keys the carried feet follow the body within 0.1 mm (root_motion.cpp).
    EXPECT_LE(behavior.difference, 0.002f) << name << " as a behavior";
    EXPECT_LE(layer.difference, 0.002f) << name << " on a root-motion layer";
  }
}
