// The public character-profile functions: the guess as it is
// (profile_guess.hpp), and a profile file read against its asset, with the
// guess for what the file leaves out or gets wrong.
#include "marionette/core/text.hpp"
#include "marionette/core/text_file.hpp"
#include "marionette/rig/character_profile.hpp"
#include "marionette/speech/lipsync.hpp"
#include "marionette/speech/speech_service.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string_view>
#include <tuple>
#include <utility>

#include <nlohmann/json.hpp>

#include "marionette/rig/detail/json_places.hpp"
#include "limb_guess.hpp"
#include "profile_blend_spaces.hpp"
#include "profile_events.hpp"
#include "profile_guess.hpp"
#include "profile_skeleton.hpp"

namespace marionette {

namespace {
using Json = nlohmann::json;
using namespace profile_detail;
using json_detail::JsonPlaces;
using json_detail::JsonReaderBase;
using json_detail::parseJsonText;

// "AU12", "AU12L", "AU12_R": a FACS action unit, optionally one-sided.
bool isFacsUnit(const std::string& k) {
  if (k.size() < 3 || k[0] != 'A' || k[1] != 'U') return false;
  std::size_t i = 2;
  while (i < k.size() && isDigit(k[i])) ++i;
  if (i == 2 || i - 2 > 2) return false;
  if (i < k.size() && k[i] == '_') ++i;
  if (i < k.size() && (k[i] == 'L' || k[i] == 'R')) ++i;
  return i == k.size() && k.back() != '_';
}

class ProfileReader : JsonReaderBase {
 public:
  ProfileReader(const std::string& file, const std::string& text, const Asset& asset, const FileReader& files,
                Diagnostics& d)
      : JsonReaderBase(file, text, d, "ignored, its fields guessed"), asset_(asset), files_(files),
        tree_(asset.skeleton) {}

  void read(const Json& doc, CharacterProfile& p, const Guess& guessed) {
    unknownKeys(doc, "", {"jointMap", "joints", "limbs", "face", "visemes", "clips", "gestures", "events", "blendSpaces", "lifeHeight", "voices", "gestureVocabulary", "facs", "idleLife", "comment"});
    const Json& clips = section(doc, "clips");
    unknownKeys(clips, "/clips", {"idle", "walk", "run"});
    if (doc.contains("jointMap") && jointMap(doc["jointMap"], p)) {
      for (const char* key : {"joints", "limbs"})
        if (doc.contains(key))
          warn(std::string("/") + key, "ignored: the profile names a joint map (\"jointMap\"), the one description of the body's joints", true);
    } else {
      bodyJoints(doc, p, guessed);
    }

    if (!(doc.contains("face") && face(doc["face"], p))) p.face = guessed.profile.face, noteGuessed(guessed, "face");
    // The FACS table is always found from the face (a profile's "facs" only fills its gaps).
    p.facs = guessed.profile.facs;
    for (const auto& [field, line] : guessed.notes)
      if (field == "facs") notes_.push_back(line);
    if (doc.contains("facs")) facs(doc["facs"], p);
    if (!(doc.contains("visemes") && visemes(doc["visemes"], p)))
      p.visemes = guessed.profile.visemes, noteGuessed(guessed, "visemes");

    const std::pair<const char*, std::string CharacterProfile::*> clipFields[] = {
        {"idle", &CharacterProfile::idle}, {"walk", &CharacterProfile::walk}, {"run", &CharacterProfile::run}};
    for (const auto& [field, member] : clipFields) {
      if (auto n = clips.contains(field) ? name(clips[field], std::string("/clips/") + field, Kind::Clip) : std::nullopt)
        note(field, p.*member = *n);
      else
        p.*member = guessed.profile.*member, noteGuessed(guessed, field);
    }

    if (!(doc.contains("gestures") && gestures(doc["gestures"], p)))
      p.gestures = guessed.profile.gestures, noteGuessed(guessed, "gestures");
    if (doc.contains("events")) {
      const std::size_t n = readProfileEvents(doc["events"], asset_, p, [&](const std::string& at, const std::string& m,
                                                                          bool atKey) { warn(at, m, atKey); });
      notes_.push_back("events: " + std::to_string(n) + " on " + std::to_string(p.events.size()) + " clip(s) (profile)");
    }
    if (doc.contains("blendSpaces")) {
      const std::size_t n = readProfileBlendSpaces(doc["blendSpaces"], asset_, p, [&](const std::string& at, const std::string& m,
                                                                                    bool atKey) { warn(at, m, atKey); });
      notes_.push_back("blendSpaces: " + std::to_string(n) + " (profile)");
    }
    if (doc.contains("lifeHeight")) p.lifeHeight = lifeHeight(doc["lifeHeight"]);
    if (doc.contains("voices")) voices(doc["voices"], p);
    if (doc.contains("gestureVocabulary")) gestureVocabulary(doc["gestureVocabulary"], p);
    if (doc.contains("idleLife")) idleLife(doc["idleLife"], p.idleLife);
    p.notes = std::move(notes_);
  }

 private:
  enum class Kind { Joint, Morph, Clip };

  // "jointMap": a joint-map file (relative to the profile) names the body's joints. False
  // (with a warning) when it cannot be used: the joints are then read or guessed.
  bool jointMap(const Json& j, CharacterProfile& p) {
    if (!j.is_string() || j.get<std::string>().empty()) {
      warn("/jointMap", "expected the path of a joint-map file (a string); ignored, the joints read or guessed");
      return false;
    }
    const std::filesystem::path given = j.get<std::string>();
    const std::filesystem::path path = given.is_absolute() ? given : std::filesystem::path(file_).parent_path() / given;
    const retarget::JointMapResult map = retarget::loadJointMap(path.lexically_normal().generic_string(), asset_, files_);
    if (!map.diagnostics.ok()) {
      // One warning here, at "jointMap", with the map's own diagnostics in it (they name the
      // map's file): the profile still loads, with the joints read or guessed.
      std::string why;
      for (std::size_t i = 0; i < map.diagnostics.items.size() && i < 3; ++i)
        why += (i ? "; " : "") + map.diagnostics.items[i].format();
      if (map.diagnostics.items.size() > 3) why += "; ...";
      warn("/jointMap", "the joint map '" + given.string() + "' cannot be used (" + why + "); the joints read or guessed");
      return false;
    }
    setProfileJoints(p, map.map, asset_.skeleton);
    notes_.push_back("joints: from the joint map " + path.lexically_normal().string());
    // The map's warnings are about retargeting with it (a required bone the skeleton lacks,
    // an unsaid clavicle); they are checked where the map is read on its own (loadJointMap),
    // and recorded here.
    for (const Diagnostic& d : map.diagnostics.items) notes_.push_back("joint map: " + d.format());
    const std::pair<const char*, const Limb*> limbs[] = {
        {"leftLeg", &p.leftLeg}, {"rightLeg", &p.rightLeg}, {"leftArm", &p.leftArm}, {"rightArm", &p.rightArm}};
    for (const auto& [field, limb] : limbs)  // the map's own topology checks warn; the notes say what a leg's end is
      notes_.push_back(std::string(field) + ": " + describeLimb(*limb) + " (joint map)" +
                       checkLimb(*limb, field[std::string_view(field).size() - 3] == 'L'));
    notes_.push_back(sidesNote(tree_, restPositions(asset_.skeleton, tree_),
                               BodyChain{tree_.find(p.hips), tree_.find(p.neck), tree_.find(p.head)}, p));
    return true;
  }

  // The older inline form: "joints" and "limbs" in the profile itself, the guess for what they leave out.
  void bodyJoints(const Json& doc, CharacterProfile& p, const Guess& guessed) {
    const Json& joints = section(doc, "joints");
    unknownKeys(joints, "/joints", {"hips", "spine", "neck", "head", "leftEye", "rightEye", "jaw"});
    const std::pair<const char*, std::string CharacterProfile::*> jointFields[] = {
        {"hips", &CharacterProfile::hips}, {"neck", &CharacterProfile::neck},         {"head", &CharacterProfile::head},
        {"leftEye", &CharacterProfile::leftEye}, {"rightEye", &CharacterProfile::rightEye}, {"jaw", &CharacterProfile::jaw}};
    for (const auto& [field, member] : jointFields) {
      if (auto n = joints.contains(field) ? name(joints[field], std::string("/joints/") + field, Kind::Joint) : std::nullopt)
        note(field, p.*member = *n);
      else
        p.*member = guessed.profile.*member, noteGuessed(guessed, field);
    }
    if (auto s = joints.contains("spine") ? spine(joints["spine"]) : std::nullopt) {
      p.spine = std::move(*s);
    } else {
      // From the file's hips and neck when it names them: the guess may differ.
      p.spine = spineBetween(tree_, tree_.find(p.hips), tree_.find(p.neck));
      notes_.push_back("spine: " + (p.spine.empty() ? std::string("none") : joined(p.spine)) +
                       " (path from the hips to the neck; not in the profile)");
    }
    checkChain(p, joints);
    limbs(doc, p, guessed);
  }


  [[nodiscard]] bool exists(const std::string& n, Kind kind) const {
    switch (kind) {
      case Kind::Joint: return tree_.find(n) >= 0;
      case Kind::Morph: return std::find(asset_.morphTargets.begin(), asset_.morphTargets.end(), n) != asset_.morphTargets.end();
      case Kind::Clip:
        return std::any_of(asset_.clips.begin(), asset_.clips.end(), [&](const Clip& c) { return c.name == n; });
    }
    return false;
  }

  // A name of the asset at `pointer`: "" (none) is fine; a name the asset lacks is
  // cleared; a value that is no string is ignored (nullopt: the caller guesses it).
  std::optional<std::string> name(const Json& j, const std::string& pointer, Kind kind) {
    static const char* const what[] = {"joint", "morph target", "clip"};
    const char* w = what[static_cast<int>(kind)];
    if (!j.is_string()) {
      warn(pointer, std::string("expected a ") + w + " name (a string, \"\" for none); ignored");
      return std::nullopt;
    }
    std::string n = j.get<std::string>();
    if (!n.empty() && !exists(n, kind)) {
      warn(pointer, std::string("no ") + w + " named '" + n + "' in " + assetName() + "; cleared");
      return std::string();
    }
    return n;
  }

  std::optional<std::vector<std::string>> spine(const Json& j) {
    std::vector<std::string> out;
    if (!j.is_array()) {
      warn("/joints/spine", "expected an array of joint names; ignored");
      return std::nullopt;
    }
    for (std::size_t i = 0; i < j.size(); ++i) {
      const std::string pointer = "/joints/spine/" + std::to_string(i);
      if (!j[i].is_string() || j[i].get<std::string>().empty()) {
        warn(pointer, "expected a joint name; dropped");
      } else if (!exists(j[i].get<std::string>(), Kind::Joint)) {
        warn(pointer, "no joint named '" + j[i].get<std::string>() + "' in " + assetName() + "; dropped");
      } else {
        out.push_back(j[i].get<std::string>());
      }
    }
    notes_.push_back("spine: " + (out.empty() ? std::string("none") : joined(out)) + " (profile)");
    return out;
  }

  // The controllers assume head below neck below hips, and the spine between them
  // in order: say so when the file disagrees (its values are kept: the file rules).
  void checkChain(const CharacterProfile& p, const Json& joints) {
    const int hips = tree_.find(p.hips), neck = tree_.find(p.neck), head = tree_.find(p.head);
    auto at = [&](const char* field) { return std::string("/joints/") + field; };
    auto given = [&](const char* field) { return joints.contains(field); };
    if (neck >= 0 && head >= 0 && !tree_.above(neck, head) && (given("head") || given("neck")))
      warn(at(given("head") ? "head" : "neck"), "'" + p.head + "' is not below the neck '" + p.neck + "'");
    if (hips >= 0 && neck >= 0 && !tree_.above(hips, neck) && (given("neck") || given("hips")))
      warn(at(given("neck") ? "neck" : "hips"), "'" + p.neck + "' is not below the hips '" + p.hips + "'");
    for (const char* eye : {"leftEye", "rightEye", "jaw"}) {
      const std::string& v = eye[0] == 'l' ? p.leftEye : eye[0] == 'r' ? p.rightEye : p.jaw;
      const int j = tree_.find(v);
      if (head >= 0 && j >= 0 && !tree_.above(head, j) && given(eye))
        warn(at(eye), "'" + v + "' is not below the head '" + p.head + "'");
    }
    if (given("spine") && joints["spine"].is_array()) {
      int prev = hips;
      for (std::size_t i = 0; i < p.spine.size(); ++i) {
        const int j = tree_.find(p.spine[i]);
        const bool inOrder = (prev < 0 || tree_.above(prev, j)) && (neck < 0 || tree_.above(j, neck));
        if (!inOrder) {
          const Json& list = joints["spine"];
          std::size_t k = 0;  // its place in the file (dropped entries shift the indices)
          while (k < list.size() && !(list[k].is_string() && list[k].get<std::string>() == p.spine[i])) ++k;
          warn("/joints/spine/" + std::to_string(k),
               "'" + p.spine[i] + "' is not on the path from the hips to the neck, in order");
          break;
        }
        prev = j;
      }
    }
  }

  // The "limbs" section: per limb and per joint of a limb, what the file leaves
  // out is guessed; chains that do not hang together are warnings.
  void limbs(const Json& doc, CharacterProfile& p, const Guess& guessed) {
    const Json& section = this->section(doc, "limbs");
    unknownKeys(section, "/limbs", {"leftLeg", "rightLeg", "leftArm", "rightArm", "leftToe", "rightToe"});
    const std::pair<const char*, Limb CharacterProfile::*> limbFields[] = {{"leftLeg", &CharacterProfile::leftLeg},
                                                                           {"rightLeg", &CharacterProfile::rightLeg},
                                                                           {"leftArm", &CharacterProfile::leftArm},
                                                                           {"rightArm", &CharacterProfile::rightArm}};
    const std::pair<const char*, std::string Limb::*> jointsOfLimb[] = {
        {"upper", &Limb::upper}, {"lower", &Limb::lower}, {"end", &Limb::end}};
    for (const auto& [field, member] : limbFields) {
      const std::string where = std::string("/limbs/") + field;
      Limb& out = p.*member;
      out = guessed.profile.*member;
      if (!section.contains(field)) {
        noteGuessed(guessed, field);
        continue;
      }
      const Json& v = section[field];
      if (!v.is_object()) {
        warn(where, "expected an object {\"upper\", \"lower\", \"end\"} of joint names; ignored, guessed");
        noteGuessed(guessed, field);
        continue;
      }
      unknownKeys(v, where, {"upper", "lower", "end"});
      std::string leftOut;
      for (const auto& [key, part] : jointsOfLimb) {
        if (auto n = v.contains(key) ? name(v[key], where + "/" + key, Kind::Joint) : std::nullopt)
          out.*part = *n;
        else
          leftOut += (leftOut.empty() ? "" : ", ") + std::string(key);
      }
      const bool leg = field[std::string_view(field).size() - 3] == 'L';  // "...Leg"
      const std::string detached = checkLimb(out, leg, &v, where);
      notes_.push_back(std::string(field) + ": " + describeLimb(out) + " (profile" +
                       (leftOut.empty() ? "" : "; " + leftOut + " not in the profile, guessed") + ")" + detached);
    }
    const std::tuple<const char*, std::string CharacterProfile::*, const Limb*> toeFields[] = {
        {"leftToe", &CharacterProfile::leftToe, &p.leftLeg}, {"rightToe", &CharacterProfile::rightToe, &p.rightLeg}};
    for (const auto& [field, member, leg] : toeFields) {
      const std::string where = std::string("/limbs/") + field;
      if (auto n = section.contains(field) ? name(section[field], where, Kind::Joint) : std::nullopt) {
        note(field, p.*member = *n);
        const int toe = tree_.find(p.*member), foot = tree_.find(leg->end);
        if (toe >= 0 && foot >= 0 && !tree_.above(foot, toe))
          warn(where, "'" + p.*member + "' is not below the foot '" + leg->end + "'");
      } else {
        p.*member = guessed.profile.*member, noteGuessed(guessed, field);
      }
    }
    notes_.push_back(sidesNote(tree_, restPositions(asset_.skeleton, tree_),
                               BodyChain{tree_.find(p.hips), tree_.find(p.neck), tree_.find(p.head)}, p));
  }

  // The note on a limb whose leg ends elsewhere (an IK target under the root is fine); with
  // its place in the file (`given` at `where`), warnings where its joints do not descend from
  // one another. A joint map's limbs are checked by the map's reader: the note only.
  std::string checkLimb(const Limb& l, bool leg, const Json* given = nullptr, const std::string& where = {}) {
    const int u = tree_.find(l.upper), lo = tree_.find(l.lower), e = tree_.find(l.end);
    auto at = [&](const char* key, const char* other) { return where + "/" + (given->contains(key) ? key : other); };
    auto warn = [&](const char* key, const char* other, const std::string& message) {
      if (given) this->warn(at(key, other), message);
    };
    if (u >= 0 && lo >= 0 && !tree_.above(u, lo))
      warn("lower", "upper", "'" + l.lower + "' is not below the upper joint '" + l.upper + "'");
    const int before = lo >= 0 ? lo : u;
    if (before < 0 || e < 0 || tree_.above(before, e)) return {};
    const bool elsewhere = !tree_.above(e, before) && !(u >= 0 && tree_.above(e, u));
    if (leg && lo >= 0 && elsewhere)
      return "; '" + l.end + "' is not below '" + l.lower + "': the end point is its rest offset from the lower joint";
    warn("end", lo >= 0 ? "lower" : "upper",
         "'" + l.end + "' is not below the " + (lo >= 0 ? "lower" : "upper") + " joint '" + (lo >= 0 ? l.lower : l.upper) + "'");
    return {};
  }

  // False when the section is unusable (then it is guessed).
  bool face(const Json& j, CharacterProfile& p) {
    if (!j.is_object()) {
      warn("/face", "expected an object of LEXEME: [{\"morph\", \"amount\"}]; ignored");
      return false;
    }
    for (auto it = j.begin(); it != j.end(); ++it) {
      const std::string lexeme = it.key();
      const std::string where = "/face/" + JsonPlaces::escape(lexeme);
      if (!faceLexemes().count(lexeme) && !isFacsUnit(lexeme))
        warn(where, "'" + lexeme + "' is not a BML face lexeme, emotion or FACS unit (AUn); kept", true);
      if (std::vector<FaceMorph> morphs = morphList(*it, where); !morphs.empty()) p.face[lexeme] = std::move(morphs);
    }
    notes_.push_back("face: " + std::to_string(p.face.size()) + " expressions (profile)");
    return true;
  }

  // "facs": {"AU12": morphs, ...}: units the character shows by no AU, ARKit or VRM morph
  // (rig/facs.hpp); they take the place of eyelid and brow joints, not of those morphs.
  void facs(const Json& j, CharacterProfile& p) {
    if (!j.is_object()) {
      warn("/facs", "expected an object of AUn: [{\"morph\", \"amount\"}]; ignored");
      return;
    }
    int used = 0;
    for (auto it = j.begin(); it != j.end(); ++it) {
      const std::string where = "/facs/" + JsonPlaces::escape(it.key());
      const auto unit = parseFacsUnit(it.key());
      if (!unit) {
        warn(where, "'" + it.key() + "' is not a FACS unit (AUn, AUn_L, AUn_R); dropped");
        continue;
      }
      std::vector<FaceMorph> morphs = morphList(*it, where);
      if (morphs.empty()) continue;
      const std::string key = facsKey(unit->au, unit->side);
      auto found = p.facs.find(key);
      if (found != p.facs.end() && found->second.joints.empty()) {
        notes_.push_back("facs " + key + ": the profile's entry is not used, the face has " + found->second.source);
        continue;
      }
      p.facs[key] = {std::move(morphs), {}, "the profile's facs map"};
      ++used;
    }
    notes_.push_back("facs: " + std::to_string(used) + " units from the profile");
  }

  // False when the section is unusable (then it is guessed).
  bool visemes(const Json& j, CharacterProfile& p) {
    if (!j.is_object()) {
      warn("/visemes", "expected an object of CHANNEL: [{\"morph\", \"amount\"}]; ignored");
      return false;
    }
    for (auto it = j.begin(); it != j.end(); ++it) {
      const std::string channel = it.key();
      const std::string where = "/visemes/" + JsonPlaces::escape(channel);
      if (!speech::lipChannelFromName(channel)) {
        warn(where, "'" + channel + "' is not a lip-sync channel (" + lipChannelList() + "); dropped");
        continue;
      }
      if (std::vector<FaceMorph> morphs = morphList(*it, where); !morphs.empty()) p.visemes[channel] = std::move(morphs);
    }
    notes_.push_back("visemes: " + std::to_string(p.visemes.size()) + " channels (profile)");
    return true;
  }

  static std::string lipChannelList() {
    std::string out;
    for (int c = 0; c < speech::kLipChannelCount; ++c) out += (c ? ", " : "") + std::string(speech::lipChannelName(c));
    return out;
  }

  // A face or viseme entry: a list of {"morph", "amount"}, or one morph name (at full amount).
  std::vector<FaceMorph> morphList(const Json& entry, const std::string& where) {
    std::vector<FaceMorph> morphs;
    if (entry.is_string()) {
      if (auto n = name(entry, where, Kind::Morph); n && !n->empty()) morphs.push_back({*n, 1.0f});
    } else if (entry.is_array()) {
      for (std::size_t i = 0; i < entry.size(); ++i)
        if (auto m = faceMorph(entry[i], where + "/" + std::to_string(i))) morphs.push_back(std::move(*m));
    } else {
      warn(where, "expected a list of {\"morph\": NAME, \"amount\": 0..1}; dropped");
    }
    return morphs;
  }

  std::optional<FaceMorph> faceMorph(const Json& e, const std::string& where) {
    if (!e.is_object() || !e.contains("morph")) {
      warn(where, "expected {\"morph\": NAME, \"amount\": 0..1}; dropped");
      return std::nullopt;
    }
    unknownKeys(e, where, {"morph", "amount"});
    const Json& m = e["morph"];
    if (!m.is_string() || m.get<std::string>().empty()) {
      warn(where + "/morph", "expected a morph target name; dropped");
      return std::nullopt;
    }
    if (!exists(m.get<std::string>(), Kind::Morph)) {
      warn(where + "/morph", "no morph target named '" + m.get<std::string>() + "' in " + assetName() + "; dropped");
      return std::nullopt;
    }
    FaceMorph out{m.get<std::string>(), 1.0f};
    if (e.contains("amount")) {
      const Json& a = e["amount"];
      if (!a.is_number()) {
        warn(where + "/amount", "expected a number in [0, 1]; using 1");
      } else {
        const double v = a.get<double>();
        const double c = std::isnan(v) ? 1.0 : std::clamp(v, 0.0, 1.0);
        if (c != v) {
          std::ostringstream text;
          text << v;
          warn(where + "/amount", "amount " + text.str() + " is outside [0, 1]; clamped to " + (c == 0.0 ? "0" : "1"));
        }
        out.amount = static_cast<float>(c);
      }
    }
    return out;
  }

  // "lifeHeight": metres, finite, in [kMin, kMax]; anything else is a warning, and ignored.
  std::optional<float> lifeHeight(const Json& j) {
    constexpr double kMin = 0.05, kMax = 20.0;
    if (!j.is_number()) {
      warn("/lifeHeight", "expected the character's life-size height in metres (a number in [0.05, 20]); ignored");
      return std::nullopt;
    }
    const double v = j.get<double>();
    if (!std::isfinite(v) || v < kMin || v > kMax) {
      std::ostringstream text;
      text << v;
      warn("/lifeHeight", "height " + text.str() + " m is outside [0.05, 20] m; ignored");
      return std::nullopt;
    }
    std::ostringstream text;
    text << v;
    notes_.push_back("lifeHeight: " + text.str() + " m (profile)");
    return static_cast<float>(v);
  }

  // An object of non-empty names to non-empty strings ("voices", "gestureVocabulary"): its pairs,
  // each other entry a warning at its place; nothing (a warning) when it is not an object.
  std::vector<std::pair<std::string, std::string>> namePairs(const Json& j, const std::string& key, const char* expected,
                                                             const char* entry) {
    std::vector<std::pair<std::string, std::string>> out;
    if (!j.is_object()) {
      warn("/" + key, std::string("expected an object of ") + expected + "; ignored");
      return out;
    }
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (it.key().empty() || !it->is_string() || it->get<std::string>().empty()) {
        warn("/" + key + "/" + JsonPlaces::escape(it.key()), std::string("expected ") + entry + "; ignored", true);
        continue;
      }
      out.emplace_back(it.key(), it->get<std::string>());
    }
    return out;
  }

  // "voices": {"openmary": "en-us", "default": "en-gb"}; keys lower-cased (speech::voiceNameMap).
  void voices(const Json& j, CharacterProfile& p) {
    const auto pairs = namePairs(j, "voices", "VOICE NAME: voice (\"openmary\": \"en-us\")",
                                 "a non-empty voice name for a non-empty key");
    if (!j.is_object()) return;
    p.voices = speech::voiceNameMap(std::map<std::string, std::string>(pairs.begin(), pairs.end()));
    notes_.push_back("voices: " + std::to_string(p.voices.size()) + " (profile)");
  }

  // "gestureVocabulary": {"greet*": "WAVE", ...}: other realizers' names to procedural lexemes.
  void gestureVocabulary(const Json& j, CharacterProfile& p) {
    const auto pairs = namePairs(j, "gestureVocabulary", "PATTERN: procedural lexeme (\"greet*\": \"WAVE\")",
                                 "a non-empty pattern and a procedural lexeme");
    if (!j.is_object()) return;
    for (const auto& [pattern, lexeme] : pairs) p.gestureVocabulary.push_back({pattern, toUpper(lexeme)});
    notes_.push_back("gestureVocabulary: " + std::to_string(p.gestureVocabulary.size()) + " (profile)");
  }

  // "idleLife": {"blink": true | {"meanInterval": s, "variation": cv}, "breathing": true | {"rate":
  // breaths a minute, "amplitude": degrees}}. The emitters check the ranges when they start.
  void idleLife(const Json& j, IdleLifeProfile& out) {
    if (!j.is_object()) {
      warn("/idleLife", "expected an object {\"blink\": true, \"breathing\": true}; ignored");
      return;
    }
    unknownKeys(j, "/idleLife", {"blink", "breathing"});
    auto emitter = [&](const char* key, std::initializer_list<const char*> known,
                       std::initializer_list<std::pair<const char*, std::optional<float>*>> fields) {
      if (!j.contains(key)) return false;
      const Json& e = j[key];
      const std::string at = std::string("/idleLife/") + key;
      if (e.is_boolean()) return e.get<bool>();
      if (!e.is_object()) {
        warn(at, "expected true, false or an object of parameters; ignored");
        return false;
      }
      for (const auto& [name, value] : fields) {
        if (!e.contains(name)) continue;
        const Json& v = e[name];
        if (v.is_number() && std::isfinite(v.get<double>()) && v.get<double>() >= 0.0) *value = v.get<float>();
        else warn(at + "/" + name, "expected a number >= 0; ignored, the default used");
      }
      unknownKeys(e, at, known);
      return true;
    };
    out.blink = emitter("blink", {"meanInterval", "variation"},
                        {{"meanInterval", &out.blinkMeanInterval}, {"variation", &out.blinkVariation}});
    out.breathing = emitter("breathing", {"rate", "amplitude"},
                            {{"rate", &out.breathsPerMinute}, {"amplitude", &out.breathingAmplitude}});
    notes_.push_back(std::string("idleLife: blink ") + (out.blink ? "on" : "off") + ", breathing " +
                     (out.breathing ? "on" : "off") + " (profile)");
  }

  bool gestures(const Json& j, CharacterProfile& p) {
    if (!j.is_object()) {
      warn("/gestures", "expected an object of LEXEME: clip name; ignored");
      return false;
    }
    for (auto it = j.begin(); it != j.end(); ++it) {
      const std::string where = "/gestures/" + JsonPlaces::escape(it.key());
      if (it.key().empty()) {
        warn(where, "empty gesture lexeme; ignored", true);
        continue;
      }
      if (auto clip = name(*it, where, Kind::Clip); clip && !clip->empty()) p.gestures[it.key()] = *clip;
    }
    notes_.push_back("gestures: " + std::to_string(p.gestures.size()) + " (profile)");
    return true;
  }

  void note(const char* field, const std::string& value) {
    notes_.push_back(std::string(field) + ": " + (value.empty() ? std::string("none") : inQuotes(value)) + " (profile)");
  }
  void noteGuessed(const Guess& g, const char* field) {
    for (const auto& [f, line] : g.notes)
      if (f == field) notes_.push_back(line + "; not in the profile, guessed");
  }

  [[nodiscard]] std::string assetName() const {
    return asset_.sourcePath.empty() ? std::string("the asset") : "'" + asset_.sourcePath + "'";
  }

  std::vector<std::string> notes_;
  const Asset& asset_;
  const FileReader& files_;  // where the joint map the profile names is read
  Tree tree_;
};

CharacterProfileResult load(const std::string& path, const Asset& asset, const FileReader& files) {
  CharacterProfileResult result;
  Guess guessed = guess(asset);
  auto fallBack = [&] {  // on an error the caller still gets a usable profile: the guess
    result.profile = guessed.profile;
    for (const auto& [field, note] : guessed.notes) result.profile.notes.push_back(note);
    result.profile.notes.push_back("profile: " + path + " not used (error); everything guessed");
    return result;
  };
  std::string text;
  if (!readTextFile(files, path, text, result.diagnostics, "cannot read the character profile '" + path + "'"))
    return fallBack();
  Json doc;
  if (!parseJsonText(path, text, doc, result.diagnostics)) return fallBack();
  if (!doc.is_object()) {
    result.diagnostics.error(path, "expected an object with \"joints\", \"face\", \"clips\" and \"gestures\"", 1, 1);
    return fallBack();
  }
  ProfileReader reader(path, text, asset, files, result.diagnostics);
  reader.read(doc, result.profile, guessed);
  // In file order, as a reader goes through the file (all are warnings here).
  std::stable_sort(result.diagnostics.items.begin(), result.diagnostics.items.end(),
                   [](const Diagnostic& a, const Diagnostic& b) { return std::pair{a.line, a.column} < std::pair{b.line, b.column}; });
  return result;
}

}  // namespace

void setProfileJoints(CharacterProfile& p, const retarget::JointMap& map, const Skeleton& skeleton) {
  using retarget::Bone;
  using retarget::Chain;
  // By name, as the profile holds joints; a joint whose name an earlier joint shares (a map
  // may pick it as "#N") cannot be named so: left empty, with a note.
  auto name = [&](int j) {
    if (j < 0 || static_cast<std::size_t>(j) >= skeleton.jointCount()) return std::string();
    const std::string& n = skeleton.names[static_cast<std::size_t>(j)];
    if (!n.empty() && skeleton.findJoint(n) == j) return n;
    p.notes.push_back("joint map: joint #" + std::to_string(j) + " '" + n +
                      "' cannot be named in a profile (no name, or an earlier joint has it); left out");
    return std::string();
  };
  auto bone = [&](Bone b) { return name(map.joint(b)); };
  p.hips = bone(Bone::Hips);
  p.spine.clear();
  for (int j : map.chain(Chain::Spine))
    if (std::string n = name(j); !n.empty()) p.spine.push_back(std::move(n));
  p.neck = map.chain(Chain::Neck).empty() ? std::string() : name(map.chain(Chain::Neck).front());
  p.head = bone(Bone::Head);
  p.leftEye = bone(Bone::LeftEye);
  p.rightEye = bone(Bone::RightEye);
  p.jaw = bone(Bone::Jaw);
  p.leftLeg = {bone(Bone::LeftUpperLeg), bone(Bone::LeftLowerLeg), bone(Bone::LeftFoot)};
  p.rightLeg = {bone(Bone::RightUpperLeg), bone(Bone::RightLowerLeg), bone(Bone::RightFoot)};
  p.leftArm = {bone(Bone::LeftUpperArm), bone(Bone::LeftLowerArm), bone(Bone::LeftHand)};
  p.rightArm = {bone(Bone::RightUpperArm), bone(Bone::RightLowerArm), bone(Bone::RightHand)};
  p.leftToe = bone(Bone::LeftToes);
  p.rightToe = bone(Bone::RightToes);
}

CharacterProfile guessCharacterProfile(const Asset& asset) {
  try {
    Guess g = guess(asset);
    for (auto& [field, note] : g.notes) g.profile.notes.push_back(std::move(note));
    return std::move(g.profile);
  } catch (...) {  // only std::bad_alloc can get here; a profile is optional data
    CharacterProfile p;
    p.notes.push_back("guess failed (out of memory); empty profile");
    return p;
  }
}

CharacterProfileResult loadCharacterProfile(const std::string& path, const Asset& asset, const FileReader& files) {
  try {
    return load(path, asset, files);
  } catch (const std::exception& e) {  // never throws: a bad profile is a diagnostic
    CharacterProfileResult r;
    r.diagnostics.error(path, std::string("cannot load the character profile: ") + e.what());
    return r;
  }
}

}  // namespace marionette
