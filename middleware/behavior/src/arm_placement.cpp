#include "marionette/behavior/arm_placement.hpp"

#include <algorithm>
#include <cmath>

#include "marionette/animation/pose.hpp"
#include "marionette/core/finite.hpp"

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

}  // namespace

bool makeArms(const RigJoints& j, const Skeleton& s, LimbIk (&arms)[2]) noexcept {
  arms[0] = makeLimbIk(s, limbWithEnd(j.leftArm, s));
  arms[1] = makeLimbIk(s, limbWithEnd(j.rightArm, s));
  return arms[0].upper >= 0 || arms[1].upper >= 0;
}

bool measureArm(const Skeleton& s, std::span<const Transform> pose, const LimbIk& limb, const LimbIk& other, int side,
                const glm::vec3& target, ArmMemory& memory, ArmAim& out) noexcept {
  if (limb.upper < 0) return false;
  const int clavicle = s.parents[static_cast<std::size_t>(limb.upper)];
  out.shoulder = originOf(s, pose, limb.upper);
  out.elbow = originOf(s, pose, limb.lower);
  out.end = limbEndModel(s, pose, limb);
  out.upperLength = glm::length(out.elbow - out.shoulder);
  out.lowerLength = glm::length(out.end - out.elbow);
  const glm::vec3 to = target - out.shoulder;
  out.distance = glm::length(to);
  if (!(out.upperLength > 1e-6f) || !(out.lowerLength > 1e-6f) || !(out.distance > 1e-4f) ||
      !std::isfinite(out.distance))
    return false;
  out.direction = to / out.distance;

  // The one aim with no elbow direction: behind and across the body.
  glm::vec3 outward = other.upper >= 0 ? out.shoulder - originOf(s, pose, other.upper)
                                       : out.shoulder - originOf(s, pose, clavicle >= 0 ? s.parents[static_cast<std::size_t>(clavicle)] : -1);
  outward.y = 0.0f;
  outward = glm::length(outward) > 1e-6f ? glm::normalize(outward) : glm::vec3(side == 0 ? 1.0f : -1.0f, 0.0f, 0.0f);
  const glm::vec3 up(0.0f, 1.0f, 0.0f);
  const glm::vec3 forward = side == 0 ? glm::cross(outward, up) : glm::cross(up, outward);
  const glm::vec3 away = glm::normalize(-outward - forward);
  out.elbowSide = elbowDirection(out.direction, away, memory.pole);
  memory.pole = out.elbowSide;
  return true;
}

float armReach(float l1, float l2, float bend) noexcept {
  return std::sqrt(std::max(l1 * l1 + l2 * l2 + 2.0f * l1 * l2 * std::cos(bend), 0.0f));
}

glm::vec3 foldedElbow(const ArmAim& aim, float distance, float bend, glm::vec3& end) noexcept {
  const float l1 = aim.upperLength, l2 = aim.lowerLength;
  const float reach = std::clamp(distance, std::max(std::fabs(l1 - l2), 1e-3f * (l1 + l2)) * 1.001f, armReach(l1, l2, bend));
  const float along = (l1 * l1 - l2 * l2 + reach * reach) / (2.0f * reach);
  end = aim.shoulder + aim.direction * reach;
  return aim.shoulder + aim.direction * along + aim.elbowSide * std::sqrt(std::max(l1 * l1 - along * along, 0.0f));
}

// The elbow is a hinge: its axis stays where it is in the upper arm's frame (measured at
// the first frame), so the upper arm turns as a whole frame onto (shoulder to elbow, hinge)
// and the forearm swings about the hinge. Swinging each bone by its smallest arc instead
// would flip the upper arm's twist when the arm turns through the opposite of its current
// direction (raised straight up from hanging down).
void placeArm(const Skeleton& s, std::span<Transform> pose, const LimbIk& limb, const ArmAim& aim,
              const glm::vec3& elbow, const glm::vec3& wrist, float weight, ArmMemory& memory) noexcept {
  const auto upper = static_cast<std::size_t>(limb.upper), lower = static_cast<std::size_t>(limb.lower);
  const glm::mat4 parentModel = modelMatrixOf(s, pose, s.parents[upper]);
  const glm::mat3 upperLinear(affineMultiply(parentModel, pose[upper].matrix()));
  const glm::vec3 b1 = glm::normalize(elbow - aim.shoulder);
  const glm::vec3 h1 = orthonormalTo(glm::cross(b1, wrist - elbow), b1);
  if (glm::length(h1) < 0.5f || !isFinite(h1)) return;

  // The hinge in the upper arm's frame, from the first frame's bend (or, for a
  // straight arm, the plane it is about to bend in).
  const glm::vec3 b0 = glm::normalize(aim.elbow - aim.shoulder);
  if (!memory.hingeKnown) {
    const glm::vec3 bent = glm::cross(b0, aim.end - aim.elbow);
    glm::vec3 h = orthonormalTo(bent, b0);
    if (glm::length(h) < 0.5f || glm::length(bent) < 1e-3f * aim.upperLength * aim.lowerLength)
      h = orthonormalTo(glm::cross(b0, orthonormalTo(aim.elbowSide, b0)), b0);
    if (glm::length(h) < 0.5f) return;
    memory.hingeLocal = glm::inverse(upperLinear) * h;
    memory.hingeKnown = true;
  }
  const glm::vec3 h0 = orthonormalTo(upperLinear * memory.hingeLocal, b0);
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
    pose[lower].rotation = applyModelRotation(aboveLower, glm::mat3_cast(glm::angleAxis(angle, h1)), lowerBefore);
  }
  if (weight < 1.0f) {
    pose[upper].rotation = slerpShortest(upperBefore, pose[upper].rotation, weight);
    pose[lower].rotation = slerpShortest(lowerBefore, pose[lower].rotation, weight);
  }
}

}  // namespace marionette
