// Two-bone IK: turn a leg (thigh, shin) or an arm (upper arm, forearm) so that
// its end (ankle, wrist) reaches a target, the knee or elbow bending toward a
// pole point. Analytic (law of cosines), two minimal-arc swings in model space;
// bone lengths are kept since only local rotations change. Near full extension
// the reach is softened, so a target moving past the chain's length does not
// snap the knee straight.
#pragma once
#include <span>

#include "marionette/core/transform.hpp"
#include "marionette/rig/rig.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette {

struct TwoBoneIkSettings {
  // Fraction of the full chain length over which the reach is softened near
  // full extension: up to (1 - softness) of the length a target is reached
  // exactly; beyond it the reach eases toward the full length (never quite
  // straight, continuous with a continuous slope). 0: a hard limit. Clamped to [0, 1].
  float softness = 0.05f;
};

// A limb prepared for the solver (makeLimbIk); upper < 0 when it is unusable.
struct LimbIk {
  int upper = -1, lower = -1, end = -1;
  // False for an end joint that does not descend from `lower` (RobotExpressive's
  // feet are IK targets under the root): then the end point is lower's model
  // transform applied to `endOffsetInLower`, the end's rest offset in lower's frame.
  bool endIsDescendant = true;
  glm::vec3 endOffsetInLower{0.0f};
};

// Checks the limb against the skeleton (indices in range, lower below upper,
// bones longer than 1e-6 m in the rest pose) and measures the end offset from
// the rest pose. Returns upper = -1 when the limb is unusable: a joint missing,
// out of range, not chained, or a zero-length bone. No allocation.
[[nodiscard]] LimbIk makeLimbIk(const Skeleton& skeleton, const RigJoints::LimbJoints& limb) noexcept;
// An arm as the solvers use it: ending at the forearm's first child when the profile names
// no end joint (RobotExpressive: its palm at the wrist).
[[nodiscard]] RigJoints::LimbJoints limbWithEnd(const RigJoints::LimbJoints& limb, const Skeleton& skeleton) noexcept;

// The end point of the limb in model space for this pose (NaN-free; the
// origin when the limb is unusable).
[[nodiscard]] glm::vec3 limbEndModel(const Skeleton& skeleton, std::span<const Transform> localPose,
                                     const LimbIk& limb) noexcept;

// Rotates localPose[upper] and localPose[lower] so that the limb's end point
// reaches `targetModel` (model space: rootTransform included), blended with the
// pose by `weight` in [0, 1] (0 leaves the pose bit-identical). The knee/elbow
// bends toward `poleModel`; a pole on the line to the target (or not finite)
// keeps the current bend plane, and a straight chain then bends about its
// upper joint's own axes. Targets nearer than the chain can fold give the
// most folded chain pointing at them; farther ones the straightest (see
// TwoBoneIkSettings::softness). A detached end joint (!endIsDescendant) is not
// moved: place it at the reached point yourself.
// Returns the remaining distance from the end point to the target (metres),
// +infinity when nothing was done because the limb is unusable, the pose too
// short or the target not finite. Walks the parent chains; no allocation.
float solveTwoBoneIk(const Skeleton& skeleton, std::span<Transform> localPose, const LimbIk& limb,
                     const glm::vec3& targetModel, const glm::vec3& poleModel, float weight,
                     const TwoBoneIkSettings& settings = {}) noexcept;

}  // namespace marionette
