#include "marionette/retarget/target_check.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <iterator>
#include <set>

#include "marionette/rig/joint_map.hpp"

namespace marionette::retarget {

namespace {

// The minimum humanoid: its root, head and limbs down to the elbows and knees. Hands and feet
// are end-effectors some rigs lack (RobotExpressive's palms hang from its forearms): the joint
// map's own warnings name them, and the report's coverage says what is measured.
constexpr Bone kMinimumHumanoid[] = {Bone::Hips,          Bone::Head,          Bone::LeftUpperArm, Bone::LeftLowerArm,
                                     Bone::RightUpperArm, Bone::RightLowerArm, Bone::LeftUpperLeg, Bone::LeftLowerLeg,
                                     Bone::RightUpperLeg, Bone::RightLowerLeg};

}  // namespace

std::string_view targetClassName(TargetClass c) noexcept {
  switch (c) {
    case TargetClass::Humanoid: return "humanoid";
    case TargetClass::PartialHumanoid: return "partial humanoid";
    case TargetClass::NotHumanoid: return "not a humanoid";
    case TargetClass::ManyLegged: return "quadruped or many-legged";
    case TargetClass::NoSkeleton: return "no skeleton";
  }
  return "?";
}

int legsOnTheGround(const Skeleton& skeleton) {
  const std::size_t n = skeleton.jointCount();
  if (n < 2 || !skeleton.validate().empty()) return 0;
  const std::vector<glm::mat4> model = skeleton.restModelMatrices();
  std::vector<int> children(n, 0);
  for (std::size_t j = 0; j < n; ++j)
    if (skeleton.parents[j] >= 0) ++children[static_cast<std::size_t>(skeleton.parents[j])];
  // The ground is the lowest end joint (a root node at the origin, under the body, is not).
  float lowest = std::numeric_limits<float>::infinity(), highest = -lowest;
  for (std::size_t j = 0; j < n; ++j) {
    highest = std::max(highest, model[j][3].y);
    if (children[j] == 0 && skeleton.parents[j] >= 0) lowest = std::min(lowest, model[j][3].y);
  }
  const float height = highest - lowest;
  if (!std::isfinite(height) || !(height > 0.0f)) return 0;
  std::set<int> legs;
  for (std::size_t j = 0; j < n; ++j) {
    // An end on the ground (a lone root, e.g. a mesh's own node, is no limb).
    if (children[j] != 0 || skeleton.parents[j] < 0 || model[j][3].y - lowest > 0.05f * height) continue;
    int top = static_cast<int>(j);
    while (top >= 0 && model[static_cast<std::size_t>(top)][3].y - lowest <= 0.25f * height)
      top = skeleton.parents[static_cast<std::size_t>(top)];
    if (top >= 0) legs.insert(top);  // the limb's first joint above a quarter of the height
  }
  return static_cast<int>(legs.size());
}

TargetCheck checkRetargetTarget(const Asset& asset, const JointMap& map, bool needsMesh) {
  TargetCheck c;
  const Skeleton& s = asset.skeleton;
  const bool skinned = std::any_of(asset.meshes.begin(), asset.meshes.end(), [](const Mesh& m) { return m.skinned; });
  if (s.jointCount() == 0) {
    c.kind = TargetClass::NoSkeleton;
    c.reason = "no skeleton (no joint)";
    return c;
  }
  if (needsMesh && !skinned) {
    c.kind = TargetClass::NoSkeleton;
    c.reason = asset.meshes.empty() ? "no skeleton: no mesh at all, so nothing would move"
                                    : "no skeleton: none of its " + std::to_string(asset.meshes.size()) +
                                          " meshes is skinned to a joint (" + std::to_string(s.jointCount()) +
                                          " nodes), so nothing would move";
    return c;
  }
  for (Bone b : kMinimumHumanoid)
    if (map.joint(b) < 0) c.missing.push_back(b);
  c.groundLegs = legsOnTheGround(s);
  if (c.groundLegs >= 4) {
    c.kind = TargetClass::ManyLegged;
    c.reason = "a quadruped or many-legged body: " + std::to_string(c.groundLegs) +
               " legs reach the ground at rest, where a humanoid motion drives two";
    return c;
  }
  if (!c.missing.empty()) {
    // Most of the minimum missing: a prop or a machine with a skin, not a humanoid at all.
    c.kind = 2 * c.missing.size() > std::size(kMinimumHumanoid) ? TargetClass::NotHumanoid : TargetClass::PartialHumanoid;
    std::string names;
    for (Bone b : c.missing) names += (names.empty() ? "" : ", ") + std::string(boneName(b));
    c.reason = std::string(c.kind == TargetClass::NotHumanoid ? "not a humanoid" : "not a full humanoid") +
               ": its joint map lacks " + names;
  }
  return c;
}

}  // namespace marionette::retarget
