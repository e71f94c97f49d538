// PoseHold: the pose the renderer draws with and how opaque (marionette_ar/pose_hold.hpp).
#include <gtest/gtest.h>

#include "marionette_ar/pose_hold.hpp"

namespace {

using marionette::ar::PoseHold;
using marionette::ar::PoseQuality;

const glm::dmat4 kPose(1.0);

TEST(PoseHold, TrackingIsOpaqueLimitedFadesByConfidenceWithoutSnapping) {
  PoseHold hold(1.0, true);
  EXPECT_EQ(hold.opacity(0.0), 0.0f);  // nothing to draw with yet
  hold.update(true, kPose, 0.0);
  EXPECT_EQ(hold.opacity(0.0), 1.0f);  // the first pose shows at once
  // LIMITED with a confident pose, then an uncertain one: the target opacity follows the
  // confidence, and each frame moves only part of the way there.
  EXPECT_FLOAT_EQ(PoseHold::targetOpacity({true, 0, 0}), PoseHold::kLimitedHighest);
  EXPECT_NEAR(PoseHold::targetOpacity({true, 0.01, 0.1}), 0.35f + 0.45f * (1 - 3 * 0.01f / 0.05f), 1e-6);
  EXPECT_FLOAT_EQ(PoseHold::targetOpacity({true, 0.5, 10}), PoseHold::kLimitedLowest);
  EXPECT_FLOAT_EQ(PoseHold::targetOpacity({false, 0.5, 10}), 1.0f);
  const PoseQuality uncertain{true, 0.015, 0.5};
  float last = hold.opacity(0.0);
  for (int i = 1; i <= 30; ++i) {
    hold.update(true, kPose, i / 30.0, uncertain);
    const float now = hold.opacity(i / 30.0);
    EXPECT_LT(now, last) << i;                 // down, monotonically
    EXPECT_GT(last - now, 0.0f);
    EXPECT_LT(last - now, 0.3f) << i;          // never a snap: under 30 % of the way per frame at 30 fps
    last = now;
  }
  EXPECT_NEAR(last, PoseHold::targetOpacity(uncertain), 0.01f);  // there after a second
  // Back to TRACKING: up again, eased.
  hold.update(true, kPose, 31 / 30.0, {});
  EXPECT_GT(hold.opacity(31 / 30.0), last);
  EXPECT_LT(hold.opacity(31 / 30.0), 1.0f);
}

TEST(PoseHold, LostFadesOutOverTheHoldTime) {
  PoseHold hold(0.5, true);
  hold.update(true, kPose, 0.0);
  hold.update(false, kPose, 0.1);
  EXPECT_TRUE(hold.charactersVisible(0.1));
  EXPECT_NEAR(hold.opacity(0.1), 1.0f * (1 - 0.1 / 0.5), 1e-6);
  EXPECT_NEAR(hold.opacity(0.35), 1.0f * (1 - 0.35 / 0.5), 1e-6);
  EXPECT_EQ(hold.opacity(0.6), 0.0f);
  EXPECT_FALSE(hold.charactersVisible(0.6));
  // Kept when lost: no lower than LIMITED's lowest.
  PoseHold kept(0.5, false);
  kept.update(true, kPose, 0.0);
  kept.update(false, kPose, 0.1);
  EXPECT_TRUE(kept.charactersVisible(5.0));
  EXPECT_EQ(kept.opacity(5.0), PoseHold::kLimitedLowest);
  // Found again: eased back up from where the fade was.
  hold.update(true, kPose, 0.3);
  EXPECT_GT(hold.opacity(0.3), 0.0f);
  EXPECT_LT(hold.opacity(0.3), 1.0f);
}

}  // namespace
