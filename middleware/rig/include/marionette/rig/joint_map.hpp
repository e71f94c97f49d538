// Joint maps: a skeleton's joints named by a canonical humanoid set, so that a
// motion made for one skeleton can drive another (retargeter.hpp). Canonical
// names are the VRM humanoid bone names ("hips", "leftUpperArm", ...). The
// spine, the neck and each finger are chains (any number of joints, root to
// tip), because skeletons differ there most: CMU has LowerBack/Spine/Spine1,
// RobotExpressive Abdomen/Torso, Godette tummy/chest.
// Sources of a map: a JSON file (assets/jointmaps/*.json), the file's own VRM
// humanoid map, or a guess from names and topology (the character profile's
// guess plus clavicles and fingers). Command time only.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "marionette/core/diagnostic.hpp"
#include "marionette/asset/asset.hpp"
#include "marionette/core/file_reader.hpp"

namespace marionette::retarget {

// Single canonical joints. Left and right are the character's own.
enum class Bone : std::uint8_t {
  Hips, Head, LeftEye, RightEye, Jaw,
  LeftShoulder, LeftUpperArm, LeftLowerArm, LeftHand,     // LeftShoulder: the clavicle
  RightShoulder, RightUpperArm, RightLowerArm, RightHand,
  LeftUpperLeg, LeftLowerLeg, LeftFoot, LeftToes,
  RightUpperLeg, RightLowerLeg, RightFoot, RightToes,
};
inline constexpr int kBoneCount = 21;
// Chains, root to tip: the spine (above the hips, below the neck), the neck (below
// the head), and each finger (from its first joint past the hand).
enum class Chain : std::uint8_t {
  Spine, Neck,
  LeftThumb, LeftIndex, LeftMiddle, LeftRing, LeftLittle,
  RightThumb, RightIndex, RightMiddle, RightRing, RightLittle,
};
inline constexpr int kChainCount = 12;

// "hips", "head", "leftEye", ..., "leftShoulder", "leftUpperArm", "leftLowerArm",
// "leftHand", ..., "leftUpperLeg", "leftLowerLeg", "leftFoot", "leftToes", ...
[[nodiscard]] std::string_view boneName(Bone bone) noexcept;
[[nodiscard]] std::optional<Bone> boneFromName(std::string_view name) noexcept;
// "spine", "neck", "leftThumb", "leftIndex", "leftMiddle", "leftRing", "leftLittle", ...
[[nodiscard]] std::string_view chainName(Chain chain) noexcept;
[[nodiscard]] std::optional<Chain> chainFromName(std::string_view name) noexcept;

struct JointMap {
  std::array<int, kBoneCount> bones;            // joint index per Bone, -1 when absent
  std::array<std::vector<int>, kChainCount> chains;  // joint indices root to tip; empty when absent
  std::vector<std::string> notes;               // how each entry was found (file, VRM map, name, topology)

  JointMap() { bones.fill(-1); }
  [[nodiscard]] int joint(Bone b) const noexcept { return bones[static_cast<std::size_t>(b)]; }
  [[nodiscard]] const std::vector<int>& chain(Chain c) const noexcept { return chains[static_cast<std::size_t>(c)]; }
  // The canonical name of a joint of the skeleton ("spine[1]" for a chain's second joint), or "".
  [[nodiscard]] std::string canonicalName(int joint) const;
};

struct JointMapResult {
  JointMap map;
  Diagnostics diagnostics;  // each names the file, line:column where known, and the entry
};

// The bones a humanoid motion needs that `map` lacks (hips, head, upper and lower arms and
// legs, hands, feet), in canonical order.
[[nodiscard]] std::vector<Bone> missingRequiredBones(const JointMap& map);

// Reads a joint-map JSON file for a skeleton. Joint names must exist in the skeleton; "#N"
// names joint N (for skeletons without names, e.g. CesiumMan). Missing required bones
// (hips, head, upper/lower arms and legs, hands, feet) and joints mapped twice are warnings
// naming them; unknown keys and names the skeleton lacks too; so are clavicles, toes, spine
// and neck the file does not list ("" / [] says the skeleton has none), and what the topology
// or the rest pose contradicts (docs/joint-maps.md).
// `files`: where the map is read (core/file_reader.hpp; empty: the disk).
[[nodiscard]] JointMapResult loadJointMap(const std::string& path, const Asset& asset, const FileReader& files = {});
// The map from the asset alone: its VRM humanoid map when it has one, else names and topology.
// Ambiguities settled by topology are noted (CMU's "LeftShoulder" is the clavicle in one export
// and the upper arm in another; the hips are the joint the legs and the spine share). Missing
// required bones, duplicates and topology contradictions are warnings.
[[nodiscard]] JointMapResult guessJointMap(const Asset& asset);
// The map as JSON text in loadJointMap's format (joint names, or "#N" for unnamed joints).
[[nodiscard]] std::string jointMapJson(const JointMap& map, const Skeleton& skeleton);

// The joint-map file that fits an asset, among the *.json files of `folders` (e.g. the
// shipped share/marionette/jointmaps): the first that loads without a warning, so every
// joint it names exists, nothing required is left out and the topology agrees. The file
// named after the asset's file (RobotExpressive.glb: RobotExpressive.json) is tried first,
// then the rest in folder order and name order. Folders that do not exist are skipped;
// files that do not load are passed over. nullopt when none fits.
struct JointMapMatch {
  std::string file;
  JointMapResult result;
};
[[nodiscard]] std::optional<JointMapMatch> findJointMap(const Asset& asset, const std::vector<std::string>& folders);

// Where the shipped joint maps are looked for, in order: $MARIONETTE_JOINTMAPS when set, the
// installation's share/marionette/jointmaps (`binaryFolder` is the folder of the running
// program or library: bin/ or lib/; empty when unknown), then `sourceFolder` (the source
// tree's assets/jointmaps, for a program run from its build tree).
[[nodiscard]] std::vector<std::string> shippedJointMapFolders(const std::string& binaryFolder,
                                                              const std::string& sourceFolder);

}  // namespace marionette::retarget
