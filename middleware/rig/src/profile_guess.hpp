// Internal to the character-profile code: the guess of a whole profile from an
// asset (joints by name and topology, face and visemes from morph names and VRM
// expressions, clips and gestures from clip names), with a note per field. The
// loader falls back on it for what a profile file leaves out.
#pragma once
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "marionette/asset/asset.hpp"
#include "marionette/rig/character_profile.hpp"
#include "profile_skeleton.hpp"

namespace marionette::profile_detail {

// The guessed profile and its field-tagged notes (the loader keeps those of the
// fields the file leaves out).
struct Guess {
  CharacterProfile profile;
  Notes notes;
};

// Everything guessed from the asset alone; the body's joints from guessJointMap.
[[nodiscard]] Guess guess(const Asset& asset);

// The body's joints by name and topology (hips, spine, neck, head, eyes, jaw, limbs,
// toes), each with a note tagged by its field: where the joint-map guess starts
// (joint_map_guess.cpp), before it settles the hips and adds clavicles and fingers.
void guessBodyJoints(const Asset& asset, const Tree& t, CharacterProfile& p, Notes& notes);

// ---- Joints (profile_guess_joints.cpp) ---------------------------------------

struct JointGuess {
  int hips = -1, neck = -1, head = -1, leftEye = -1, rightEye = -1, jaw = -1;
  std::string hipsHow, neckHow, headHow, leftEyeHow, rightEyeHow, jawHow;
};

// Hips, neck, head, eyes and jaw: the VRM humanoid map, else names, else topology.
[[nodiscard]] JointGuess guessJoints(const Asset& asset, const Tree& t);

// Joints on the path below `hips` down to `neck`, both excluded, in hips-to-neck order.
[[nodiscard]] std::vector<std::string> spineBetween(const Tree& t, int hips, int neck);

// ---- Face (profile_guess_face.cpp) -------------------------------------------

// Fills p.face with notes tagged "face": VRM expressions first, then morph names.
void guessFace(const Asset& asset, CharacterProfile& p, Notes& notes);

// Fills p.facs with notes tagged "facs": each FACS unit and side of rig/facs.hpp's table
// by AU-named morphs, else ARKit blendshapes, else VRM expressions, else eyelid and brow joints.
void guessFacs(const Asset& asset, CharacterProfile& p, Notes& notes);

// The lip-sync channels a character's morphs can show (speech/lipsync.hpp):
// the file's VRM mouth shapes first (A I U E O, both VRM versions), then a full
// set of OVR viseme morphs ("viseme_PP", ...), then an ARKit-style jaw opening.
void guessVisemes(const Asset& asset, CharacterProfile& p, Notes& notes);

// The BML face lexemes and emotions the face guess knows, to check a file's face keys.
[[nodiscard]] const std::set<std::string_view>& faceLexemes();

// ---- Clips (profile_guess_clips.cpp) -----------------------------------------

// Fills p.idle, p.walk, p.run and p.gestures from clip names, with notes tagged
// idle, walk, run and gestures.
void guessClips(const Asset& asset, CharacterProfile& p, Notes& notes);

}  // namespace marionette::profile_detail
