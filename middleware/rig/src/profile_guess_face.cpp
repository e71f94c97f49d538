// The face of a character profile: which morph targets make each BML face
// lexeme (the file's VRM expressions, else morph names) and each lip-sync
// channel (VRM mouth shapes, OVR viseme morphs, a jaw opening).
#include "profile_guess.hpp"

#include <algorithm>
#include <map>
#include <utility>

#include "marionette/core/text.hpp"

namespace marionette::profile_detail {

namespace {

// Morph-target prefixes: VRoid's Fcl_ALL_, shape-key and blend-shape prefixes.
const std::set<std::string_view> kMorphNoise = {"fcl",   "all",        "blendshape", "blendshape1", "bs",   "shape",
                                                "shapes", "key",       "morph",      "expression",  "exp",  "face",
                                                "facial", "vrc",       "target"};

// Morph keys (lower case, without side or prefix words) for each lexeme, best
// first. `side` -1/+1 makes the left/right lexeme take only morphs of that side.
struct LexemeRule {
  const char* lexeme;
  int side;
  std::vector<std::string_view> keys;
};

const std::vector<LexemeRule>& lexemeRules() {
  static const std::vector<std::string_view> raiseBrows = {"raisebrows", "raisebrow", "browsup", "browup", "browraise",
                                                           "browouterup", "brwsurprised"};
  static const std::vector<std::string_view> lowerBrows = {"lowerbrows", "lowerbrow", "browsdown", "browdown",
                                                           "browlower"};
  static const std::vector<std::string_view> lowerCorners = {"lowermouthcorners", "mouthcornersdown",
                                                             "mouthcornerdown", "mouthfrown", "frown"};
  static const std::vector<std::string_view> raiseCorners = {"raisemouthcorners", "mouthcornersup", "mouthcornerup",
                                                             "mouthsmile"};
  static const std::vector<LexemeRule> rules = {
      {"SMILE", 0, {"smile", "joy", "happy", "mthjoy", "mouthsmile"}},
      {"ANGER", 0, {"angry", "anger", "mad", "mthangry"}},
      {"SADNESS", 0, {"sad", "sadness", "sorrow", "mthsorrow"}},
      {"SURPRISE", 0, {"surprised", "surprise", "shocked", "mthsurprised"}},
      {"FEAR", 0, {"fear", "afraid", "scared", "fearful"}},
      {"DISGUST", 0, {"disgust", "disgusted"}},
      {"CLOSE_EYES", 0, {"closeeyes", "eyesclosed", "eyeclosed", "eyeclose", "eyesclose", "blink", "eyeblink"}},
      {"WIDEN_EYES", 0, {"wideneyes", "eyeswide", "eyewide", "eyewiden", "eyesurprised"}},
      {"EYE_SQUINT", 0, {"eyesquint", "eyessquint", "squint"}},
      {"OPEN_MOUTH", 0, {"openmouth", "mouthopen", "jawopen"}},
      {"OPEN_LIPS", 0, {"openlips", "lipsopen", "lipspart", "lipsparted"}},
      {"PRESS_LIPS", 0, {"presslips", "lipspress", "lipspressed", "mouthpress"}},
      {"PUCKER_LIPS", 0, {"puckerlips", "lipspucker", "mouthpucker", "pucker"}},
      {"BARE_TEETH", 0, {"bareteeth", "teethbare"}},
      {"BARE_TEETH_WIDE", 0, {"bareteethwide"}},
      {"TONGUE_OUT", 0, {"tongueout", "tongue"}},
      {"OBLIQUE_BROWS", 0, {"obliquebrows", "browinnerup", "browsinnerup"}},
      {"RAISE_BROWS", 0, raiseBrows},
      {"RAISE_LEFT_BROW", -1, raiseBrows},
      {"RAISE_RIGHT_BROW", 1, raiseBrows},
      {"LOWER_BROWS", 0, lowerBrows},
      {"LOWER_LEFT_BROW", -1, lowerBrows},
      {"LOWER_RIGHT_BROW", 1, lowerBrows},
      {"LOWER_MOUTH_CORNERS", 0, lowerCorners},
      {"LOWER_LEFT_MOUTH_CORNER", -1, lowerCorners},
      {"LOWER_RIGHT_MOUTH_CORNER", 1, lowerCorners},
      {"RAISE_MOUTH_CORNERS", 0, raiseCorners},
      {"RAISE_LEFT_MOUTH_CORNER", -1, raiseCorners},
      {"RAISE_RIGHT_MOUTH_CORNER", 1, raiseCorners},
  };
  return rules;
}

// VRM expression presets (0.x and 1.0 names) that are BML lexemes.
const std::vector<std::pair<std::string_view, const char*>> kVrmExpressions = {
    {"joy", "SMILE"},       {"happy", "SMILE"},         {"angry", "ANGER"}, {"sorrow", "SADNESS"},
    {"sad", "SADNESS"},     {"surprised", "SURPRISE"}, {"blink", "CLOSE_EYES"}};

// The morphs of one of the file's VRM expressions, with their weights; empty when it has none.
std::vector<FaceMorph> vrmExpressionMorphs(const Asset& asset, std::string_view expression) {
  std::vector<FaceMorph> morphs;
  auto it = asset.humanoid.expressions.find(std::string(expression));
  if (it == asset.humanoid.expressions.end()) return morphs;
  for (const auto& [index, weight] : it->second)
    if (index >= 0 && static_cast<std::size_t>(index) < asset.morphTargets.size() && weight > 0.0f)
      morphs.push_back({asset.morphTargets[static_cast<std::size_t>(index)], std::clamp(weight, 0.0f, 1.0f)});
  return morphs;
}

}  // namespace

void guessFace(const Asset& asset, CharacterProfile& p, Notes& notes) {
  // The file's own expression groups first: authored intent, with weights.
  if (asset.hasHumanoid) {
    for (const auto& [preset, lexeme] : kVrmExpressions) {
      if (p.face.count(lexeme)) continue;
      std::vector<FaceMorph> morphs = vrmExpressionMorphs(asset, preset);
      if (morphs.empty()) continue;
      std::string list;
      for (const auto& m : morphs) list += (list.empty() ? "" : ", ") + inQuotes(m.morph) + " " + std::to_string(m.amount).substr(0, 4);
      notes.emplace_back("face", std::string("face ") + lexeme + ": " + list + " (VRM expression '" + std::string(preset) + "')");
      p.face[lexeme] = std::move(morphs);
    }
  }
  std::vector<NameParts> morphs;
  for (const auto& m : asset.morphTargets) morphs.push_back(parts(m, kMorphNoise));
  for (const LexemeRule& rule : lexemeRules()) {
    if (p.face.count(rule.lexeme)) continue;
    for (std::string_view key : rule.keys) {
      int both = -1, left = -1, right = -1;
      for (std::size_t i = 0; i < morphs.size(); ++i) {
        if (morphs[i].key() != key) continue;
        int& slot = morphs[i].side == 0 ? both : (morphs[i].side < 0 ? left : right);
        if (slot < 0) slot = static_cast<int>(i);
      }
      std::vector<FaceMorph> found;
      if (rule.side < 0 && left >= 0) found.push_back({asset.morphTargets[left], 1.0f});
      else if (rule.side > 0 && right >= 0) found.push_back({asset.morphTargets[right], 1.0f});
      else if (rule.side == 0 && both >= 0) found.push_back({asset.morphTargets[both], 1.0f});
      else if (rule.side == 0 && left >= 0 && right >= 0)  // "blink_left" + "blink_right"
        found = {{asset.morphTargets[left], 1.0f}, {asset.morphTargets[right], 1.0f}};
      if (found.empty()) continue;
      std::vector<std::string> names;
      for (const auto& f : found) names.push_back(f.morph);
      notes.emplace_back("face", std::string("face ") + rule.lexeme + ": " + joined(names) + " (name)");
      p.face[rule.lexeme] = std::move(found);
      break;
    }
  }
  if (p.face.empty())
    notes.emplace_back("face", asset.morphTargets.empty() ? "face: none (no morph targets)"
                                                          : "face: none (no morph name matches a face lexeme)");
}

namespace {

// A morph named after a unit ("AU12", "blendShape.AU_12_L", "AU45Left"): that unit, else none.
// A morph's own name without its mesh's prefix ("blendShape1.mouthSmileLeft": "mouthSmileLeft").
std::string_view withoutMeshPrefix(std::string_view morph) {
  const std::size_t cut = morph.find_last_of(".:|");
  return cut == std::string_view::npos ? morph : morph.substr(cut + 1);
}

std::optional<FacsUnitRequest> auMorph(std::string_view morph) {
  morph = withoutMeshPrefix(morph);
  if (morph.size() < 3 || lower(morph[0]) != 'a' || lower(morph[1]) != 'u') return std::nullopt;
  std::string compact(morph.substr(0, 2));
  for (std::size_t i = 2; i < morph.size(); ++i)
    if (!(i == 2 && (morph[i] == '_' || morph[i] == '-'))) compact += morph[i];  // "AU_12" as "AU12"
  return parseFacsUnit(compact);
}

// The side's names of a table target: "mouthSmile*" on the left is "mouthSmile" with side -1.
struct SidedName {
  std::string key;  // lower case, no side word
  int side;
};
std::vector<SidedName> sidedNames(std::string_view target, int side) {
  std::string key;
  for (char c : target)
    if (c != '*') key += lower(c);
  if (target.empty() || target.back() != '*') return {{key, 0}};
  if (side != 0) return {{key, side}};
  return {{key, -1}, {key, 1}};
}

// The morphs showing one unit on one side, and where they come from; empty when nothing does.
FacsMapping facsFromMorphs(const Asset& asset, const std::vector<NameParts>& morphs, const FacsUnitInfo& unit, int side) {
  FacsMapping m;
  // AU-named morphs: the unit itself (both sides from a left and a right one).
  std::vector<FaceMorph> bySide[3];  // left, both, right
  for (std::size_t i = 0; i < asset.morphTargets.size(); ++i)
    if (auto u = auMorph(asset.morphTargets[i]); u && u->au == unit.au)
      bySide[u->side + 1].push_back({asset.morphTargets[i], 1.0f});
  m.morphs = bySide[side + 1];
  if (side == 0 && m.morphs.empty() && !bySide[0].empty() && !bySide[2].empty()) {
    m.morphs = bySide[0];
    m.morphs.insert(m.morphs.end(), bySide[2].begin(), bySide[2].end());
  }
  if (!m.morphs.empty()) {
    m.source = "AU morphs";
    return m;
  }
  // ARKit: every name of the unit must be there.
  for (const FacsTarget& t : unit.arkit)
    for (const SidedName& n : sidedNames(t.name, side)) {
      const auto it = std::find_if(morphs.begin(), morphs.end(),
                                   [&](const NameParts& np) { return np.key() == n.key && np.side == n.side; });
      if (it == morphs.end()) return {};
      m.morphs.push_back({asset.morphTargets[static_cast<std::size_t>(it - morphs.begin())], t.weight});
    }
  if (!m.morphs.empty()) m.source = "ARKit blendshapes";
  return m;
}

// The first VRM preset of the unit the file has (0.x or 1.0 names; a side's Blink_L / blinkLeft).
FacsMapping facsFromVrm(const Asset& asset, const FacsUnitInfo& unit, int side) {
  FacsMapping m;
  if (!asset.hasHumanoid) return m;
  for (const FacsTarget& t : unit.vrm) {
    std::string base(t.name);
    const bool sidedPreset = !base.empty() && base.back() == '*';
    if (sidedPreset) base.pop_back();
    if (!sidedPreset && side != 0) continue;  // a both-sides preset does not show one side
    std::vector<std::string> names;
    if (!sidedPreset || side == 0) names = {base};
    else names = side < 0 ? std::vector<std::string>{base + "_l", base + "left"} : std::vector<std::string>{base + "_r", base + "right"};
    for (const std::string& name : names)
      for (const auto& [preset, binds] : asset.humanoid.expressions) {
        if (!equalsIgnoringCase(preset, name)) continue;
        for (const auto& [index, weight] : binds)
          if (index >= 0 && static_cast<std::size_t>(index) < asset.morphTargets.size() && weight > 0.0f)
            m.morphs.push_back({asset.morphTargets[static_cast<std::size_t>(index)], std::clamp(weight, 0.0f, 1.0f) * t.weight});
        if (!m.morphs.empty()) {
          m.source = "VRM expression '" + preset + "'";
          return m;
        }
      }
  }
  return m;
}

// A character without VRM presets may still carry the same expressions as plain morphs
// (RobotExpressive's Angry, Surprised, Sad), which the face guess found as emotion lexemes.
FacsMapping facsFromExpressions(const CharacterProfile& p, const FacsUnitInfo& unit, int side) {
  FacsMapping m;
  if (side != 0) return m;  // the lexemes are both sides
  for (const FacsTarget& t : unit.vrm)
    for (const auto& [preset, lexeme] : kVrmExpressions) {  // the presets the face guess reads as lexemes
      if (std::string_view(t.name).substr(0, std::string_view(t.name).find('*')) != preset) continue;
      const auto it = p.face.find(lexeme);
      if (it == p.face.end()) continue;
      for (const FaceMorph& f : it->second) m.morphs.push_back({f.morph, f.amount * t.weight});
      m.source = std::string("expression ") + lexeme;
      return m;
    }
  return m;
}

// Eyelid and brow joints by name: upper lids ("eyelid", "lid_upper", "UpperLid.L"; not lower
// ones) and brows ("brow", "eyebrow"), each with its side.
struct FaceJoint {
  std::string name;
  FacsFacePart part;
  int side;
};
std::vector<FaceJoint> faceJoints(const Skeleton& skeleton) {
  std::vector<FaceJoint> out;
  for (const std::string& name : skeleton.names) {
    const NameParts np = parts(name, {});
    auto has = [&](std::string_view w) { return std::find(np.core.begin(), np.core.end(), w) != np.core.end(); };
    const bool lid = has("lid") || has("eyelid") || has("lids") || has("eyelids");
    const bool lowerLid = has("low") || has("lower") || has("bottom") || has("bot") || has("down");
    if (lid && !lowerLid) out.push_back({name, FacsFacePart::UpperLid, np.side});
    else if (has("brow") || has("eyebrow") || has("brows") || has("eyebrows")) out.push_back({name, FacsFacePart::Brow, np.side});
  }
  return out;
}

}  // namespace

void guessFacs(const Asset& asset, CharacterProfile& p, Notes& notes) {
  std::vector<NameParts> morphs;  // "blendShape1.mouthSmileLeft": the name after its mesh's
  for (std::string_view m : asset.morphTargets)
    morphs.push_back(parts(withoutMeshPrefix(m), kMorphNoise));
  const std::vector<FaceJoint> joints = faceJoints(asset.skeleton);
  std::map<std::string, int> bySource;
  for (const FacsUnitInfo& unit : facsUnits())
    for (int side : {0, -1, 1}) {
      if (side != 0 && !unit.sided) break;
      const std::string key = facsKey(unit.au, side);
      if (p.facs.count(key)) continue;
      FacsMapping m = facsFromMorphs(asset, morphs, unit, side);
      if (m.morphs.empty()) m = facsFromVrm(asset, unit, side);
      if (m.morphs.empty()) m = facsFromExpressions(p, unit, side);
      if (m.morphs.empty() && unit.joint) {
        for (const FaceJoint& j : joints)
          if (j.part == unit.joint->part && (side == 0 || j.side == side || j.side == 0)) m.joints.push_back({j.name, *unit.joint});
        if (!m.joints.empty()) m.source = unit.joint->part == FacsFacePart::UpperLid ? "eyelid joints" : "brow joints";
      }
      if (m.morphs.empty() && m.joints.empty()) continue;
      ++bySource[m.source.substr(0, m.source.find(" '"))];
      p.facs[key] = std::move(m);
    }
  std::string list;
  for (const auto& [source, n] : bySource) list += (list.empty() ? "" : ", ") + std::to_string(n) + " by " + source;
  notes.emplace_back("facs", p.facs.empty() ? std::string("facs: none (no AU, ARKit or VRM morphs, no eyelid or brow joints)")
                                            : "facs: " + std::to_string(p.facs.size()) + " units and sides (" + list + ")");
}

void guessVisemes(const Asset& asset, CharacterProfile& p, Notes& notes) {
  if (asset.hasHumanoid) {
    const std::pair<const char*, const char*> vrm[] = {
        {"A", "vrm_aa"}, {"I", "vrm_ih"}, {"U", "vrm_ou"}, {"E", "vrm_ee"}, {"O", "vrm_oh"}};
    for (const auto& [alias, channel] : vrm) {
      if (std::vector<FaceMorph> morphs = vrmExpressionMorphs(asset, alias); !morphs.empty())
        p.visemes[channel] = std::move(morphs);
    }
  }
  // OVR names are short ("E", "aa", "oh"): taken only with a "viseme" word, or as a nearly full set.
  static const char* const ovr[] = {"sil", "PP", "FF", "TH", "DD", "kk", "CH", "SS", "nn", "RR", "aa", "E", "ih", "oh", "ou"};
  std::map<std::string, std::string> tagged, bare;
  for (const auto& m : asset.morphTargets) {
    const NameParts np = parts(m, kMorphNoise);
    std::vector<std::string> core = np.core;
    const bool hasTag = std::erase(core, std::string("viseme")) > 0;
    if (np.side != 0) continue;
    if (np.is({"jaw", "open"}) || np.is({"mouth", "open"})) bare.emplace("jawopen", m);
    if (core.size() == 1) (hasTag ? tagged : bare).emplace(core.front(), m);
  }
  auto lowered = [](std::string_view v) {
    std::string out;
    for (char c : v) out += lower(c);
    return out;
  };
  std::size_t bareHits = 0;
  for (const char* v : ovr) bareHits += bare.count(lowered(v));
  for (const char* v : ovr) {
    if (p.visemes.count(v)) continue;
    const std::string key = lowered(v);
    if (auto it = tagged.find(key); it != tagged.end()) p.visemes[v] = {{it->second, 1.0f}};
    else if (auto b = bare.find(key); b != bare.end() && bareHits >= 12) p.visemes[v] = {{b->second, 1.0f}};
  }
  if (auto it = bare.find("jawopen"); it != bare.end() && !p.visemes.count("jawOpen")) p.visemes["jawOpen"] = {{it->second, 1.0f}};
  std::string list;
  for (const auto& [channel, morphs] : p.visemes) {
    std::vector<std::string> names;
    for (const auto& m : morphs) names.push_back(m.morph);
    list += (list.empty() ? "" : "; ") + channel + " " + joined(names);
  }
  notes.emplace_back("visemes", p.visemes.empty() ? std::string("visemes: none (no VRM mouth shapes or viseme morphs)")
                                                  : "visemes: " + list + " (VRM expressions and morph names)");
}

const std::set<std::string_view>& faceLexemes() {
  static const std::set<std::string_view> s = [] {
    std::set<std::string_view> out;
    for (const auto& r : lexemeRules()) out.insert(r.lexeme);
    return out;
  }();
  return s;
}

}  // namespace marionette::profile_detail
