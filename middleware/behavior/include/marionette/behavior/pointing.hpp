// Pointing: aim an arm at a target with two-bone IK, no clip needed (BML
// <pointing target mode>). The elbow keeps a slight natural bend and the arm is
// solved so that the forearm's line (elbow to wrist) passes through the target:
// the hand points at it rather than the shoulder. The elbow hangs down and out.
// A target nearer than the hand would be is reached for instead (the wrist goes
// to it). A gesture clip the pointing names (lexeme) can shape the hand under it.
#pragma once
#include <span>
#include <string>

#include "marionette/behavior/arm_placement.hpp"
#include "marionette/behavior/spatial_target.hpp"
#include "marionette/behavior/two_bone_ik.hpp"
#include "marionette/core/transform.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette {

class Rig;
struct BehaviorRequest;

struct PointingSettings {
  // The elbow's bend while pointing, radians (a fully straight arm looks locked,
  // and the IK's direction is ill-defined there). Clamped to [0.02, 1.2].
  float elbowBend = 0.26f;  // 15 degrees
};

// Per-request pointing state (lives in the request's timeline entry).
struct PointingState {
  SpatialTarget target;        // a character without a joint: its chest
  bool arm[2] = {};            // left, right in use; both false until the first frame picks one
  LimbIk limb[2];              // left, right (unusable where the rig has no such arm)
  ArmMemory memory[2];         // the elbow's direction and hinge, per arm
  glm::vec3 lastTarget{0.0f};  // model frame: held when the target is lost or at the shoulder
  bool started = false;
};

// Binds a pointing request from its PointingParameters: the target (a character
// without a joint: its chest) and the arms (Nearest: the arm on the target's
// side, chosen at the first frame and kept). An arm without an end joint in the profile
// (RobotExpressive) ends at the forearm's first child (its palm at the wrist).
// Empty when it can be performed, else why not; `warning` notes an arm the rig lacks.
[[nodiscard]] std::string bindPointing(const BehaviorRequest& request, const Rig& rig, const Skeleton& skeleton,
                                       const TargetJointFinder& findJoint, PointingState& state, std::string& warning);

// One frame: aims the arm(s) at `targetModel` (model frame; `known` false keeps
// the last target) blended with the pose by `weight`. Per-frame: no allocation.
void updatePointing(PointingState& state, const glm::vec3& targetModel, bool known, float weight,
                    const PointingSettings& settings, const Skeleton& skeleton, std::span<Transform> pose) noexcept;

// How far off the forearm's line (elbow to wrist, extended) passes from the
// target, as an angle at the elbow (radians); for tests and measurements.
[[nodiscard]] float pointingErrorRadians(const Skeleton& skeleton, std::span<const Transform> pose, const LimbIk& limb,
                                         const glm::vec3& targetModel) noexcept;

}  // namespace marionette
