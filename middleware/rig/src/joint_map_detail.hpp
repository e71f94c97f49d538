// Internal to the joint-map code: the canonical names and the consistency checks
// that both a map read from a file (joint_map.cpp) and a guessed map
// (joint_map_guess.cpp) go through.
#pragma once
#include <array>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "marionette/rig/joint_map.hpp"
#include "marionette/skeleton/skeleton.hpp"
#include "marionette/asset/asset.hpp"
#include "marionette/rig/character_profile.hpp"
#include "profile_skeleton.hpp"

namespace marionette::retarget::joint_map_detail {

// The canonical names, by Bone and by Chain (boneName, chainName).
inline constexpr std::array<std::string_view, kBoneCount> kBoneNames = {
    "hips",         "head",         "leftEye",      "rightEye",     "jaw",          "leftShoulder",
    "leftUpperArm", "leftLowerArm", "leftHand",     "rightShoulder", "rightUpperArm", "rightLowerArm",
    "rightHand",    "leftUpperLeg", "leftLowerLeg", "leftFoot",     "leftToes",     "rightUpperLeg",
    "rightLowerLeg", "rightFoot",   "rightToes"};
inline constexpr std::array<std::string_view, kChainCount> kChainNames = {
    "spine",      "neck",      "leftThumb",   "leftIndex",   "leftMiddle",  "leftRing",
    "leftLittle", "rightThumb", "rightIndex", "rightMiddle", "rightRing", "rightLittle"};

inline std::size_t at(Bone b) { return static_cast<std::size_t>(b); }
inline std::size_t at(Chain c) { return static_cast<std::size_t>(c); }

// An entry of a map: a bone, or joint k of a chain.
struct Entry {
  int bone = -1, chain = -1, k = -1;
};
// "leftUpperArm", "spine[1]": an entry for messages.
[[nodiscard]] std::string entryName(const Entry& e);

// Drops every later mention of a joint already mapped (bones first, in enum
// order, then chains), so that a map never names a joint twice; calls `dropped`
// with the joint, the entry that keeps it and the one that loses it (its index
// in the chain before any drop).
template <class F>
void dropDuplicates(JointMap& m, F&& dropped) {
  std::map<int, Entry> owner;
  for (int b = 0; b < kBoneCount; ++b) {
    int& j = m.bones[static_cast<std::size_t>(b)];
    if (j < 0) continue;
    const Entry e{b, -1, -1};
    if (auto [it, fresh] = owner.emplace(j, e); !fresh) dropped(j, it->second, e), j = -1;
  }
  for (int c = 0; c < kChainCount; ++c) {
    auto& chain = m.chains[static_cast<std::size_t>(c)];
    std::vector<int> kept;
    for (std::size_t k = 0; k < chain.size(); ++k) {
      const Entry e{-1, c, static_cast<int>(k)};
      if (auto [it, fresh] = owner.emplace(chain[k], e); fresh) kept.push_back(chain[k]);
      else dropped(chain[k], it->second, e);
    }
    chain = std::move(kept);
  }
}

// The required bones the map lacks, comma-separated; "" when none.
[[nodiscard]] std::string missingRequired(const JointMap& m);

// In the canonical set but absent from some real skeletons (CesiumMan has no
// clavicles, RobotExpressive and pirouette.bvh no toes): a file must say "" or
// [] for them, so that an absence is a decision, not an oversight.
inline constexpr Bone kExpectedBones[] = {Bone::LeftShoulder, Bone::RightShoulder, Bone::LeftToes, Bone::RightToes};
inline constexpr Chain kExpectedChains[] = {Chain::Spine, Chain::Neck};

struct Problem {
  Entry entry;
  std::string message;
};

// What the topology and the rest pose say against a map: each limb joint below
// the one before it, the legs and arms below the hips, the spine between the
// hips and the neck and not above the legs (turning a spine joint must not turn
// the legs), the neck above the head, eyes and jaw below it, fingers below the
// hand, and left joints on the character's left of the right ones.
[[nodiscard]] std::vector<Problem> topologyProblems(const JointMap& m, const profile_detail::Tree& t, const Skeleton& s);

// guessJointMap's work, given the skeleton's tree and, when the caller has guessed them
// already (the profile guess), the body joints by name and their notes (nullptr: guessed here).
[[nodiscard]] JointMapResult guessFromBody(const Asset& asset, const profile_detail::Tree& t, const CharacterProfile* body,
                                           const profile_detail::Notes* found);

}  // namespace marionette::retarget::joint_map_detail
