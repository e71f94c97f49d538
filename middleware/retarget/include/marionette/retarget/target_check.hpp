// Whether a character can play a humanoid motion, and if not why (the retarget command
// refuses what it cannot serve instead of writing a file of what happened to map):
//  - no skeleton: no joint, or (where the output needs a mesh) no mesh skinned to one;
//  - a quadruped or other many-legged body: four or more legs reach the ground at rest;
//  - a partial humanoid: the minimum humanoid (hips, head, upper and lower arms and legs)
//    not all mapped (hands and feet may be absent: some rigs have none); not a humanoid
//    where most of it is missing (a prop or a machine with a skin);
//  - a humanoid.
// Offline (command time; allocates).
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "marionette/asset/asset.hpp"
#include "marionette/rig/joint_map.hpp"

namespace marionette::retarget {

enum class TargetClass : std::uint8_t { Humanoid, PartialHumanoid, NotHumanoid, ManyLegged, NoSkeleton };
// "humanoid", "partial humanoid", "not a humanoid", "quadruped or many-legged", "no skeleton"
[[nodiscard]] std::string_view targetClassName(TargetClass c) noexcept;

struct TargetCheck {
  TargetClass kind = TargetClass::Humanoid;
  std::string reason;            // one line, empty for a humanoid
  std::vector<Bone> missing;     // bones of the minimum humanoid the map lacks
  int groundLegs = 0;            // separate limbs whose ends touch the ground at rest
};

// `needsMesh`: the output is the character itself (glTF), so a mesh must be skinned to it.
[[nodiscard]] TargetCheck checkRetargetTarget(const Asset& asset, const JointMap& map, bool needsMesh);

// Separate limbs whose ends lie on the ground at rest (within 5 % of the skeleton's height
// of its lowest end joint): ends are grouped by the first joint above them that is higher than
// a quarter of the height, so that a foot's toe and heel ends count as one leg.
[[nodiscard]] int legsOnTheGround(const Skeleton& skeleton);

}  // namespace marionette::retarget
