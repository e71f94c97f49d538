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
[[nodiscard]] RootMotion extractRootMotion(Clip& clip, const Skeleton& skeleton, int rootJoint = -1);

// The joint whose translation is the character's travel: of the joints the clip
// translates, the one with the most descendants; -1 if none.
[[nodiscard]] int pickRootMotionJoint(const Clip& clip, const Skeleton& skeleton);

// Yaw (rotation about +Y, radians) of a rotation, by swing-twist decomposition.
[[nodiscard]] float yawOf(const glm::quat& q) noexcept;

}  // namespace marionette
