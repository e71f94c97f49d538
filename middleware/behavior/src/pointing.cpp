#include "marionette/behavior/pointing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "marionette/core/finite.hpp"
#include "marionette/animation/pose.hpp"
#include "marionette/behavior/behavior_request.hpp"
#include "marionette/rig/rig.hpp"

namespace marionette {

namespace {

glm::vec3 originOf(const Skeleton& s, std::span<const Transform> pose, int joint) noexcept {
  return glm::vec3(modelMatrixOf(s, pose, joint)[3]);
}

// Aims one arm: the triangle shoulder - elbow - target with the elbow's inner angle
// pi - bend puts the forearm's line through the target; a target nearer than the hand
// would be is reached for instead (the wrist goes to it, as far as the arm folds).
void aimArm(PointingState& st, int side, const glm::vec3& target, float weight, float bend, const Skeleton& s,
            std::span<Transform> pose) noexcept {
  ArmAim aim;
  if (!measureArm(s, pose, st.limb[side], st.limb[1 - side], side, target, st.memory[side], aim)) return;
  const float l1 = aim.upperLength, l2 = aim.lowerLength, distance = aim.distance;
  // x is the elbow's distance to the target, a the upper arm's angle off the aim.
  const float innerSin = std::sin(bend), innerCos = -std::cos(bend);
  const float x = l1 * innerCos + std::sqrt(std::max(distance * distance - l1 * l1 * innerSin * innerSin, 0.0f));
  glm::vec3 elbow, wrist;
  if (x > l2) {
    const float sinA = std::min(x * innerSin / distance, 1.0f);
    const float cosA = std::sqrt(std::max(1.0f - sinA * sinA, 0.0f));
    elbow = aim.shoulder + l1 * (cosA * aim.direction + sinA * aim.elbowSide);
    wrist = elbow + (l2 / x) * (target - elbow);
  } else {
    elbow = foldedElbow(aim, distance, bend, wrist);
  }
  placeArm(s, pose, st.limb[side], aim, elbow, wrist, weight, st.memory[side]);
}

}  // namespace

std::string bindPointing(const BehaviorRequest& request, const Rig& rig, const Skeleton& skeleton,
                         const TargetJointFinder& findJoint, PointingState& st, std::string& warning) {
  if (!makeArms(rig.joints(), skeleton, st.limb))
    return "the character has no arm to point with (set leftArm / rightArm in its profile)";
  const bool usable[2] = {st.limb[0].upper >= 0, st.limb[1].upper >= 0};
  const PointingParameters* p = request.as<PointingParameters>();
  if (std::string why = resolveSpatialTarget(p ? p->target : BehaviorTarget{}, "pointing", findJoint, st.target);
      !why.empty())
    return why;
  // Nearest, or an arm the rig lacks: the first frame picks the arm on the target's side.
  const PointingArms arms = p->arms;
  const bool want[2] = {arms == PointingArms::Left || arms == PointingArms::Both,
                        arms == PointingArms::Right || arms == PointingArms::Both};
  for (int side = 0; side < 2; ++side) {
    if (want[side] && usable[side]) st.arm[side] = true;
    else if (want[side])
      warning += std::string(warning.empty() ? "" : "; ") + "the character has no usable " + (side ? "right" : "left") +
                 " arm; the other one points";
  }
  return {};
}

void updatePointing(PointingState& st, const glm::vec3& targetModel, bool known, float weight,
                    const PointingSettings& settings, const Skeleton& skeleton, std::span<Transform> pose) noexcept {
  const bool finite = isFinite(targetModel);
  if (known && finite) st.lastTarget = targetModel;
  else if (!st.started) return;
  const glm::vec3 target = st.lastTarget;
  if (!st.started) {
    st.started = true;
    if (!st.arm[0] && !st.arm[1]) {  // the arm whose shoulder is nearer the target
      float reach[2];
      for (int side = 0; side < 2; ++side)
        reach[side] = st.limb[side].upper >= 0 ? glm::length(originOf(skeleton, pose, st.limb[side].upper) - target)
                                               : std::numeric_limits<float>::infinity();
      st.arm[reach[1] < reach[0] ? 1 : 0] = true;
    }
  }
  const float bend = std::clamp(settings.elbowBend, 0.02f, 1.2f);
  const float w = std::clamp(weight, 0.0f, 1.0f);
  for (int side = 0; side < 2; ++side)
    if (st.arm[side] && st.limb[side].upper >= 0) aimArm(st, side, target, w, bend, skeleton, pose);
}

float pointingErrorRadians(const Skeleton& skeleton, std::span<const Transform> pose, const LimbIk& limb,
                           const glm::vec3& targetModel) noexcept {
  if (limb.upper < 0) return std::numeric_limits<float>::infinity();
  const glm::vec3 elbow = originOf(skeleton, pose, limb.lower);
  const glm::vec3 forearm = limbEndModel(skeleton, pose, limb) - elbow, to = targetModel - elbow;
  const float a = glm::length(forearm), b = glm::length(to);
  if (!(a > 0.0f) || !(b > 0.0f)) return std::numeric_limits<float>::infinity();
  return std::acos(std::clamp(glm::dot(forearm, to) / (a * b), -1.0f, 1.0f));
}

}  // namespace marionette
