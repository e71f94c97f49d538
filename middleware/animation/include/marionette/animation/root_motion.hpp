// Root motion: the horizontal travel and the turn (yaw about +Y) of a
// locomotion clip, taken out of the clip so that it plays in place and can
// drive the character's world transform instead.
#pragma once
#include <vector>

#include "marionette/animation/clip.hpp"
#include "marionette/animation/sampling.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette {

struct RootMotion {
  int joint = -1;                 // the root joint whose motion was extracted (e.g. hips)
  std::vector<float> times;       // keys of the root's translation/rotation tracks (union)
  std::vector<glm::vec3> offset;  // model-space horizontal offset from the first key (y = 0)
  std::vector<float> yaw;         // model-space yaw from the first key, radians, unwrapped
  float duration = 0.0f;
  // Joints beside the root that the motion was also taken out of (see
  // extractRootMotion), in skeleton order; empty when the root neither travels nor turns.
  std::vector<int> carried;

  [[nodiscard]] bool empty() const noexcept { return times.empty(); }
  // Offset and yaw at clip-local time t (linear between keys, clamped at the ends).
  void evaluate(float t, glm::vec3& outOffset, float& outYaw) const noexcept;
  // Motion between scene times t0 <= t1 of a clip played with `mode`, counting
  // whole loops: `delta` is expressed in the root's heading frame at t0 (so the
  // caller rotates it by the character's current heading), `turn` in radians.
  void between(double t0, double t1, WrapMode mode, glm::vec3& delta, float& turn) const noexcept;
};

// Takes the horizontal translation (x, z in model space) and yaw of `rootJoint`
// out of `clip` (the clip then stays over its first key's position and heading)
// and returns them. `rootJoint` < 0 picks the translated joint with the most
// descendants (pickRootMotionJoint). Works for roots under a static parent chain
// (rest pose of the ancestors).
//
// Playing in place views the whole clip from a frame that follows the root. The
// root's descendants come along by themselves; what the clip poses beside the
// root, in the frame the root travels in, must lose the same motion, or it stays
// where the travel took the body from (RobotExpressive's feet ended 0.665 m off
// its shins sitting). So are carried: every joint whose parent is one of the
// root's ancestors, or that is a root of the skeleton, other than the root and
// its ancestors; that is the root's siblings and its ancestors' siblings, with
// their descendants. These are IK targets and props (RobotExpressive's
// Foot.L/R and PoleTarget.L/R beside Body), carried whether the clip keys them
// or holds them at rest (its Sitting has no foot track). Each keeps its model
// transform relative to the root at every time: its translation (and, when the
// root turns, its rotation) becomes a linear track with keys at its own and the
// root's times, and between them wherever a straight line would stray more than
// 0.1 mm (1 mrad) from the body; a track is added where the clip had none. They
// are listed in RootMotion::carried; none when the root neither travels nor turns.
[[nodiscard]] RootMotion extractRootMotion(Clip& clip, const Skeleton& skeleton, int rootJoint = -1);

// The joint whose translation is the character's travel: of the joints the clip
// translates, the one with the most descendants; -1 if none.
[[nodiscard]] int pickRootMotionJoint(const Clip& clip, const Skeleton& skeleton);

// Yaw (rotation about +Y, radians) of a rotation, by swing-twist decomposition.
[[nodiscard]] float yawOf(const glm::quat& q) noexcept;

}  // namespace marionette
