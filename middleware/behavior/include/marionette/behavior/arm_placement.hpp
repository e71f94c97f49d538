// Placing an arm (upper arm, forearm) so that its elbow and its end reach given points, the
// way pointing and reaching both move it: the elbow is a hinge whose axis stays where it is
// in the upper arm's frame, and the elbow hangs down and out (a direction field over every
// aim but one, behind and across the body). Per-frame: no allocation, no exceptions.
#pragma once
#include <span>

#include "marionette/behavior/two_bone_ik.hpp"
#include "marionette/core/transform.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette {

// What one arm keeps between frames.
struct ArmMemory {
  glm::vec3 pole{0.0f};        // the last elbow direction, model frame
  glm::vec3 hingeLocal{0.0f};  // the elbow's axis in the upper arm's frame
  bool hingeKnown = false;
};

// One arm measured in this frame's pose, aiming at a target.
struct ArmAim {
  glm::vec3 shoulder{0.0f}, elbow{0.0f}, end{0.0f};  // model frame, as posed now
  float upperLength = 0.0f, lowerLength = 0.0f;
  glm::vec3 direction{0.0f};  // unit, shoulder to target
  float distance = 0.0f;      // shoulder to target
  glm::vec3 elbowSide{0.0f};  // unit, across `direction`: where the elbow goes
};

// The profile's arms (left, right) as pointing and reaching move them (limbWithEnd); an arm
// the rig lacks is unusable (upper < 0). False when neither is usable.
bool makeArms(const RigJoints& joints, const Skeleton& skeleton, LimbIk (&arms)[2]) noexcept;

// Measures `limb` (side 0 left, 1 right; `other` the opposite arm, possibly unusable) for an
// aim at `target` (model frame) and updates memory.pole. False when the arm or the aim is
// degenerate (a zero-length bone, the target at the shoulder or not finite).
[[nodiscard]] bool measureArm(const Skeleton& skeleton, std::span<const Transform> pose, const LimbIk& limb,
                              const LimbIk& other, int side, const glm::vec3& target, ArmMemory& memory,
                              ArmAim& out) noexcept;

// The longest shoulder-to-end distance with the elbow bent by `bend` radians.
[[nodiscard]] float armReach(float upperLength, float lowerLength, float bend) noexcept;

// The elbow for the arm's end at `distance` along aim.direction (clamped to what the arm
// spans, from folded to armReach(bend)), on aim.elbowSide; `end` receives the end point.
[[nodiscard]] glm::vec3 foldedElbow(const ArmAim& aim, float distance, float bend, glm::vec3& end) noexcept;

// Turns the upper arm and the forearm so that the elbow goes to `elbow` and the limb's end
// toward `end` (the forearm swings about the hinge), blended with the pose by `weight`.
void placeArm(const Skeleton& skeleton, std::span<Transform> pose, const LimbIk& limb, const ArmAim& aim,
              const glm::vec3& elbow, const glm::vec3& end, float weight, ArmMemory& memory) noexcept;

}  // namespace marionette
