// libFuzzer target: character profiles (JSON, scene/character_profile.hpp), read by
// loadCharacterProfile from a temporary file for each of the real characters the
// project's profiles are written for. Contract: no crash; every diagnostic names the
// file; whatever the file says, the profile holds only names the asset has ("" for
// none): joints, morph targets with amounts in [0, 1], clips. Built by scripts/fuzz.
#include <algorithm>

#include "fuzz_support.hpp"
#include "marionette/rig/character_profile.hpp"

namespace {

using namespace marionette;
using fuzz::require;

void checkProfile(const CharacterProfile& p, const Asset& a) {
  auto joint = [&](const std::string& n) { require(n.empty() || a.skeleton.findJoint(n) >= 0, "unknown joint kept"); };
  auto clip = [&](const std::string& n) {
    require(n.empty() || std::any_of(a.clips.begin(), a.clips.end(), [&](const Clip& c) { return c.name == n; }),
            "unknown clip kept");
  };
  auto morphs = [&](const std::map<std::string, std::vector<FaceMorph>>& table) {
    for (const auto& [key, list] : table)
      for (const FaceMorph& m : list) {
        require(std::find(a.morphTargets.begin(), a.morphTargets.end(), m.morph) != a.morphTargets.end(),
                "unknown morph target kept");
        require(m.amount >= 0.0f && m.amount <= 1.0f, "morph amount outside [0, 1]");
      }
  };
  for (const std::string* n : {&p.hips, &p.neck, &p.head, &p.leftEye, &p.rightEye, &p.jaw, &p.leftToe, &p.rightToe})
    joint(*n);
  for (const std::string& n : p.spine) {
    require(!n.empty(), "empty spine joint");
    joint(n);
  }
  for (const Limb* l : {&p.leftLeg, &p.rightLeg, &p.leftArm, &p.rightArm}) {
    joint(l->upper);
    joint(l->lower);
    joint(l->end);
  }
  morphs(p.face);
  morphs(p.visemes);
  for (const std::string* n : {&p.idle, &p.walk, &p.run}) clip(*n);
  for (const auto& [lexeme, name] : p.gestures) {
    require(!lexeme.empty() && !name.empty(), "empty gesture");
    clip(name);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fuzz::writeInput(data, size, "in.profile.json");
  for (const Asset& asset : fuzz::realCharacters()) {
    const CharacterProfileResult r = loadCharacterProfile(path, asset);
    require(fuzz::allName(r.diagnostics, path), "a diagnostic does not name the file");
    checkProfile(r.profile, asset);  // on an error too: the guess stands in
  }
  return 0;
}
