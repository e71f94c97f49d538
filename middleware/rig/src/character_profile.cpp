#include "marionette/core/text_file.hpp"
#include "marionette/rig/character_profile.hpp"
#include "marionette/speech/lipsync.hpp"

#include <algorithm>
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
#include "profile_skeleton.hpp"

namespace marionette {

namespace {
using Json = nlohmann::json;
using namespace profile_detail;
using json_detail::JsonPlaces;
using json_detail::JsonReaderBase;
using json_detail::parseJsonText;

// ---- Names ------------------------------------------------------------------

// Morph-target prefixes: VRoid's Fcl_ALL_, shape-key and blend-shape prefixes.
const std::set<std::string_view> kMorphNoise = {"fcl",   "all",        "blendshape", "blendshape1", "bs",   "shape",
                                                "shapes", "key",       "morph",      "expression",  "exp",  "face",
                                                "facial", "vrc",       "target"};
// Clip-name padding of exporters and libraries ("Armature|mixamo.com|Layer0", "Walk_Loop").
const std::set<std::string_view> kClipNoise = {"anim",     "animation", "action", "armature", "clip",    "take",
                                               "loop",     "looped",    "cycle",  "inplace",  "in",      "place",
                                               "default",  "mixamo",    "com",    "layer",    "character", "fwd",
                                               "forward",  "rig",       "root",   "motion"};

struct JointGuess {
  int hips = -1, neck = -1, head = -1, leftEye = -1, rightEye = -1, jaw = -1;
  std::string hipsHow, neckHow, headHow, leftEyeHow, rightEyeHow, jawHow;
};

// Joints on the path below `hips` down to `neck`, both excluded, in hips-to-neck order.
std::vector<std::string> spineBetween(const Tree& t, int hips, int neck) {
  std::vector<std::string> spine;
  if (!t.above(hips, neck)) return spine;
  for (int j = t.parent[neck]; j >= 0 && j != hips; j = t.parent[j]) spine.push_back(t.names[j]);
  std::reverse(spine.begin(), spine.end());
  return spine;
}

// The VRM humanoid map, when it is complete and its chain is consistent.
bool guessFromHumanoid(const Asset& asset, const Tree& t, JointGuess& g) {
  if (!asset.hasHumanoid) return false;
  auto bone = [&](const char* key) {
    auto it = asset.humanoid.bones.find(key);
    return it == asset.humanoid.bones.end() ? -1 : t.find(it->second);
  };
  const int hips = bone("hips"), neck = bone("neck"), head = bone("head");
  if (hips < 0 || neck < 0 || head < 0 || !t.above(hips, neck) || !t.above(neck, head)) return false;
  g.hips = hips, g.neck = neck, g.head = head;
  g.hipsHow = g.neckHow = g.headHow = "VRM humanoid";
  auto below = [&](int j) { return t.above(head, j) ? j : -1; };
  if ((g.leftEye = below(bone("leftEye"))) >= 0) g.leftEyeHow = "VRM humanoid";
  if ((g.rightEye = below(bone("rightEye"))) >= 0) g.rightEyeHow = "VRM humanoid";
  if ((g.jaw = below(bone("jaw"))) >= 0) g.jawHow = "VRM humanoid";
  return true;
}

// Walking up from the neck, the joints where other branches (holding >= 2 leaves:
// arms, legs) leave the spine: the first is the chest (or the neck, where the arms
// hang from it), the next the hips.
int hipsAboveNeck(const Tree& t, int neck, int head) {
  int branchings = 0;
  int from = head >= 0 ? t.childToward(neck, head) : -1;
  for (int j = neck; t.valid(j); from = j, j = t.parent[j]) {
    const int other = t.leaves[j] - (from >= 0 ? t.leaves[from] : (j == neck ? t.leaves[j] : 0));
    if (other >= 2 && ++branchings == 2) return j;
  }
  return -1;
}

JointGuess guessJoints(const Asset& asset, const Tree& t) {
  JointGuess g;
  if (guessFromHumanoid(asset, t, g)) return g;

  std::vector<int> hipsC, neckC, headC, eyeC[2], jawC;
  for (int j = 0; j < t.count(); ++j) {
    const NameParts np = parts(t.names[j], kJointNoise);
    if (np.side == 0) {
      if (np.is({"hips"}) || np.is({"hip"}) || np.is({"pelvis"})) hipsC.push_back(j);
      // "lowerneck" (CMU 3dsMax-friendly) is where the neck starts: the root-most wins below.
      if (np.is({"neck"}) || np.is({"lower", "neck"}) || np.is({"lowerneck"}) || np.is({"upper", "neck"}) ||
          np.is({"upperneck"}))
        neckC.push_back(j);
      if (np.is({"head"})) headC.push_back(j);
      if (np.is({"jaw"}) || np.is({"lower", "jaw"})) jawC.push_back(j);
    } else if (np.is({"eye"}) || np.is({"face", "eye"}) || np.is({"eye", "ball"}) || np.is({"eyeball"})) {
      eyeC[np.side > 0].push_back(j);
    }
  }
  auto underAny = [&](const std::vector<int>& tops, int j) {
    if (tops.empty()) return true;  // nothing of that name: no constraint
    return std::any_of(tops.begin(), tops.end(), [&](int a) { return t.above(a, j); });
  };
  auto shallowest = [&](const std::vector<int>& c) {
    int best = -1;
    for (int j : c)
      if (best < 0 || t.depth[j] < t.depth[best]) best = j;
    return best;
  };

  // Head: a head-named joint below a neck-named one, below a hips-named one.
  std::vector<int> heads;
  std::string rejected;
  for (int j : headC) {
    if (underAny(neckC, j) && underAny(hipsC, j)) heads.push_back(j);
    else rejected += (rejected.empty() ? "" : ", ") + inQuotes(t.names[j]);
  }
  const std::string rejectNote = rejected.empty() ? "" : "; " + rejected + " rejected: not below a neck and the hips";
  if ((g.head = shallowest(heads)) >= 0) {
    g.headHow = "name";
  } else {
    // The joint the eyes (or the jaw) hang from is the head, whatever its name.
    const int le = shallowest(eyeC[0]), re = shallowest(eyeC[1]), jaw = shallowest(jawC);
    if (le >= 0 && re >= 0 && t.parent[le] == t.parent[re] && t.parent[le] >= 0 && underAny(hipsC, t.parent[le])) {
      g.head = t.parent[le];
      g.headHow = "topology: parent of the eyes" + rejectNote;
    } else if (jaw >= 0 && t.parent[jaw] >= 0 && underAny(hipsC, t.parent[jaw])) {
      g.head = t.parent[jaw];
      g.headHow = "topology: parent of the jaw" + rejectNote;
    }
  }

  // Neck: the root-most neck-named joint above the head (CMU has Neck and Neck1);
  // else the unbranched chain above the head, up to where the arms branch off.
  if (g.head >= 0) {
    for (int j = t.parent[g.head]; j >= 0; j = t.parent[j])
      if (std::find(neckC.begin(), neckC.end(), j) != neckC.end()) g.neck = j, g.neckHow = "name";
    if (g.neck < 0 && t.parent[g.head] >= 0) {
      int j = t.parent[g.head];
      while (t.parent[j] >= 0 && t.children[t.parent[j]].size() == 1 &&
             std::find(hipsC.begin(), hipsC.end(), t.parent[j]) == hipsC.end())
        j = t.parent[j];
      if (std::find(hipsC.begin(), hipsC.end(), j) == hipsC.end())
        g.neck = j, g.neckHow = "topology: unbranched chain above the head";
    }
  } else {
    std::vector<int> necks;
    for (int j : neckC)
      if (underAny(hipsC, j)) necks.push_back(j);
    if ((g.neck = shallowest(necks)) >= 0) {
      g.neckHow = "name";
      if (t.children[g.neck].size() == 1)
        g.head = t.children[g.neck][0], g.headHow = "topology: only child of the neck" + rejectNote;
    }
  }

  // Hips: the deepest hips-named joint above the neck (Pab has Hips above Pelvis;
  // the legs branch at Pelvis); else where the legs branch off the spine.
  const int top = g.neck >= 0 ? g.neck : g.head;
  if (top >= 0) {
    for (int j = t.parent[top]; j >= 0 && g.hips < 0; j = t.parent[j])
      if (std::find(hipsC.begin(), hipsC.end(), j) != hipsC.end()) g.hips = j, g.hipsHow = "name";
    if (g.hips < 0 && g.neck >= 0 && (g.hips = hipsAboveNeck(t, g.neck, g.head)) >= 0)
      g.hipsHow = "topology: where the legs branch off below the arms";
  } else if ((g.hips = shallowest(hipsC)) >= 0) {
    g.hipsHow = "name";
  } else {
    // Nothing named: the root-most joint with a pair of legs and one odd branch.
    for (int j = 0; j < t.count(); ++j)
      if (t.oddChildOut(j, 1) >= 0 && (g.hips < 0 || t.depth[j] < t.depth[g.hips])) g.hips = j;
    if (g.hips >= 0) g.hipsHow = "topology: root-most joint with two legs and a spine";
  }

  // Neither neck nor head named: down the spine to the chest, whose odd branch is the neck.
  if (g.hips >= 0 && g.neck < 0 && g.head < 0) {
    int j = t.oddChildOut(g.hips, 1);
    while (t.valid(j) && t.children[j].size() == 1) j = t.children[j][0];
    const int neck = t.oddChildOut(j, 0);
    if (neck >= 0) {
      g.neck = neck, g.neckHow = "topology: odd branch of the chest";
      if (t.children[neck].size() == 1) g.head = t.children[neck][0], g.headHow = "topology: only child of the neck";
    }
  }
  if (g.head < 0 && !rejected.empty()) g.headHow = rejectNote.substr(2);

  // Eyes and jaw: named joints below the head.
  auto below = [&](const std::vector<int>& c) {
    std::vector<int> ok;
    for (int j : c)
      if (g.head < 0 || t.above(g.head, j)) ok.push_back(j);
    return shallowest(ok);
  };
  if ((g.leftEye = below(eyeC[0])) >= 0) g.leftEyeHow = "name";
  if ((g.rightEye = below(eyeC[1])) >= 0) g.rightEyeHow = "name";
  if ((g.jaw = below(jawC)) >= 0) g.jawHow = "name";
  return g;
}

// ---- Face -------------------------------------------------------------------

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

// The lip-sync channels a character's morphs can show (speech/lipsync.hpp):
// the file's VRM mouth shapes first (A I U E O, both VRM versions), then a full
// set of OVR viseme morphs ("viseme_PP", ...), then an ARKit-style jaw opening.
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

// ---- Clips ------------------------------------------------------------------

// Words that make a clip something other than the plain cycle ("WalkJump", "Idle_to_Walk").
const std::set<std::string_view> kClipExclusions = {"jump",  "to",     "start", "stop",  "end",    "turn",
                                                    "transition", "back", "backward", "backwards", "strafe",
                                                    "crouch", "injured", "sit", "sitting", "death", "die",
                                                    "attack", "left", "right", "l", "r"};

std::vector<std::string> clipCore(const std::string& name) {
  // Blender exports "Armature|Idle": the action name is the last part.
  const auto bar = name.find_last_of('|');
  std::vector<std::string> core;
  for (auto& w : words(bar == std::string::npos ? std::string_view(name) : std::string_view(name).substr(bar + 1)))
    if (!isDigit(w[0]) && !kClipNoise.count(w)) core.push_back(std::move(w));
  return core;
}

// The clip best named like one of `ws` (earlier words first; a bare word beats a
// qualified one like "Slow Run"); "" when none.
std::string findClip(const Asset& asset, std::initializer_list<std::string_view> ws) {
  int bestScore = 1 << 30;
  std::string best;
  for (const Clip& clip : asset.clips) {
    const auto core = clipCore(clip.name);
    if (core.empty() || core.size() > 2) continue;
    if (std::any_of(core.begin(), core.end(), [](const std::string& w) { return kClipExclusions.count(w) > 0; })) continue;
    int rank = 0;
    for (std::string_view w : ws) {
      if (std::find(core.begin(), core.end(), w) != core.end()) {
        const int score = rank * 2 + (core.size() == 1 ? 0 : 1);
        if (score < bestScore) bestScore = score, best = clip.name;
        break;
      }
      ++rank;
    }
  }
  return best;
}

// Gesture lexemes and the joined clip-name words that perform them. Only arm and
// hand gestures: head nods and shakes ("Yes", "No") are head behaviors in BML.
const std::vector<std::pair<const char*, std::vector<std::string_view>>> kGestureRules = {
    {"WAVE", {"wave", "waving", "wavehand", "handwave"}},
    {"THUMBS_UP", {"thumbsup", "thumbup"}},
    {"POINT", {"point", "pointing"}},
    {"CLAP", {"clap", "clapping"}},
    {"SHRUG", {"shrug", "shrugging"}},
    {"CROSS_ARMS", {"crossarms", "armscrossed", "crossedarms"}},
};

void guessClips(const Asset& asset, CharacterProfile& p, Notes& notes) {
  auto note = [&](const char* field, const std::string& clip) {
    notes.emplace_back(field, std::string(field) + ": " + (clip.empty() ? "none" : inQuotes(clip) + " (name)"));
  };
  p.idle = findClip(asset, {"idle", "idling", "breathing", "stand", "standing"});
  note("idle", p.idle);
  p.walk = findClip(asset, {"walk", "walking"});
  note("walk", p.walk);
  p.run = findClip(asset, {"run", "running", "jog", "jogging", "sprint", "sprinting"});
  note("run", p.run);
  for (const auto& [lexeme, keys] : kGestureRules) {
    for (const Clip& clip : asset.clips) {
      std::string key;
      for (const auto& w : clipCore(clip.name)) key += w;
      if (std::find(keys.begin(), keys.end(), key) == keys.end()) continue;
      p.gestures[lexeme] = clip.name;
      notes.emplace_back("gestures", std::string("gesture ") + lexeme + ": " + inQuotes(clip.name) + " (name)");
      break;
    }
  }
  if (p.gestures.empty()) notes.emplace_back("gestures", "gestures: none");
}

struct Guess {
  CharacterProfile profile;
  Notes notes;
};

Guess guess(const Asset& asset) {
  Guess g;
  const Tree t(asset.skeleton);
  const JointGuess j = guessJoints(asset, t);
  CharacterProfile& p = g.profile;
  auto set = [&](const char* field, std::string& out, int joint, const std::string& how) {
    out = t.name(joint);
    g.notes.emplace_back(field, std::string(field) + ": " + (joint >= 0 ? inQuotes(out) + " (" + how + ")"
                                                                      : "none" + (how.empty() ? "" : " (" + how + ")")));
  };
  set("hips", p.hips, j.hips, j.hipsHow);
  p.spine = spineBetween(t, j.hips, j.neck);
  g.notes.emplace_back("spine", "spine: " + (p.spine.empty() ? std::string("none") : joined(p.spine)) +
                                    (j.hips >= 0 && j.neck >= 0 ? " (path from the hips to the neck)" : ""));
  set("neck", p.neck, j.neck, j.neckHow);
  set("head", p.head, j.head, j.headHow);
  set("leftEye", p.leftEye, j.leftEye, j.leftEyeHow);
  set("rightEye", p.rightEye, j.rightEye, j.rightEyeHow);
  set("jaw", p.jaw, j.jaw, j.jawHow);
  guessLimbs(asset, t, BodyChain{j.hips, j.neck, j.head}, p, g.notes);
  guessFace(asset, p, g.notes);
  guessVisemes(asset, p, g.notes);
  guessClips(asset, p, g.notes);
  return g;
}

// ---- Loading ----------------------------------------------------------------

const std::set<std::string_view>& faceLexemes() {
  static const std::set<std::string_view> s = [] {
    std::set<std::string_view> out;
    for (const auto& r : lexemeRules()) out.insert(r.lexeme);
    return out;
  }();
  return s;
}

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
  ProfileReader(const std::string& file, const std::string& text, const Asset& asset, Diagnostics& d)
      : JsonReaderBase(file, text, d, "ignored, its fields guessed"), asset_(asset), tree_(asset.skeleton) {}

  void read(const Json& doc, CharacterProfile& p, const Guess& guessed) {
    unknownKeys(doc, "", {"joints", "limbs", "face", "visemes", "clips", "gestures", "comment"});
    const Json& joints = section(doc, "joints");
    const Json& clips = section(doc, "clips");
    unknownKeys(joints, "/joints", {"hips", "spine", "neck", "head", "leftEye", "rightEye", "jaw"});
    unknownKeys(clips, "/clips", {"idle", "walk", "run"});

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

    if (!(doc.contains("face") && face(doc["face"], p))) p.face = guessed.profile.face, noteGuessed(guessed, "face");
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
    p.notes = std::move(notes_);
  }

 private:
  enum class Kind { Joint, Morph, Clip };


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
      const std::string detached = checkLimb(out, v, where, leg);
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

  // Warnings where a limb's joints do not descend from one another. A leg's end
  // elsewhere (an IK target under the root) is fine: the returned note says so.
  std::string checkLimb(const Limb& l, const Json& given, const std::string& where, bool leg) {
    const int u = tree_.find(l.upper), lo = tree_.find(l.lower), e = tree_.find(l.end);
    auto at = [&](const char* key, const char* other) { return where + "/" + (given.contains(key) ? key : other); };
    if (u >= 0 && lo >= 0 && !tree_.above(u, lo))
      warn(at("lower", "upper"), "'" + l.lower + "' is not below the upper joint '" + l.upper + "'");
    const int before = lo >= 0 ? lo : u;
    if (before < 0 || e < 0 || tree_.above(before, e)) return {};
    const bool elsewhere = !tree_.above(e, before) && !(u >= 0 && tree_.above(e, u));
    if (leg && lo >= 0 && elsewhere)
      return "; '" + l.end + "' is not below '" + l.lower + "': the end point is its rest offset from the lower joint";
    warn(at("end", lo >= 0 ? "lower" : "upper"),
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
  Tree tree_;
};

CharacterProfileResult load(const std::string& path, const Asset& asset) {
  CharacterProfileResult result;
  Guess guessed = guess(asset);
  auto fallBack = [&] {  // on an error the caller still gets a usable profile: the guess
    result.profile = guessed.profile;
    for (const auto& [field, note] : guessed.notes) result.profile.notes.push_back(note);
    result.profile.notes.push_back("profile: " + path + " not used (error); everything guessed");
    return result;
  };
  std::string text, why;
  if (!readTextFile(path, text, why)) {
    result.diagnostics.error(path, "cannot read the character profile '" + path + "': " + why);
    return fallBack();
  }
  Json doc;
  if (!parseJsonText(path, text, doc, result.diagnostics)) return fallBack();
  if (!doc.is_object()) {
    result.diagnostics.error(path, "expected an object with \"joints\", \"face\", \"clips\" and \"gestures\"", 1, 1);
    return fallBack();
  }
  ProfileReader reader(path, text, asset, result.diagnostics);
  reader.read(doc, result.profile, guessed);
  // In file order, as a reader goes through the file (all are warnings here).
  std::stable_sort(result.diagnostics.items.begin(), result.diagnostics.items.end(),
                   [](const Diagnostic& a, const Diagnostic& b) { return std::pair{a.line, a.column} < std::pair{b.line, b.column}; });
  return result;
}

}  // namespace

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

CharacterProfileResult loadCharacterProfile(const std::string& path, const Asset& asset) {
  try {
    return load(path, asset);
  } catch (const std::exception& e) {  // never throws: a bad profile is a diagnostic
    CharacterProfileResult r;
    r.diagnostics.error(path, std::string("cannot load the character profile: ") + e.what());
    return r;
  }
}

}  // namespace marionette
