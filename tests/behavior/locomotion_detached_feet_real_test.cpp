// RobotExpressive's feet are IK targets under the root, not children of its
// shins; its foot meshes hang from them. Locomotion must keep them on the legs
// as the clips do: the gait used to play its in-place Walking and Running with
// the body's sway and hip turn taken out (root motion made in place although
// the clips do not travel), which moved the legs and not the feet.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "marionette/animation/pose.hpp"
#include "marionette/animation/sampling.hpp"
#include "marionette/behavior/two_bone_ik.hpp"
#include "marionette/scene/scene.hpp"
#include "detached_feet.hpp"
#include "real_rig.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::test;

TEST(LocomotionOnRealCharacters, RobotFeetStayOnItsLegsAsInItsClips) {
  const std::string file = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(file);
  const RobotWithLegs robot = robotWithDetachedFeet();
  ASSERT_TRUE(robot.rig);
  const auto& rig = robot.rig;
  const LimbIk* legs = robot.legs;
  float authored = 0.0f;
  for (const char* clip : {"Walking", "Running", "Idle"})
    authored = std::max(authored, authoredFootGap(rig->skeleton(), rig->findClip(clip)->clip, legs, 480));

  // 5 m walking; 20 m running (5 m is too short to get above the walk's speed at 2 m/s^2).
  for (const auto& [manner, target] : {std::pair{"WALK", glm::vec2(3, 4)}, std::pair{"RUN", glm::vec2(12, 16)}}) {
    Scene scene;
    Character* c = scene.addCharacter("robot", rig);
    c->play(0, "Idle");
    BehaviorRequest r;
    r.id = "walk";
    r.kind = BehaviorKind::Locomotion;
    r.syncs = {{"start", 0.0}, {"end", 5.0}};
    LocomotionParameters p;
    p.waypoints = {target};
    p.manner = std::string(manner) == "RUN" ? LocomotionManner::Run : LocomotionManner::Walk;
    p.facing = glm::radians(90.0f);
    r.parameters = std::move(p);
    ASSERT_TRUE(c->addBehavior(r).realized);
    // One clip at full weight, and while the gait blends over the idle or walk and run blend.
    float worst = 0.0f, blending = 0.0f, runWeight = 0.0f;
    for (int frame = 0; frame < 12 * 60; ++frame) {
      scene.update(1.0 / 60.0);
      const auto model = c->transformBuffer().modelMatrices();
      const float gap = std::max(footGap(model, legs[0]), footGap(model, legs[1]));
      const float run = c->locomotion()->runWeight();
      float& into = c->locomotion()->weight() >= 0.99f && (run == 0.0f || run == 1.0f) ? worst : blending;
      into = std::max(into, gap);
      runWeight = std::max(runWeight, run);
    }
    EXPECT_EQ(c->locomotionStatus("walk").state, LocomotionStatus::State::Done) << manner;
    std::printf("%s: feet at most %.3f m off the legs' ends on one clip, %.3f m while blending (run weight up to %.2f); "
                "the clips: %.3f m\n",
                manner, static_cast<double>(worst), static_cast<double>(blending), static_cast<double>(runWeight),
                static_cast<double>(authored));
    if (std::string(manner) == "RUN") {
      EXPECT_EQ(runWeight, 1.0f);
    }
    EXPECT_LT(worst, authored + 0.01f) << manner;
    // Blending two poses interpolates the feet's places but the legs' rotations,
    // which disagree by up to 19 cm here: a known limit, bounded so that it is seen
    // (was 23 cm with the in-place root).
    EXPECT_LT(blending, 0.2f) << manner;
  }
}
