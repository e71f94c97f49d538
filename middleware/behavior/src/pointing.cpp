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

// Where the elbow goes for an aim d: a direction field across d that is
// continuous everywhere but at one aim, `away` (behind and across the body,
// where no arm points). It is the sphere's image of a constant plane field
// under stereographic projection from `away`: X(d) = (1 - d.N) a - (d.a)(d - N),
// with a the down direction across N. So the elbow hangs down for aims ahead,
// out, across and behind, points back for the arm hanging, and out in front
// for the arm raised; any field made by projecting one fixed vector would have
// two singular aims, one of them reachable (hairy-ball theorem: one is needed).
glm::vec3 elbowDirection(const glm::vec3& d, const glm::vec3& away, const glm::vec3& last) noexcept {
  glm::vec3 a = glm::vec3(0.0f, -1.0f, 0.0f) - away * -away.y;  // down, across `away`
  a = glm::length(a) > 1e-6f ? glm::normalize(a) : glm::vec3(0.0f, 0.0f, -1.0f);
  const glm::vec3 x = (1.0f - glm::dot(d, away)) * a - glm::dot(d, a) * (d - away);
  const float n = glm::length(x);
  if (n > 1e-4f && std::isfinite(n)) return x / n;
  const glm::vec3 held = last - d * glm::dot(d, last);  // at the singular aim: keep the last
  if (glm::length(held) > 1e-4f) return glm::normalize(held);
  const glm::vec3 any = glm::cross(d, std::fabs(d.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0));
  return glm::normalize(any);
}

// The rotation taking the orthonormal pair (b0, h0) onto (b1, h1).
glm::mat3 frameRotation(const glm::vec3& b0, const glm::vec3& h0, const glm::vec3& b1, const glm::vec3& h1) noexcept {
  const glm::mat3 from(b0, h0, glm::cross(b0, h0)), to(b1, h1, glm::cross(b1, h1));
  return to * glm::transpose(from);
}

// A model-space rotation about a joint as a change of its local rotation: with
// A its parent's model linear part, A R' = q A R gives R' = (A^-1 q A) R.
glm::quat applyModelRotation(const glm::mat4& parentModel, const glm::mat3& q, const glm::quat& local) noexcept {
  const glm::mat3 a(parentModel);
  const float det = glm::determinant(a);
  if (!(std::fabs(det) > 1e-30f) || !std::isfinite(det)) return local;
  return safeNormalize(glm::quat_cast(glm::inverse(a) * q * a) * local);
}

glm::vec3 orthonormalTo(const glm::vec3& v, const glm::vec3& unit) noexcept {
  const glm::vec3 w = v - unit * glm::dot(v, unit);
  const float n = glm::length(w);
  return n > 1e-6f ? w / n : glm::vec3(0.0f);
}

// Aims one arm. The elbow is a hinge: its axis stays where it is in the upper
// arm's frame (measured at the first frame), so the upper arm turns as a whole
// frame onto (shoulder to elbow, hinge) and the forearm swings about the hinge.
// Swinging each bone by its smallest arc instead would flip the upper arm's twist
// when the arm turns through the opposite of its current direction (raised straight
// up from hanging down).
void aimArm(PointingState& st, int side, const glm::vec3& target, float weight, float bend, const Skeleton& s,
            std::span<Transform> pose) noexcept {
  const LimbIk& limb = st.limb[side];
  const auto upper = static_cast<std::size_t>(limb.upper), lower = static_cast<std::size_t>(limb.lower);
  const int clavicle = s.parents[upper];
  const glm::mat4 parentModel = modelMatrixOf(s, pose, clavicle);
  const glm::mat4 upperModel = affineMultiply(parentModel, pose[upper].matrix());
  const glm::vec3 shoulder(upperModel[3]);
  const glm::vec3 elbow0 = originOf(s, pose, limb.lower), wrist0 = limbEndModel(s, pose, limb);
  const float l1 = glm::length(elbow0 - shoulder), l2 = glm::length(wrist0 - elbow0);
  const glm::vec3 to = target - shoulder;
  const float distance = glm::length(to);
  if (!(l1 > 1e-6f) || !(l2 > 1e-6f) || !(distance > 1e-4f) || !std::isfinite(distance)) return;
  const glm::vec3 d = to / distance;

  // The one aim with no elbow direction: behind and across the body.
  const LimbIk& other = st.limb[1 - side];
  glm::vec3 outward = other.upper >= 0 ? shoulder - originOf(s, pose, other.upper)
                                       : shoulder - originOf(s, pose, clavicle >= 0 ? s.parents[static_cast<std::size_t>(clavicle)] : -1);
  outward.y = 0.0f;
  outward = glm::length(outward) > 1e-6f ? glm::normalize(outward) : glm::vec3(side == 0 ? 1.0f : -1.0f, 0.0f, 0.0f);
  const glm::vec3 up(0.0f, 1.0f, 0.0f);
  const glm::vec3 forward = side == 0 ? glm::cross(outward, up) : glm::cross(up, outward);
  const glm::vec3 away = glm::normalize(-outward - forward);
  const glm::vec3 p = elbowDirection(d, away, st.pole[side]);
  st.pole[side] = p;

  // The triangle shoulder - elbow - target with the elbow's inner angle pi - bend:
  // x is the elbow's distance to the target, a the upper arm's angle off the aim.
  const float innerSin = std::sin(bend), innerCos = -std::cos(bend);
  const float x = l1 * innerCos + std::sqrt(std::max(distance * distance - l1 * l1 * innerSin * innerSin, 0.0f));
  glm::vec3 elbow, wrist;
  if (x > l2) {
    const float sinA = std::min(x * innerSin / distance, 1.0f);
    const float cosA = std::sqrt(std::max(1.0f - sinA * sinA, 0.0f));
    elbow = shoulder + l1 * (cosA * d + sinA * p);
    wrist = elbow + (l2 / x) * (target - elbow);
  } else {  // nearer than the hand would be: reach for it, as far as the arm folds
    const float longest = std::sqrt(l1 * l1 + l2 * l2 + 2.0f * l1 * l2 * std::cos(bend));  // with the bend kept
    const float reach = std::clamp(distance, std::max(std::fabs(l1 - l2), 1e-3f * (l1 + l2)) * 1.001f, longest);
    const float along = (l1 * l1 - l2 * l2 + reach * reach) / (2.0f * reach);
    elbow = shoulder + d * along + p * std::sqrt(std::max(l1 * l1 - along * along, 0.0f));
    wrist = shoulder + d * reach;
  }
  const glm::vec3 b1 = glm::normalize(elbow - shoulder);
  const glm::vec3 h1 = orthonormalTo(glm::cross(b1, wrist - elbow), b1);
  if (glm::length(h1) < 0.5f) return;

  // The hinge in the upper arm's frame, from the first frame's bend (or, for a
  // straight arm, the plane it is about to bend in).
  const glm::mat3 upperLinear(upperModel);
  const glm::vec3 b0 = glm::normalize(elbow0 - shoulder);
  if (!st.hingeKnown[side]) {
    glm::vec3 h = orthonormalTo(glm::cross(b0, wrist0 - elbow0), b0);
    if (glm::length(h) < 0.5f || glm::length(glm::cross(b0, wrist0 - elbow0)) < 1e-3f * l1 * l2)
      h = orthonormalTo(glm::cross(b0, orthonormalTo(p, b0)), b0);
    if (glm::length(h) < 0.5f) return;
    st.hingeLocal[side] = glm::inverse(upperLinear) * h;
    st.hingeKnown[side] = true;
  }
  const glm::vec3 h0 = orthonormalTo(upperLinear * st.hingeLocal[side], b0);
  if (glm::length(h0) < 0.5f || !isFinite(h0)) return;

  const glm::quat upperBefore = pose[upper].rotation, lowerBefore = pose[lower].rotation;
  pose[upper].rotation = applyModelRotation(parentModel, frameRotation(b0, h0, b1, h1), upperBefore);
  // The forearm onto the wrist, about the hinge (both lie across it now).
  const glm::mat4 aboveLower = modelMatrixOf(s, pose, s.parents[lower]);
  const glm::vec3 elbow1 = originOf(s, pose, limb.lower);
  const glm::vec3 f0 = orthonormalTo(limbEndModel(s, pose, limb) - elbow1, h1);
  const glm::vec3 f1 = glm::normalize(wrist - elbow1);
  if (glm::length(f0) > 0.5f) {
    const float angle = std::atan2(glm::dot(glm::cross(f0, f1), h1), glm::dot(f0, f1));
    pose[lower].rotation =
        applyModelRotation(aboveLower, glm::mat3_cast(glm::angleAxis(angle, h1)), lowerBefore);
  }
  if (weight < 1.0f) {
    pose[upper].rotation = slerpShortest(upperBefore, pose[upper].rotation, weight);
    pose[lower].rotation = slerpShortest(lowerBefore, pose[lower].rotation, weight);
  }
}

}  // namespace

std::string bindPointing(const BehaviorRequest& request, const Rig& rig, const Skeleton& skeleton,
                         const TargetJointFinder& findJoint, PointingState& st, std::string& warning) {
  const RigJoints& j = rig.joints();
  st.limb[0] = makeLimbIk(skeleton, limbWithEnd(j.leftArm, skeleton));
  st.limb[1] = makeLimbIk(skeleton, limbWithEnd(j.rightArm, skeleton));
  const bool usable[2] = {st.limb[0].upper >= 0, st.limb[1].upper >= 0};
  if (!usable[0] && !usable[1])
    return "the character has no arm to point with (set leftArm / rightArm in its profile)";
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
