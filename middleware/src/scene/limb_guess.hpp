// Internal to the character-profile code: finding the legs, arms and toes of a
// skeleton (VRM humanoid map, then names, then the shape of an unnamed
// skeleton), and checking left and right against the rest pose.
#pragma once
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "marionette/io/asset.hpp"
#include "marionette/scene/character_profile.hpp"
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

// "upper 'A', lower 'B', end none": a limb for notes.
[[nodiscard]] std::string describeLimb(const Limb& l);

}  // namespace marionette::profile_detail
