// A character profile: what the behavior controllers need to know about an
// asset that its file does not say: which joints are the spine, neck, head,
// eyes and jaw; which morph targets make each facial expression (BML face
// lexemes and FACS action units); which clips are idle, walk and run, and
// which clips are gestures. Read from a JSON file per asset (assets/profiles/),
// or guessed from joint, morph and clip names when there is none.
#pragma once
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "marionette/rig/facs.hpp"
#include "marionette/animation/blend_space.hpp"
#include "marionette/core/diagnostic.hpp"
#include "marionette/asset/asset.hpp"
#include "marionette/core/file_reader.hpp"
#include "marionette/rig/gesture_vocabulary.hpp"
#include "marionette/rig/joint_map.hpp"

namespace marionette {

// One morph target an expression moves, and its weight at full expression.
struct FaceMorph {
  std::string morph;   // a name in Asset::morphTargets
  float amount = 1.0f; // in [0, 1]
};

// How one FACS unit ("AU12", "AU45_L") shows on this character when it has no AU morph of
// that name in `face` (rig/facs.hpp): morphs, or eyelid and brow joints, and where they came
// from ("ARKit blendshapes", "VRM expression 'joy'", "the profile's facs map", "eyelid joints").
struct FacsJointMove {
  std::string joint;  // a joint of the skeleton
  FacsJointRule rule;
};
struct FacsMapping {
  std::vector<FaceMorph> morphs;
  std::vector<FacsJointMove> joints;
  std::string source;
};

// A leg or an arm as three joints by name, "" for any the character lacks. Leg:
// thigh, shin, foot (the ankle). Arm: upper arm, forearm, hand (the wrist).
// `lower` descends from `upper`; an arm's `end` descends from `lower`, a leg's
// usually does too (RobotExpressive's feet are IK targets under the root).
struct Limb {
  std::string upper, lower, end;
};

// Idle life the character has from its creation (a profile's "idleLife"; behavior/idle_life.hpp):
// blinking and breathing, each with its parameters (unset: the emitter's defaults).
struct IdleLifeProfile {
  bool blink = false, breathing = false;
  std::optional<float> blinkMeanInterval, blinkVariation;    // seconds; coefficient of variation
  std::optional<float> breathsPerMinute, breathingAmplitude;  // degrees
};

struct CharacterProfile {
  // The body's joints by name in the character's skeleton; "" when the character has none.
  // They come from the character's joint map (setProfileJoints), the one description of its
  // humanoid, unless a profile file lists them itself (the older inline form).
  std::string hips, neck, head, leftEye, rightEye, jaw;
  std::vector<std::string> spine;  // from the hips' child up to the chest, hips excluded
  // Left and right are the character's own.
  Limb leftLeg, rightLeg, leftArm, rightArm;
  std::string leftToe, rightToe;  // below the foot; "" when absent
  // BML faceLexeme names (SMILE, RAISE_BROWS, ...) and FACS units ("AU12") to morphs.
  std::map<std::string, std::vector<FaceMorph>> face;
  // FACS units to what shows them when `face` has no morph of the unit's name: AU-named
  // morphs, else ARKit blendshapes, else VRM expressions, else the profile's "facs" map, else
  // eyelid and brow joints (guessFacs; docs/controllers.md, "FACS on any face").
  std::map<std::string, FacsMapping> facs;
  // Lip-sync channels (speech/lipsync.hpp names: "PP", "aa", "vrm_aa", "jawOpen", ...) to morphs.
  std::map<std::string, std::vector<FaceMorph>> visemes;
  // Clip names of the rig; "" when absent.
  std::string idle, walk, run;
  // BML gesture lexemes to clip names (BEAT -> "ThumbsUp", ...).
  std::map<std::string, std::string> gestures;
  // Blend spaces by clip names (a profile's "blendSpaces"; the Rig makes them: Rig::blendSpaces).
  std::vector<BlendSpaceDefinition> blendSpaces;
  // Authored animation events by clip name, beside the clip's own (Clip::events):
  // the profile's "events" (docs/character-profiles.md, docs/animation-events.md).
  std::map<std::string, std::vector<ClipEvent>> events;
  // The character's height in metres when it stands life size (a profile's "lifeHeight", in
  // [0.05, 20]): for a file whose own size is not the character's (RobotExpressive's is 4.46 m
  // tall). Never guessed: nothing when the profile does not say (docs/authoring.md).
  std::optional<float> lifeHeight;
  // Voice names in this character's BML to the synthesizer's ("openmary": "en-us"; "default":
  // its voice when a <speech> names none, or one the synthesizer lacks): a profile's "voices",
  // keys lower case (speech::withVoiceNames), applied before the scene's.
  std::map<std::string, std::string> voices;
  // Other realizers' gesture names to procedural lexemes, looked up before the shipped
  // vocabulary (a profile's "gestureVocabulary": rig/gesture_vocabulary.hpp).
  GestureVocabulary gestureVocabulary;
  // Blinking and breathing from the character's creation (a profile's "idleLife").
  IdleLifeProfile idleLife;
  // One line per guess made (what was found, or what was missing), for logs and --stats.
  std::vector<std::string> notes;
};

struct CharacterProfileResult {
  CharacterProfile profile;
  Diagnostics diagnostics;  // each naming the file, line:column where known, and the field
};

// Names the body's joints from a joint map (rig/joint_map.hpp): hips, spine, neck (the
// neck chain's first joint), head, eyes, jaw, legs (upper leg, lower leg, foot), arms (upper
// arm, forearm, hand) and toes. The other fields are left as they are.
void setProfileJoints(CharacterProfile& profile, const retarget::JointMap& map, const Skeleton& skeleton);

// Reads a profile JSON file for `asset`. Names that the asset lacks (joint,
// morph, clip) are warnings naming the field and the name; fields the file
// leaves out are guessed as guessCharacterProfile does (with a note). The body's
// joints come from the joint map the file names ("jointMap", relative to the file;
// docs/character-profiles.md), else from the file's "joints" and "limbs", else from
// the guessed joint map.
// Where the installed profiles are, in the order they are searched: $MARIONETTE_PROFILES,
// share/marionette/profiles beside `binaryFolder`'s parent (a program's or library's
// folder, installed), then `sourceFolder` (the source tree's assets/profiles). Empty
// arguments are left out.
[[nodiscard]] std::vector<std::string> shippedProfileFolders(const std::string& binaryFolder,
                                                             const std::string& sourceFolder);
struct ProfileMatch {
  std::string file;
  CharacterProfile profile;
};
// The installed profile of a known asset: the file named after the asset's file
// (RobotExpressive.glb: RobotExpressive.json) in the first folder that has one that loads
// for this asset without a warning. Nothing when none does (the profile is then guessed).
// `files`: where the folders are read (empty: the disk); the web build's are built in.
[[nodiscard]] std::optional<ProfileMatch> findShippedProfile(const Asset& asset, const std::vector<std::string>& folders,
                                                               const FileReader& files = {});

// `files`: where the profile and its joint map are read (core/file_reader.hpp; empty: the disk).
[[nodiscard]] CharacterProfileResult loadCharacterProfile(const std::string& path, const Asset& asset,
                                                          const FileReader& files = {});

// Guesses a profile from the asset alone. The body's joints are guessJointMap's;
// that guess reads joint names in the common conventions
// (Mixamo, VRM/J_Bip, Blender ".L/.R", CMU BVH, Pab), checked against the
// topology (the head is a descendant of the neck, which descends from the
// hips; a limb's joints descend from one another); limbs of unnamed skeletons
// from their shape, sides from the rest pose; expressions from morph names;
// locomotion clips from clip names.
[[nodiscard]] CharacterProfile guessCharacterProfile(const Asset& asset);

}  // namespace marionette
