// Reaching: one hand goes to a target (a world point, an object of the scene, a character's
// joint) and holds it, with pointing's arm chain and hinge (arm_placement.hpp), no clip
// needed (SmartBody's <sbm:reach>, Marionette's <reach>). The point that touches is the
// palm: the hand joint moved halfway toward the middle finger's first joint when the rig
// has one (else the hand joint). Phases, as the request's weight envelope: start (the hand
// leaves the pose), ready = stroke (it arrives: the contact), held until relax, back in the
// pose by end. A target beyond the arm's reach from the shoulder: the palm stops on the
// line shoulder to target, the arm extended but not locked (the character neither leans nor
// steps), with a warning. The elbow never bends backward (at least minElbowBend).
#pragma once
#include <span>
#include <string>

#include "marionette/behavior/arm_placement.hpp"
#include "marionette/behavior/spatial_target.hpp"

namespace marionette {

class Rig;
struct BehaviorRequest;

struct ReachSettings {
  // The elbow's least bend, radians: the arm at full reach is extended, not locked straight.
  float minElbowBend = 0.17f;  // about 10 degrees
  // The least time a hand takes to get there (and back): a ready at the start, or a reach
  // shorter than twice this, would otherwise make the arm jump.
  float minMoveSeconds = 0.25f;
};

// Per-request reach state (lives in the request's timeline entry).
struct ReachState {
  SpatialTarget target;
  int side = -1;                // 0 left, 1 right; -1 until chosen (at bind or the first frame)
  LimbIk limb[2];               // left, right (unusable where the rig has no such arm)
  ArmMemory memory[2];
  glm::vec3 palmInEnd[2] = {glm::vec3(0.0f), glm::vec3(0.0f)};  // the palm in the arm's end joint's frame
  glm::vec3 lastTarget{0.0f};   // model frame: held when a target character is lost
  bool started = false;
  // The last frame's figures (for the status and tests): shoulder to target, the arm's reach.
  float distance = 0.0f, reach = 0.0f;
  bool outOfReach = false;
};

// The request's envelope as a reach needs it (BehaviorTimeline::Entry's fields): full weight
// by ready and from relax, but never faster than settings.minMoveSeconds; a reach too short
// for both moves gets a lower peak (the hand goes part of the way).
struct ReachTiming {
  double blendInEnd = 0.0, blendOutStart = 0.0;
  float peak = 1.0f;  // multiplies the request's weight
};
[[nodiscard]] ReachTiming reachTiming(const BehaviorRequest& request, const ReachSettings& settings, std::string& warning);

// Binds a reach request from its ReachParameters: the arms, the palms, the target. Empty
// when it can be performed, else why not (no arm, no target, a target that is not finite);
// `warning` notes approximations (a pick-up that carries nothing, an arm the rig lacks).
[[nodiscard]] std::string bindReach(const BehaviorRequest& request, const Rig& rig, const Skeleton& skeleton,
                                    const TargetJointFinder& findJoint, ReachState& state, std::string& warning);

// Picks the arm whose shoulder is nearer `targetModel` (when the request named none) and
// says, for a target beyond that arm's reach, how far it is (names the request `id`).
void chooseReachArm(ReachState& state, const glm::vec3& targetModel, const Skeleton& skeleton,
                    std::span<const Transform> pose) noexcept;
[[nodiscard]] std::string reachDistanceNote(const ReachState& state, std::string_view id, const glm::vec3& targetModel,
                                            const ReachSettings& settings, const Skeleton& skeleton,
                                            std::span<const Transform> pose);

// One frame: brings the palm to `targetModel` (model frame; `known` false keeps the last
// target) blended with the pose by `weight`. Per-frame: no allocation, no exceptions.
void updateReach(ReachState& state, const glm::vec3& targetModel, bool known, float weight,
                 const ReachSettings& settings, const Skeleton& skeleton, std::span<Transform> pose) noexcept;

// The palm of the reaching arm (side) in model space for this pose; for tests and measurements.
[[nodiscard]] glm::vec3 reachPalmModel(const ReachState& state, int side, const Skeleton& skeleton,
                                       std::span<const Transform> pose) noexcept;

}  // namespace marionette
