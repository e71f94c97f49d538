// Internal to the character-profile code: finding the legs, arms and toes of a
// skeleton (VRM humanoid map, then names, then the shape of an unnamed
// skeleton), and checking left and right against the rest pose.
#pragma once
#include <array>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "marionette/asset/asset.hpp"
#include "marionette/rig/character_profile.hpp"
#include "profile_skeleton.hpp"

namespace marionette::profile_detail {

// The body chain already found (tree indices, -1 when unknown).
struct BodyChain {
  int hips = -1, neck = -1, head = -1;
};

// Model-space rest positions, one per tree joint (malformed skeletons tolerated).
[[nodiscard]] std::vector<glm::vec3> restPositions(const Skeleton& s, const Tree& t);

// Fills p.leftLeg ... p.rightToe, with notes tagged leftLeg, rightLeg, leftArm,
// rightArm, leftToe, rightToe, and one tagged "sides" (sidesNote).
void guessLimbs(const Asset& asset, const Tree& t, const BodyChain& body, CharacterProfile& p, Notes& notes);

// "sides: ..." — whether the joints the profile calls left are on the
// character's left in the rest pose, and how the facing was found.
[[nodiscard]] std::string sidesNote(const Tree& t, const std::vector<glm::vec3>& rest, const BodyChain& body,
                                    const CharacterProfile& p);

// A leg by tree index (-1 where absent), for restSide.
struct LegJoints {
  int upper = -1, lower = -1, end = -1, toe = -1;
};

// Where joint `a` lies from joint `b` in the rest pose, as the character sees it:
// +1 on its left, -1 on its right, 0 when the rest pose cannot tell (also when
// neither toes nor knees show the facing). The facing is found as for the
// profile's sides (toes, else knees); `facing`, when
// given, gets its text ("it faces +Z, from the toes; its left is +X").
[[nodiscard]] int restSide(const std::vector<glm::vec3>& rest, const BodyChain& body,
                           const std::array<LegJoints, 2>& legs, int a, int b, std::string* facing = nullptr);

// "upper 'A', lower 'B', end none": a limb for notes.
[[nodiscard]] std::string describeLimb(const Limb& l);

}  // namespace marionette::profile_detail
