// A whole character profile guessed from the asset: the body's joints (through the
// joint map), the face and the clips, each field with the note of how it was found.
#include "profile_guess.hpp"

#include <tuple>

#include "limb_guess.hpp"
#include "joint_map_detail.hpp"

namespace marionette::profile_detail {

void guessBodyJoints(const Asset& asset, const Tree& t, CharacterProfile& p, Notes& notes) {
  const JointGuess j = guessJoints(asset, t);
  auto set = [&](const char* field, std::string& out, int joint, const std::string& how) {
    out = t.name(joint);
    notes.emplace_back(field, std::string(field) + ": " + (joint >= 0 ? inQuotes(out) + " (" + how + ")"
                                                                    : "none" + (how.empty() ? "" : " (" + how + ")")));
  };
  set("hips", p.hips, j.hips, j.hipsHow);
  p.spine = spineBetween(t, j.hips, j.neck);
  notes.emplace_back("spine", "spine: " + (p.spine.empty() ? std::string("none") : joined(p.spine)) +
                                  (j.hips >= 0 && j.neck >= 0 ? " (path from the hips to the neck)" : ""));
  set("neck", p.neck, j.neck, j.neckHow);
  set("head", p.head, j.head, j.headHow);
  set("leftEye", p.leftEye, j.leftEye, j.leftEyeHow);
  set("rightEye", p.rightEye, j.rightEye, j.rightEyeHow);
  set("jaw", p.jaw, j.jaw, j.jawHow);
  guessLimbs(asset, t, BodyChain{j.hips, j.neck, j.head}, p, notes);
}

Guess guess(const Asset& asset) {
  Guess g;
  CharacterProfile& p = g.profile;
  const Tree t(asset.skeleton);
  guessBodyJoints(asset, t, p, g.notes);
  // One humanoid: where the guessed joint map names a body joint (it starts from the guess
  // above, takes a VRM humanoid map first and settles the hips by topology), the profile
  // takes it; the name guess only fills what the map leaves out (a VRM file that lists no
  // spine bones: the path from the hips to the neck).
  const retarget::JointMapResult map = retarget::joint_map_detail::guessFromBody(asset, t, &p, &g.notes);
  CharacterProfile fromMap;
  setProfileJoints(fromMap, map.map, asset.skeleton);
  auto take = [&](const char* field, std::string& mine, const std::string& theirs) {
    if (theirs.empty() || theirs == mine) return;
    g.notes.emplace_back(field, std::string(field) + ": " + inQuotes(theirs) + ", not " + (mine.empty() ? "none" : inQuotes(mine)) +
                                    " (the joint map's)");
    mine = theirs;
  };
  take("hips", p.hips, fromMap.hips);
  take("neck", p.neck, fromMap.neck);
  take("head", p.head, fromMap.head);
  take("leftEye", p.leftEye, fromMap.leftEye);
  take("rightEye", p.rightEye, fromMap.rightEye);
  take("jaw", p.jaw, fromMap.jaw);
  if (!fromMap.spine.empty() && fromMap.spine != p.spine) {
    g.notes.emplace_back("spine", "spine: " + joined(fromMap.spine) + " (the joint map's)");
    p.spine = fromMap.spine;
  }
  const std::tuple<const char*, Limb CharacterProfile::*> limbs[] = {{"leftLeg", &CharacterProfile::leftLeg},
                                                                     {"rightLeg", &CharacterProfile::rightLeg},
                                                                     {"leftArm", &CharacterProfile::leftArm},
                                                                     {"rightArm", &CharacterProfile::rightArm}};
  for (const auto& [field, limb] : limbs) {
    take(field, (p.*limb).upper, (fromMap.*limb).upper);
    take(field, (p.*limb).lower, (fromMap.*limb).lower);
    take(field, (p.*limb).end, (fromMap.*limb).end);
  }
  take("leftToe", p.leftToe, fromMap.leftToe);
  take("rightToe", p.rightToe, fromMap.rightToe);
  guessFace(asset, p, g.notes);
  guessFacs(asset, p, g.notes);
  guessVisemes(asset, p, g.notes);
  guessClips(asset, p, g.notes);
  return g;
}

}  // namespace marionette::profile_detail
