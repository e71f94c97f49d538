#include "marionette/retarget/joint_map.hpp"

#include <algorithm>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <utility>

#include <nlohmann/json.hpp>

#include "marionette/scene/character_profile.hpp"
#include "../scene/json_places.hpp"
#include "../scene/profile_skeleton.hpp"

namespace marionette::retarget {

namespace {
using Json = nlohmann::json;
using json_detail::JsonPlaces;
using profile_detail::inQuotes;
using profile_detail::Tree;

constexpr std::array<std::string_view, kBoneCount> kBoneNames = {
    "hips",         "head",         "leftEye",      "rightEye",     "jaw",          "leftShoulder",
    "leftUpperArm", "leftLowerArm", "leftHand",     "rightShoulder", "rightUpperArm", "rightLowerArm",
    "rightHand",    "leftUpperLeg", "leftLowerLeg", "leftFoot",     "leftToes",     "rightUpperLeg",
    "rightLowerLeg", "rightFoot",   "rightToes"};
constexpr std::array<std::string_view, kChainCount> kChainNames = {
    "spine",      "neck",      "leftThumb",   "leftIndex",   "leftMiddle",  "leftRing",
    "leftLittle", "rightThumb", "rightIndex", "rightMiddle", "rightRing", "rightLittle"};

// Without these a humanoid cannot be driven: a motion needs its root, head and limbs.
constexpr Bone kRequired[] = {Bone::Hips,          Bone::Head,          Bone::LeftUpperArm,  Bone::LeftLowerArm,
                              Bone::LeftHand,      Bone::RightUpperArm, Bone::RightLowerArm, Bone::RightHand,
                              Bone::LeftUpperLeg,  Bone::LeftLowerLeg,  Bone::LeftFoot,      Bone::RightUpperLeg,
                              Bone::RightLowerLeg, Bone::RightFoot};

std::size_t at(Bone b) { return static_cast<std::size_t>(b); }
std::size_t at(Chain c) { return static_cast<std::size_t>(c); }

// ---- Consistency ------------------------------------------------------------

// Drops every later mention of a joint already mapped (bones first, in enum
// order, then chains), so that a map never names a joint twice; calls `dropped`
// with the joint, the entry that keeps it and the one that loses it.
template <class F>
void dropDuplicates(JointMap& m, F&& dropped) {
  std::map<int, std::string> owner;
  for (int b = 0; b < kBoneCount; ++b) {
    int& j = m.bones[static_cast<std::size_t>(b)];
    if (j < 0) continue;
    const std::string name(kBoneNames[static_cast<std::size_t>(b)]);
    if (auto [it, fresh] = owner.emplace(j, name); !fresh) dropped(j, it->second, name, -1), j = -1;
  }
  for (int c = 0; c < kChainCount; ++c) {
    auto& chain = m.chains[static_cast<std::size_t>(c)];
    std::vector<int> kept;
    for (std::size_t k = 0; k < chain.size(); ++k) {
      const std::string name = std::string(kChainNames[static_cast<std::size_t>(c)]) + "[" + std::to_string(k) + "]";
      if (auto [it, fresh] = owner.emplace(chain[k], name); fresh) kept.push_back(chain[k]);
      else dropped(chain[k], it->second, name, static_cast<int>(k));
    }
    chain = std::move(kept);
  }
}

void noteMissing(JointMap& m) {
  std::string missing;
  for (Bone b : kRequired)
    if (m.joint(b) < 0) missing += (missing.empty() ? "" : ", ") + std::string(boneName(b));
  if (!missing.empty()) m.notes.push_back("required bones missing: " + missing);
}

// ---- Guessing: VRM humanoid map ---------------------------------------------

const char* const kFingers[] = {"Thumb", "Index", "Middle", "Ring", "Little"};

JointMap fromHumanoid(const Asset& asset, const Tree& t) {
  JointMap m;
  auto joint = [&](const std::string& vrmBone) {
    auto it = asset.humanoid.bones.find(vrmBone);
    if (it == asset.humanoid.bones.end()) return -1;
    const int j = t.find(it->second);
    if (j < 0) m.notes.push_back(vrmBone + ": VRM humanoid names joint " + inQuotes(it->second) + ", which the skeleton lacks");
    return j;
  };
  // The canonical names are VRM's, so single bones map one to one.
  for (int b = 0; b < kBoneCount; ++b) {
    const std::string name(kBoneNames[static_cast<std::size_t>(b)]);
    m.bones[static_cast<std::size_t>(b)] = joint(name);
  }
  // Chains gather VRM's optional in-between bones, ordered root to tip by depth.
  auto chain = [&](std::initializer_list<std::string> vrmBones) {
    std::vector<int> out;
    for (const auto& n : vrmBones)
      if (const int j = joint(n); j >= 0) out.push_back(j);
    std::stable_sort(out.begin(), out.end(), [&](int a, int b) { return t.depth[a] < t.depth[b]; });
    return out;
  };
  m.chains[at(Chain::Spine)] = chain({"spine", "chest", "upperChest"});
  m.chains[at(Chain::Neck)] = chain({"neck"});
  for (int side = 0; side < 2; ++side) {
    for (int f = 0; f < 5; ++f) {
      // VRM 0.0: Proximal, Intermediate, Distal; VRM 1.0: the thumb has Metacarpal instead of Intermediate.
      const std::string p = std::string(side == 0 ? "left" : "right") + kFingers[f];
      m.chains[at(Chain::LeftThumb) + static_cast<std::size_t>(side * 5 + f)] =
          chain({p + "Metacarpal", p + "Proximal", p + "Intermediate", p + "Distal"});
    }
  }
  m.notes.push_back("all entries from the file's VRM humanoid map (" + std::to_string(asset.humanoid.bones.size()) +
                    " bones)");
  return m;
}

// ---- Guessing: names and topology -------------------------------------------

// The finger a joint's name says (0 thumb .. 4 little), or -1. When a name has two
// finger words the last one counts: Pab's left pinky is "LeftHandRingPinky1".
int fingerOf(const std::string& name) {
  int finger = -1;
  for (const auto& w : profile_detail::words(name)) {
    if (w == "thumb") finger = 0;
    else if (w == "index" || w == "pointer") finger = 1;
    else if (w == "middle" || w == "mid") finger = 2;
    else if (w == "ring") finger = 3;
    else if (w == "pinky" || w == "little" || w == "small" || w == "pinkie") finger = 4;
  }
  return finger;
}

// The finger chains below a hand: per finger, its named joints root to tip. Joints
// of a finger that branch away from its first chain are left out with a note.
void guessFingers(const Tree& t, int hand, int side, JointMap& m) {
  const std::string sideName = side == 0 ? "left" : "right";
  std::array<std::vector<int>, 5> named;
  std::vector<std::string> unnamed;
  for (int j = hand + 1; j < t.count(); ++j) {  // descendants come after their ancestor
    if (!t.above(hand, j)) continue;
    if (const int f = fingerOf(t.names[j]); f >= 0) named[static_cast<std::size_t>(f)].push_back(j);
    else unnamed.push_back(t.names[j]);
  }
  bool any = false;
  for (int f = 0; f < 5; ++f) {
    auto& js = named[static_cast<std::size_t>(f)];
    std::stable_sort(js.begin(), js.end(), [&](int a, int b) { return t.depth[a] < t.depth[b]; });
    std::vector<int> chain;
    std::vector<std::string> off;
    for (int j : js) {
      if (chain.empty() || t.above(chain.back(), j)) chain.push_back(j);
      else off.push_back(t.names[j]);
    }
    const std::string cname = sideName + kFingers[f];
    if (!off.empty()) m.notes.push_back(cname + ": " + profile_detail::joined(off) + " left out (not on one chain)");
    any = any || !chain.empty();
    m.chains[at(Chain::LeftThumb) + static_cast<std::size_t>(side * 5 + f)] = std::move(chain);
  }
  if (!unnamed.empty())
    m.notes.push_back(sideName + " fingers: joints below the hand " + inQuotes(t.names[hand]) + " not named after a finger (" +
                      profile_detail::joined(unnamed) + "); left out" + (any ? "" : ", no finger chains"));
}

// The one joint between the chest end of the body chain and an upper arm: the
// clavicle. None when the arm hangs straight from the chest (CesiumMan) or when
// there are several (no telling which one is the clavicle).
void guessClavicle(const Tree& t, int upperArm, const std::set<int>& body, Bone bone, JointMap& m) {
  const std::string bname(boneName(bone));
  if (upperArm < 0) {
    m.notes.push_back(bname + ": none (no upper arm)");
    return;
  }
  std::vector<int> between;
  int p = t.parent[upperArm];
  for (; p >= 0 && !body.count(p); p = t.parent[p]) between.push_back(p);
  if (p < 0) {
    m.notes.push_back(bname + ": none (the upper arm " + inQuotes(t.names[upperArm]) + " is not below the spine)");
  } else if (between.empty()) {
    m.notes.push_back(bname + ": none (the upper arm " + inQuotes(t.names[upperArm]) + " hangs from " +
                      inQuotes(t.names[p]) + ")");
  } else if (between.size() > 1) {
    std::vector<std::string> names;
    for (int j : between) names.push_back(t.names[j]);
    m.notes.push_back(bname + ": none (" + std::to_string(between.size()) + " joints between " + inQuotes(t.names[p]) +
                      " and the upper arm: " + profile_detail::joined(names) + ")");
  } else {
    m.bones[at(bone)] = between[0];
    m.notes.push_back(bname + ": " + inQuotes(t.names[between[0]]) + " (topology: the one joint between " +
                      inQuotes(t.names[p]) + " and the upper arm " + inQuotes(t.names[upperArm]) + ")");
  }
}

// Names that are the clavicle in some conventions and the upper arm in others
// (CMU: MotionBuilder-friendly "LeftShoulder" is the clavicle, 3dsMax-friendly the upper arm).
bool saysShoulder(const std::string& name) {
  for (const auto& w : profile_detail::words(name))
    if (w == "shoulder" || w == "shldr" || w.ends_with("shoulder")) return true;
  return false;
}

JointMap fromNames(const Asset& asset, const Tree& t) {
  JointMap m;
  const CharacterProfile p = guessCharacterProfile(asset);
  // The profile's notes on the joints it found, for the record of how each was found.
  for (const auto& n : p.notes) {
    const std::string field = n.substr(0, n.find(':'));
    static const std::set<std::string> kJointFields = {"hips",    "spine",    "neck",    "head",     "leftEye",
                                                       "rightEye", "jaw",     "leftLeg", "rightLeg", "leftArm",
                                                       "rightArm", "leftToe", "rightToe", "sides"};
    if (kJointFields.count(field)) m.notes.push_back("profile " + n);
  }
  auto set = [&](Bone b, const std::string& name) { m.bones[at(b)] = name.empty() ? -1 : t.find(name); };
  set(Bone::Hips, p.hips);
  set(Bone::Head, p.head);
  set(Bone::LeftEye, p.leftEye);
  set(Bone::RightEye, p.rightEye);
  set(Bone::Jaw, p.jaw);
  set(Bone::LeftUpperArm, p.leftArm.upper);
  set(Bone::LeftLowerArm, p.leftArm.lower);
  set(Bone::LeftHand, p.leftArm.end);
  set(Bone::RightUpperArm, p.rightArm.upper);
  set(Bone::RightLowerArm, p.rightArm.lower);
  set(Bone::RightHand, p.rightArm.end);
  set(Bone::LeftUpperLeg, p.leftLeg.upper);
  set(Bone::LeftLowerLeg, p.leftLeg.lower);
  set(Bone::LeftFoot, p.leftLeg.end);
  set(Bone::LeftToes, p.leftToe);
  set(Bone::RightUpperLeg, p.rightLeg.upper);
  set(Bone::RightLowerLeg, p.rightLeg.lower);
  set(Bone::RightFoot, p.rightLeg.end);
  set(Bone::RightToes, p.rightToe);

  for (const auto& s : p.spine)
    if (const int j = t.find(s); j >= 0) m.chains[at(Chain::Spine)].push_back(j);
  // The neck chain: the neck joint down to the head's parent (CMU: Neck, Neck1).
  const int neck = p.neck.empty() ? -1 : t.find(p.neck), head = m.joint(Bone::Head);
  if (neck >= 0) {
    std::vector<int> chain;
    if (head >= 0 && t.above(neck, head)) {
      for (int j = t.parent[head]; j >= 0 && j != t.parent[neck]; j = t.parent[j]) chain.push_back(j);
      std::reverse(chain.begin(), chain.end());
    } else {
      chain.push_back(neck);
    }
    m.chains[at(Chain::Neck)] = std::move(chain);
    m.notes.push_back("neck: " + inQuotes(p.neck) + " down to the head's parent");
  }

  // Clavicles hang from the chest end of the spine, or from the neck (Pab), or the hips.
  std::set<int> body(m.chain(Chain::Spine).begin(), m.chain(Chain::Spine).end());
  body.insert(m.chain(Chain::Neck).begin(), m.chain(Chain::Neck).end());
  if (m.joint(Bone::Hips) >= 0) body.insert(m.joint(Bone::Hips));
  guessClavicle(t, m.joint(Bone::LeftUpperArm), body, Bone::LeftShoulder, m);
  guessClavicle(t, m.joint(Bone::RightUpperArm), body, Bone::RightShoulder, m);
  for (auto [clavicle, upper] : {std::pair{Bone::LeftShoulder, Bone::LeftUpperArm}, {Bone::RightShoulder, Bone::RightUpperArm}}) {
    const int c = m.joint(clavicle), u = m.joint(upper);
    if (u >= 0 && saysShoulder(t.names[u]))
      m.notes.push_back(std::string(boneName(upper)) + ": " + inQuotes(t.names[u]) +
                        " is the upper arm here (the joint above the elbow" +
                        (c >= 0 ? ", below the clavicle " + inQuotes(t.names[c]) : std::string()) +
                        "), though the name is the clavicle's in other conventions");
    else if (c >= 0 && u >= 0 && saysShoulder(t.names[c]))
      m.notes.push_back(std::string(boneName(clavicle)) + ": " + inQuotes(t.names[c]) + " is the clavicle here (above the upper arm " +
                        inQuotes(t.names[u]) + "), though the name is the upper arm's in other conventions");
  }

  for (int side = 0; side < 2; ++side) {
    const int hand = m.joint(side == 0 ? Bone::LeftHand : Bone::RightHand);
    if (hand >= 0) guessFingers(t, hand, side, m);
    else m.notes.push_back(std::string(side == 0 ? "left" : "right") + " fingers: none (no hand)");
  }
  return m;
}

// ---- Loading ----------------------------------------------------------------

class MapReader {
 public:
  MapReader(const std::string& file, const std::string& text, const Asset& asset, Diagnostics& d)
      : file_(file), lines_(text), places_(text), tree_(asset.skeleton), diags_(d) {
    for (const auto& [pointer, offset] : places_.duplicates)
      warnAt(static_cast<std::ptrdiff_t>(offset), pointer.substr(1) + ": duplicate key; the last one is used");
  }

  void read(const Json& doc, JointMap& m) {
    unknownKeys(doc, "", {"comment", "bones", "chains"});
    if (doc.contains("comment") && !doc["comment"].is_string()) warn("/comment", "expected a string");
    const Json& bones = section(doc, "bones");
    const Json& chains = section(doc, "chains");
    for (auto it = bones.begin(); it != bones.end(); ++it) {
      const std::string ptr = "/bones/" + JsonPlaces::escape(it.key());
      const auto b = boneFromName(it.key());
      if (!b) {
        warn(ptr, "unknown bone '" + it.key() + "' ignored (bones: hips, head, leftEye, ..., rightToes)", true);
        continue;
      }
      if (!it.value().is_string()) {
        warn(ptr, "expected a joint name, \"#N\" or \"\" for none; ignored");
        continue;
      }
      m.bones[at(*b)] = joint(it.value().get<std::string>(), ptr);
    }
    for (auto it = chains.begin(); it != chains.end(); ++it) {
      const std::string ptr = "/chains/" + JsonPlaces::escape(it.key());
      const auto c = chainFromName(it.key());
      if (!c) {
        warn(ptr, "unknown chain '" + it.key() + "' ignored (chains: spine, neck, leftThumb, ..., rightLittle)", true);
        continue;
      }
      if (!it.value().is_array()) {
        warn(ptr, "expected an array of joint names root to tip ([] for none); ignored");
        continue;
      }
      std::vector<int> chain;
      for (std::size_t k = 0; k < it.value().size(); ++k) {
        const std::string kp = ptr + "/" + std::to_string(k);
        const Json& v = it.value()[k];
        if (!v.is_string()) {
          warn(kp, "expected a joint name or \"#N\"; ignored");
          continue;
        }
        const int j = joint(v.get<std::string>(), kp);
        if (j < 0) {
          if (!v.get<std::string>().empty()) continue;  // already warned
          warn(kp, "an empty name in a chain; ignored");
          continue;
        }
        if (!chain.empty() && !tree_.above(chain.back(), j))
          warn(kp, inQuotes(tree_.names[j]) + " is not below " + inQuotes(tree_.names[chain.back()]) +
                       ": a chain goes root to tip");
        chain.push_back(j);
      }
      m.chains[at(*c)] = std::move(chain);
    }
    dropDuplicates(m, [&](int j, const std::string& keeps, const std::string& loses, int) {
      std::string ptr = "/bones/" + loses;
      if (const auto br = loses.find('['); br != std::string::npos)
        ptr = "/chains/" + loses.substr(0, br) + "/" + loses.substr(br + 1, loses.size() - br - 2);
      warn(ptr, "joint " + inQuotes(tree_.names[j]) + " is already mapped as " + keeps + "; dropped here");
    });
    std::string missing;
    for (Bone b : kRequired)
      if (m.joint(b) < 0) missing += (missing.empty() ? "" : ", ") + std::string(boneName(b));
    if (!missing.empty()) {
      const std::ptrdiff_t offset = places_.value("/bones") >= 0 ? places_.value("/bones") : 0;
      warnAt(offset, "required bones not mapped: " + missing);
    }
    checkOrder(m);
    m.notes.push_back("all entries from " + file_);
  }

 private:
  // Limb joints out of order are likely typos (left for right, lower for upper).
  // Feet are not checked: RobotExpressive's are IK targets under the root.
  void checkOrder(const JointMap& m) {
    const std::pair<Bone, Bone> pairs[] = {
        {Bone::Hips, Bone::Head},          {Bone::LeftShoulder, Bone::LeftUpperArm},
        {Bone::LeftUpperArm, Bone::LeftLowerArm}, {Bone::LeftLowerArm, Bone::LeftHand},
        {Bone::RightShoulder, Bone::RightUpperArm}, {Bone::RightUpperArm, Bone::RightLowerArm},
        {Bone::RightLowerArm, Bone::RightHand},   {Bone::LeftUpperLeg, Bone::LeftLowerLeg},
        {Bone::RightUpperLeg, Bone::RightLowerLeg}};
    for (auto [a, b] : pairs) {
      const int ja = m.joint(a), jb = m.joint(b);
      if (ja < 0 || jb < 0 || tree_.above(ja, jb)) continue;
      warn("/bones/" + std::string(boneName(b)), std::string(boneName(b)) + " " + inQuotes(tree_.names[jb]) +
                                                     " is not below " + std::string(boneName(a)) + " " +
                                                     inQuotes(tree_.names[ja]));
    }
  }

  // A joint by name, or "#N" by index; -1 (with a warning) when the skeleton lacks it.
  int joint(const std::string& name, const std::string& ptr) {
    if (name.empty()) return -1;
    if (const int j = tree_.find(name); j >= 0) return j;
    if (name[0] == '#') {
      const std::string digits = name.substr(1);
      const bool number = !digits.empty() && digits.size() <= 9 &&
                          std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; });
      if (!number) {
        warn(ptr, "'" + name + "' is neither a joint name nor \"#N\" with N a joint index; ignored");
        return -1;
      }
      const int j = std::stoi(digits);
      if (j < tree_.count()) return j;
      warn(ptr, "joint index " + name + " out of range: the skeleton has " + std::to_string(tree_.count()) +
                    " joints (#0 to #" + std::to_string(tree_.count() - 1) + "); ignored");
      return -1;
    }
    warn(ptr, "no joint named '" + name + "' in the skeleton; ignored");
    return -1;
  }

  void warnAt(std::ptrdiff_t offset, const std::string& message) {
    const auto [line, column] = lines_.at(offset);
    diags_.warning(file_, message, line, column);
  }
  void warn(const std::string& pointer, const std::string& message, bool atKey = false) {
    std::ptrdiff_t offset = atKey ? places_.key(pointer) : places_.value(pointer);
    if (offset < 0) offset = places_.value(pointer);
    warnAt(offset, pointer.substr(1) + ": " + message);
  }
  void unknownKeys(const Json& obj, const std::string& where, std::initializer_list<const char*> known) {
    for (auto it = obj.begin(); it != obj.end(); ++it) {
      const bool ok = std::any_of(known.begin(), known.end(), [&](const char* k) { return it.key() == k; });
      if (!ok) warn(where + "/" + JsonPlaces::escape(it.key()), "unknown key '" + it.key() + "' ignored", true);
    }
  }
  const Json& section(const Json& doc, const char* key) {
    static const Json empty = Json::object();
    if (!doc.contains(key)) return empty;
    if (doc[key].is_object()) return doc[key];
    warn(std::string("/") + key, "expected an object; ignored");
    return empty;
  }

  const std::string& file_;
  LineIndex lines_;
  JsonPlaces places_;
  Tree tree_;
  Diagnostics& diags_;
};

JointMapResult load(const std::string& path, const Asset& asset) {
  JointMapResult r;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    r.diagnostics.error(path, "cannot read the joint map '" + path + "' (missing or unreadable)");
    return r;
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  Json doc;
  if (!json_detail::parseJsonText(path, text, doc, r.diagnostics)) return r;
  if (!doc.is_object()) {
    r.diagnostics.error(path, "expected an object with \"bones\" and \"chains\"", 1, 1);
    return r;
  }
  MapReader reader(path, text, asset, r.diagnostics);
  reader.read(doc, r.map);
  std::stable_sort(r.diagnostics.items.begin(), r.diagnostics.items.end(), [](const Diagnostic& a, const Diagnostic& b) {
    return std::pair{a.line, a.column} < std::pair{b.line, b.column};
  });
  return r;
}

JointMapResult guess(const Asset& asset) {
  JointMapResult r;
  const Tree t(asset.skeleton);
  const bool vrm = asset.hasHumanoid && asset.humanoid.bones.count("hips") &&
                   t.find(asset.humanoid.bones.at("hips")) >= 0;
  r.map = vrm ? fromHumanoid(asset, t) : fromNames(asset, t);
  dropDuplicates(r.map, [&](int j, const std::string& keeps, const std::string& loses, int) {
    r.map.notes.push_back(loses + ": " + inQuotes(t.name(j)) + " is already " + keeps + "; dropped");
  });
  noteMissing(r.map);
  return r;
}

// A JSON string literal.
std::string quoted(const std::string& s) { return Json(s).dump(); }

}  // namespace

std::string_view boneName(Bone bone) noexcept {
  const auto i = static_cast<std::size_t>(bone);
  return i < kBoneNames.size() ? kBoneNames[i] : std::string_view();
}

std::optional<Bone> boneFromName(std::string_view name) noexcept {
  for (std::size_t i = 0; i < kBoneNames.size(); ++i)
    if (kBoneNames[i] == name) return static_cast<Bone>(i);
  return std::nullopt;
}

std::string_view chainName(Chain chain) noexcept {
  const auto i = static_cast<std::size_t>(chain);
  return i < kChainNames.size() ? kChainNames[i] : std::string_view();
}

std::optional<Chain> chainFromName(std::string_view name) noexcept {
  for (std::size_t i = 0; i < kChainNames.size(); ++i)
    if (kChainNames[i] == name) return static_cast<Chain>(i);
  return std::nullopt;
}

std::string JointMap::canonicalName(int joint) const {
  if (joint < 0) return {};
  for (std::size_t b = 0; b < bones.size(); ++b)
    if (bones[b] == joint) return std::string(kBoneNames[b]);
  for (std::size_t c = 0; c < chains.size(); ++c)
    for (std::size_t k = 0; k < chains[c].size(); ++k)
      if (chains[c][k] == joint) return std::string(kChainNames[c]) + "[" + std::to_string(k) + "]";
  return {};
}

JointMapResult loadJointMap(const std::string& path, const Asset& asset) {
  try {
    return load(path, asset);
  } catch (const std::exception& e) {  // never throws: a bad map is a diagnostic
    JointMapResult r;
    r.diagnostics.error(path, std::string("cannot load the joint map: ") + e.what());
    return r;
  }
}

JointMapResult guessJointMap(const Asset& asset) {
  try {
    return guess(asset);
  } catch (const std::exception& e) {  // only std::bad_alloc can get here
    JointMapResult r;
    r.diagnostics.error(asset.sourcePath, std::string("cannot guess the joint map: ") + e.what());
    return r;
  }
}

std::string jointMapJson(const JointMap& map, const Skeleton& skeleton) {
  const Tree t(skeleton);
  // A name identifies a joint only when it is unique and not itself "#..."; else "#N".
  auto ref = [&](int j) -> std::string {
    if (!t.valid(j)) return "";
    const std::string& n = t.names[static_cast<std::size_t>(j)];
    const bool unique = !n.empty() && n[0] != '#' && t.find(n) == j;
    return unique ? n : "#" + std::to_string(j);
  };
  std::string out = "{\n  \"comment\": \"written by jointMapJson\",\n  \"bones\": {\n";
  for (int b = 0; b < kBoneCount; ++b) {
    out += "    " + quoted(std::string(kBoneNames[static_cast<std::size_t>(b)])) + ": " +
           quoted(ref(map.bones[static_cast<std::size_t>(b)])) + (b + 1 < kBoneCount ? ",\n" : "\n");
  }
  out += "  },\n  \"chains\": {\n";
  for (int c = 0; c < kChainCount; ++c) {
    std::string items;
    for (int j : map.chains[static_cast<std::size_t>(c)])
      if (t.valid(j)) items += (items.empty() ? "" : ", ") + quoted(ref(j));
    out += "    " + quoted(std::string(kChainNames[static_cast<std::size_t>(c)])) + ": [" + items + "]" +
           (c + 1 < kChainCount ? ",\n" : "\n");
  }
  out += "  }\n}\n";
  return out;
}

}  // namespace marionette::retarget
