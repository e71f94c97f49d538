#include "marionette/behavior/two_bone_ik.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "marionette/core/finite.hpp"
#include "marionette/animation/pose.hpp"

namespace marionette {

namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();


// Joints the pose and the skeleton both have.
int jointCount(const Skeleton& s, std::size_t poseSize) noexcept {
  return static_cast<int>(std::min({s.parents.size(), poseSize, s.restPose.size()}));
}

int parentOf(const Skeleton& s, int j) noexcept {
  const int p = s.parents[static_cast<std::size_t>(j)];
  return p < j ? p : -1;  // a malformed parent after its child would loop: treat as a root
}

// True when `ancestor` is a proper ancestor of `j`.
bool descends(const Skeleton& s, int ancestor, int j) noexcept {
  for (int p = parentOf(s, j); p >= 0; p = parentOf(s, p))
    if (p == ancestor) return true;
  return false;
}

// Model matrix of joint j for this pose (the root space for j < 0).
glm::mat4 modelOf(const Skeleton& s, std::span<const Transform> pose, int j) noexcept {
  glm::mat4 m(1.0f);
  for (; j >= 0; j = parentOf(s, j)) m = affineMultiply(pose[static_cast<std::size_t>(j)].matrix(), m);
  return affineMultiply(s.rootTransform, m);
}

// The locals from below `top` down to `j`: model(j) = model(top) * below(top, j).
glm::mat4 below(const Skeleton& s, std::span<const Transform> pose, int top, int j) noexcept {
  glm::mat4 m(1.0f);
  for (; j >= 0 && j != top; j = parentOf(s, j)) m = affineMultiply(pose[static_cast<std::size_t>(j)].matrix(), m);
  return m;
}

// The limb's joints in model space for one pose.
struct ChainPose {
  glm::mat4 aboveUpper, upper, lower;  // model matrices: upper's parent, upper, lower
  glm::vec3 a, b, c;                   // upper's and lower's origins, the end point
};

ChainPose evaluate(const Skeleton& s, std::span<const Transform> pose, const LimbIk& limb) noexcept {
  ChainPose cp;
  cp.aboveUpper = modelOf(s, pose, parentOf(s, limb.upper));
  cp.upper = affineMultiply(cp.aboveUpper, pose[static_cast<std::size_t>(limb.upper)].matrix());
  cp.lower = affineMultiply(cp.upper, below(s, pose, limb.upper, limb.lower));
  cp.a = glm::vec3(cp.upper[3]);
  cp.b = glm::vec3(cp.lower[3]);
  cp.c = limb.endIsDescendant ? glm::vec3(affineMultiply(cp.lower, below(s, pose, limb.lower, limb.end))[3])
                              : glm::vec3(cp.lower * glm::vec4(limb.endOffsetInLower, 1.0f));
  return cp;
}

bool usable(const Skeleton& s, std::size_t poseSize, const LimbIk& l) noexcept {
  const int n = jointCount(s, poseSize);
  auto in = [&](int j) { return j >= 0 && j < n; };
  if (!in(l.upper) || !in(l.lower) || !descends(s, l.upper, l.lower)) return false;
  if (l.endIsDescendant) return in(l.end) && descends(s, l.lower, l.end);
  return isFinite(l.endOffsetInLower);
}

// Length and direction of v without overflow for huge v (a target 1e30 m away).
float lengthOf(const glm::vec3& v, glm::vec3* direction = nullptr) noexcept {
  const float m = std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
  if (!(m > 0.0f) || !std::isfinite(m)) return m > 0.0f ? kInfinity : 0.0f;
  const glm::vec3 scaled = v / m;
  const float k = std::sqrt(glm::dot(scaled, scaled));
  if (direction) *direction = scaled / k;
  return m * k;
}

glm::vec3 across(const glm::vec3& v, const glm::vec3& unitAxis) noexcept { return v - unitAxis * glm::dot(v, unitAxis); }

// The smallest rotation taking direction `from` to direction `to`; about
// `halfTurnAxis` (perpendicular to both) when they are opposite.
glm::quat rotationBetween(const glm::vec3& from, const glm::vec3& to, const glm::vec3& halfTurnAxis) noexcept {
  glm::vec3 f, t;
  if (!(lengthOf(from, &f) > 0.0f) || !(lengthOf(to, &t) > 0.0f)) return glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
  const float d = glm::dot(f, t);
  if (d < -0.99999f) return glm::quat(0.0f, halfTurnAxis.x, halfTurnAxis.y, halfTurnAxis.z);
  const glm::vec3 c = glm::cross(f, t);
  return safeNormalize(glm::quat(1.0f + d, c.x, c.y, c.z));  // half-angle form of (axis c, angle acos d)
}

// A model-space rotation `q` about a joint, as a change of its local rotation:
// with A the parent's model linear part, A R' = q A R gives R' = (A^-1 q A) R.
glm::quat localDelta(const glm::mat4& parentModel, const glm::quat& q) noexcept {
  const glm::mat3 a(parentModel);
  const float det = glm::determinant(a);
  if (!(std::fabs(det) > 1e-30f) || !std::isfinite(det)) return glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
  return safeNormalize(glm::quat_cast(glm::inverse(a) * glm::mat3_cast(q) * a));
}

// Distance from the upper joint to the end point that the solver aims for: the
// target's distance up to (1 - softness) of the full length, then easing toward
// the full length, r0 + s (1 - e^(-(d - r0) / s)): continuous, with a continuous
// slope, and never quite straight (no snap of the knee).
float softReach(float distance, float full, float softness) noexcept {
  const float s = (std::isfinite(softness) ? std::clamp(softness, 0.0f, 1.0f) : 0.0f) * full;
  const float r0 = full - s;
  if (s <= 0.0f || distance <= r0) return std::min(distance, full);
  return r0 + s * (1.0f - std::exp(-(distance - r0) / s));
}

// Unit vector across the line to the target, on the side the knee should go:
// toward the pole; else where the knee is now; else, for a straight chain, along
// the upper joint's axis that is most across the line.
glm::vec3 bendDirection(const ChainPose& cp, const glm::vec3& u, const glm::vec3& pole, float full) noexcept {
  glm::vec3 w;
  if (isFinite(pole) && lengthOf(across(pole - cp.a, u), &w) > 1e-4f * full) return w;
  if (lengthOf(across(cp.b - cp.a, u), &w) > 1e-5f * full) return w;
  int best = 0;
  float bestDot = 2.0f;
  glm::vec3 axes[3];
  for (int i = 0; i < 3; ++i) {
    if (!(lengthOf(glm::vec3(cp.upper[i]), &axes[i]) > 0.0f)) continue;
    const float d = std::fabs(glm::dot(axes[i], u));
    if (d < bestDot) bestDot = d, best = i;
  }
  if (bestDot < 2.0f && lengthOf(across(axes[best], u), &w) > 0.0f) return w;
  // Nothing usable (a degenerate upper frame): any direction across the line.
  lengthOf(across(std::fabs(u.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0), u), &w);
  return w;
}

}  // namespace

LimbIk makeLimbIk(const Skeleton& skeleton, const RigJoints::LimbJoints& j) noexcept {
  const int n = jointCount(skeleton, skeleton.restPose.size());
  auto in = [&](int k) { return k >= 0 && k < n; };
  if (!in(j.upper) || !in(j.lower) || !in(j.end) || j.end == j.lower || j.end == j.upper) return {};
  if (!descends(skeleton, j.upper, j.lower)) return {};
  LimbIk out;
  out.endIsDescendant = descends(skeleton, j.lower, j.end);
  if (!out.endIsDescendant && (descends(skeleton, j.end, j.lower))) return {};  // an "end" above the limb
  const std::span<const Transform> rest(skeleton.restPose);
  const glm::mat4 upper = modelOf(skeleton, rest, j.upper);
  const glm::mat4 lower = modelOf(skeleton, rest, j.lower);
  const glm::mat4 end = modelOf(skeleton, rest, j.end);
  const float det = glm::determinant(glm::mat3(lower));
  if (!(std::fabs(det) > 1e-30f) || !std::isfinite(det)) return {};
  out.endOffsetInLower = glm::vec3(glm::inverse(lower) * end[3]);
  const float thigh = lengthOf(glm::vec3(lower[3] - upper[3])), shin = lengthOf(glm::vec3(end[3] - lower[3]));
  if (!(thigh > 1e-6f) || !(shin > 1e-6f) || !std::isfinite(thigh + shin) || !isFinite(out.endOffsetInLower)) return {};
  out.upper = j.upper, out.lower = j.lower, out.end = j.end;
  return out;
}

glm::vec3 limbEndModel(const Skeleton& skeleton, std::span<const Transform> localPose, const LimbIk& limb) noexcept {
  if (!usable(skeleton, localPose.size(), limb)) return glm::vec3(0.0f);
  const glm::vec3 c = evaluate(skeleton, localPose, limb).c;
  return isFinite(c) ? c : glm::vec3(0.0f);
}

float solveTwoBoneIk(const Skeleton& skeleton, std::span<Transform> localPose, const LimbIk& limb,
                     const glm::vec3& targetModel, const glm::vec3& poleModel, float weight,
                     const TwoBoneIkSettings& settings) noexcept {
  if (!usable(skeleton, localPose.size(), limb) || !isFinite(targetModel)) return kInfinity;
  const std::span<const Transform> pose(localPose.data(), localPose.size());
  const ChainPose cp = evaluate(skeleton, pose, limb);
  const float w = std::isfinite(weight) ? std::clamp(weight, 0.0f, 1.0f) : 0.0f;
  const float l1 = lengthOf(cp.b - cp.a), l2 = lengthOf(cp.c - cp.b), full = l1 + l2;
  if (w <= 0.0f || !(l1 > 1e-7f) || !(l2 > 1e-7f) || !std::isfinite(full) || !isFinite(cp.c))
    return lengthOf(targetModel - cp.c);  // nothing to do, or a bone of zero length: pose unchanged

  // Where the end point goes: along u, the direction to the target (or, for a
  // target at the upper joint, the chain's current direction), at the softened reach.
  glm::vec3 u;
  const float distance = lengthOf(targetModel - cp.a, &u);
  if (!(distance > 1e-6f * full) && !(lengthOf(cp.c - cp.a, &u) > 1e-6f * full)) lengthOf(cp.b - cp.a, &u);
  const float minReach = std::max(std::fabs(l1 - l2), 1e-3f * full);  // folded as far as it goes
  const float reach = std::clamp(softReach(distance, full, settings.softness), minReach, full);

  // The knee: l1 from the upper joint and l2 from the end goal, on the pole's side.
  const glm::vec3 side = bendDirection(cp, u, poleModel, full);
  const float along = (l1 * l1 - l2 * l2 + reach * reach) / (2.0f * reach);
  const float out = std::sqrt(std::max(0.0f, l1 * l1 - along * along));
  const glm::vec3 knee = cp.a + u * along + side * out;
  const glm::vec3 goal = cp.a + u * reach;
  const glm::vec3 bendAxis = glm::cross(u, side);  // unit: u and side are orthonormal

  const glm::quat upper0 = localPose[static_cast<std::size_t>(limb.upper)].rotation;
  const glm::quat lower0 = localPose[static_cast<std::size_t>(limb.lower)].rotation;
  // Swing the upper bone onto the knee, then (from the positions that gives,
  // so rounding does not add up) the lower bone onto the goal.
  const glm::quat swingUpper = rotationBetween(cp.b - cp.a, knee - cp.a, bendAxis);
  const glm::quat upper1 = safeNormalize(localDelta(cp.aboveUpper, swingUpper) * upper0);
  localPose[static_cast<std::size_t>(limb.upper)].rotation = upper1;
  const ChainPose swung = evaluate(skeleton, pose, limb);
  const int aboveLower = parentOf(skeleton, limb.lower);
  const glm::mat4 aboveLowerModel =
      aboveLower == limb.upper ? swung.upper : affineMultiply(swung.upper, below(skeleton, pose, limb.upper, aboveLower));
  const glm::quat swingLower = rotationBetween(swung.c - swung.b, goal - swung.b, bendAxis);
  const glm::quat lower1 = safeNormalize(localDelta(aboveLowerModel, swingLower) * lower0);

  if (w < 1.0f) {
    localPose[static_cast<std::size_t>(limb.upper)].rotation = slerpShortest(upper0, upper1, w);
    localPose[static_cast<std::size_t>(limb.lower)].rotation = slerpShortest(lower0, lower1, w);
  } else {
    localPose[static_cast<std::size_t>(limb.lower)].rotation = lower1;
  }
  return lengthOf(targetModel - evaluate(skeleton, pose, limb).c);
}

RigJoints::LimbJoints limbWithEnd(const RigJoints::LimbJoints& limb, const Skeleton& s) noexcept {
  RigJoints::LimbJoints a = limb;
  if (a.end < 0 && a.lower >= 0)
    for (std::size_t j = static_cast<std::size_t>(a.lower) + 1; j < s.parents.size(); ++j)
      if (s.parents[j] == a.lower) {
        a.end = static_cast<int>(j);
        break;
      }
  return a;
}

}  // namespace marionette
