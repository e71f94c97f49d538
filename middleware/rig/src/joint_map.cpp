// Joint maps: the canonical names, a map file read and checked against its
// skeleton, and a map written back as JSON. The guess is joint_map_guess.cpp.
#include "marionette/core/text_file.hpp"
#include "marionette/rig/joint_map.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <utility>

#include <nlohmann/json.hpp>

#include "marionette/rig/detail/json_places.hpp"
#include "marionette/core/enum_names.hpp"
#include "joint_map_detail.hpp"
#include "limb_guess.hpp"
#include "profile_skeleton.hpp"

namespace marionette::retarget {

namespace {
using Json = nlohmann::json;
using json_detail::JsonPlaces;
using json_detail::JsonReaderBase;
using profile_detail::inQuotes;
using profile_detail::Tree;
using namespace joint_map_detail;

// ---- Consistency ------------------------------------------------------------

// Without these a humanoid cannot be driven: a motion needs its root, head and limbs.
constexpr Bone kRequired[] = {Bone::Hips,          Bone::Head,          Bone::LeftUpperArm,  Bone::LeftLowerArm,
                              Bone::LeftHand,      Bone::RightUpperArm, Bone::RightLowerArm, Bone::RightHand,
                              Bone::LeftUpperLeg,  Bone::LeftLowerLeg,  Bone::LeftFoot,      Bone::RightUpperLeg,
                              Bone::RightLowerLeg, Bone::RightFoot};

Entry entryOf(Bone b) { return {static_cast<int>(b), -1, -1}; }

}  // namespace

std::vector<Bone> missingRequiredBones(const JointMap& map) {
  std::vector<Bone> missing;
  for (Bone b : kRequired)
    if (map.joint(b) < 0) missing.push_back(b);
  return missing;
}

namespace joint_map_detail {

std::string entryName(const Entry& e) {
  if (e.bone >= 0) return std::string(kBoneNames[static_cast<std::size_t>(e.bone)]);
  return std::string(kChainNames[static_cast<std::size_t>(e.chain)]) + "[" + std::to_string(e.k) + "]";
}

std::string missingRequired(const JointMap& m) {
  std::string missing;
  for (Bone b : missingRequiredBones(m)) missing += (missing.empty() ? "" : ", ") + std::string(boneName(b));
  return missing;
}

std::vector<Problem> topologyProblems(const JointMap& m, const Tree& t, const Skeleton& s) {
  std::vector<Problem> out;
  auto q = [&](int j) { return inQuotes(t.name(j)); };
  auto describe = [&](Entry e, int j) { return entryName(e) + " " + q(j); };
  auto below = [&](Entry upper, int ju, Entry lower, int jl) {
    if (ju < 0 || jl < 0 || t.above(ju, jl)) return;
    out.push_back({lower, describe(lower, jl) + " is not below " + describe(upper, ju)});
  };
  auto bone = [&](Bone b) { return std::pair{entryOf(b), m.joint(b)}; };
  // The nearest mapped joint of `bs` (in order), for checks that skip absent ones.
  auto first = [&](std::initializer_list<Bone> bs) {
    for (Bone b : bs)
      if (m.joint(b) >= 0) return bone(b);
    return std::pair{Entry{}, -1};
  };
  // Limb bones in order: each below the one before it, and its child. A joint
  // between keeps its rest rotation when retargeted, and a named one there means
  // the names lie (a forearm called the upper arm). A foot need not be below its
  // shin: RobotExpressive's are IK targets under the root.
  const std::pair<Bone, Bone> segments[] = {
      {Bone::LeftUpperArm, Bone::LeftLowerArm},   {Bone::LeftLowerArm, Bone::LeftHand},
      {Bone::RightUpperArm, Bone::RightLowerArm}, {Bone::RightLowerArm, Bone::RightHand},
      {Bone::LeftUpperLeg, Bone::LeftLowerLeg},   {Bone::RightUpperLeg, Bone::RightLowerLeg},
      {Bone::LeftLowerLeg, Bone::LeftFoot},       {Bone::RightLowerLeg, Bone::RightFoot}};
  for (auto [a, b] : segments) {
    const int ja = m.joint(a), jb = m.joint(b);
    if (b != Bone::LeftFoot && b != Bone::RightFoot) below(entryOf(a), ja, entryOf(b), jb);
    if (ja < 0 || jb < 0 || !t.above(ja, jb) || t.parent[jb] == ja) continue;
    std::vector<std::string> between;
    for (int j = t.parent[jb]; j != ja; j = t.parent[j]) between.insert(between.begin(), t.names[j]);
    out.push_back({entryOf(b), describe(entryOf(b), jb) + " is not the child of " + describe(entryOf(a), ja) + ": " +
                                   profile_detail::joined(between) + " lies between (it keeps its rest rotation)"});
  }
  const std::pair<Bone, Bone> pairs[] = {{Bone::LeftShoulder, Bone::LeftUpperArm}, {Bone::RightShoulder, Bone::RightUpperArm},
                                         {Bone::Head, Bone::LeftEye},              {Bone::Head, Bone::RightEye},
                                         {Bone::Head, Bone::Jaw},                  {Bone::LeftFoot, Bone::LeftToes},
                                         {Bone::RightFoot, Bone::RightToes}};
  for (auto [a, b] : pairs) below(entryOf(a), m.joint(a), entryOf(b), m.joint(b));

  const int hips = m.joint(Bone::Hips);
  const Entry hipsE = entryOf(Bone::Hips);
  for (Bone b : {Bone::LeftUpperLeg, Bone::RightUpperLeg}) below(hipsE, hips, entryOf(b), m.joint(b));
  for (auto [e, j] : {first({Bone::LeftShoulder, Bone::LeftUpperArm}), first({Bone::RightShoulder, Bone::RightUpperArm})})
    below(hipsE, hips, e, j);
  // Spine, neck and head in a row, from the hips up.
  std::vector<std::pair<Entry, int>> column{{hipsE, hips}};
  for (Chain c : {Chain::Spine, Chain::Neck}) {
    const auto& chain = m.chain(c);
    for (std::size_t k = 0; k < chain.size(); ++k) column.push_back({Entry{-1, static_cast<int>(c), static_cast<int>(k)}, chain[k]});
  }
  column.push_back(bone(Bone::Head));
  for (std::size_t i = 1; i < column.size(); ++i) {
    std::size_t p = i;  // the nearest mapped joint before this one
    while (p > 0 && column[p - 1].second < 0) --p;
    if (p > 0) below(column[p - 1].first, column[p - 1].second, column[i].first, column[i].second);
  }
  const auto& spine = m.chain(Chain::Spine);
  for (std::size_t k = 0; k < spine.size(); ++k)
    for (Bone leg : {Bone::LeftUpperLeg, Bone::RightUpperLeg})
      if (t.above(spine[k], m.joint(leg))) {
        out.push_back({Entry{-1, static_cast<int>(Chain::Spine), static_cast<int>(k)},
                       "spine[" + std::to_string(k) + "] " + q(spine[k]) + " is above " + describe(entryOf(leg), m.joint(leg)) +
                           ": the legs hang from it, so it is the hips (or below them), not the spine"});
        break;
      }
  // Fingers below the hand, or below the forearm of a skeleton without a hand joint.
  for (int side = 0; side < 2; ++side) {
    const auto [he, hand] = side == 0 ? first({Bone::LeftHand, Bone::LeftLowerArm}) : first({Bone::RightHand, Bone::RightLowerArm});
    for (int f = 0; f < 5; ++f) {
      const int c = static_cast<int>(Chain::LeftThumb) + side * 5 + f;
      const auto& chain = m.chains[static_cast<std::size_t>(c)];
      for (std::size_t k = 0; k < chain.size(); ++k) {
        const Entry e{-1, c, static_cast<int>(k)};
        if (k == 0) below(he, hand, e, chain[0]);
        else below(Entry{-1, c, static_cast<int>(k - 1)}, chain[k - 1], e, chain[k]);
      }
    }
  }

  // Sides from the rest pose: the left upper arm and leg on the character's left.
  const std::vector<glm::vec3> rest = profile_detail::restPositions(s, t);
  const profile_detail::BodyChain body{hips, !m.chain(Chain::Neck).empty() ? m.chain(Chain::Neck).front() : -1,
                                       m.joint(Bone::Head)};
  const std::array<profile_detail::LegJoints, 2> legs{
      profile_detail::LegJoints{m.joint(Bone::LeftUpperLeg), m.joint(Bone::LeftLowerLeg), m.joint(Bone::LeftFoot),
                                m.joint(Bone::LeftToes)},
      profile_detail::LegJoints{m.joint(Bone::RightUpperLeg), m.joint(Bone::RightLowerLeg), m.joint(Bone::RightFoot),
                                m.joint(Bone::RightToes)}};
  for (auto [l, r] : {std::pair{Bone::LeftUpperLeg, Bone::RightUpperLeg}, std::pair{Bone::LeftUpperArm, Bone::RightUpperArm}}) {
    if (m.joint(l) < 0 || m.joint(r) < 0) continue;
    std::string facing;
    if (profile_detail::restSide(rest, body, legs, m.joint(l), m.joint(r), &facing) < 0)
      out.push_back({entryOf(l), describe(entryOf(l), m.joint(l)) + " lies on the character's right of " +
                                     describe(entryOf(r), m.joint(r)) + " in the rest pose (" + facing +
                                     "): left and right swapped?"});
  }
  return out;
}

}  // namespace joint_map_detail

namespace {

// ---- Loading ----------------------------------------------------------------

class MapReader : JsonReaderBase {
 public:
  MapReader(const std::string& file, const std::string& text, const Asset& asset, Diagnostics& d)
      : JsonReaderBase(file, text, d, "ignored"), tree_(asset.skeleton), skeleton_(asset.skeleton) {}

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
      bonePtr_[at(*b)] = ptr;
      declaredAbsent_[at(*b)] = it.value().get<std::string>().empty();
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
      chainListed_[at(*c)] = true;
      std::vector<int> chain;
      auto& ptrs = chainPtr_[at(*c)];
      for (std::size_t k = 0; k < it.value().size(); ++k) {
        const std::string kp = ptr + "/" + std::to_string(k);
        const Json& v = it.value()[k];
        if (!v.is_string()) {
          warn(kp, "expected a joint name or \"#N\"; ignored");
          continue;
        }
        const int j = joint(v.get<std::string>(), kp);
        if (j < 0) {
          if (v.get<std::string>().empty()) warn(kp, "an empty name in a chain; ignored");
          continue;  // else already warned
        }
        chain.push_back(j);
        ptrs.push_back(kp);
      }
      m.chains[at(*c)] = std::move(chain);
    }
    // A joint mapped twice keeps its first entry (bones in canonical order, then chains).
    std::array<std::vector<bool>, kChainCount> dropped;
    for (std::size_t c = 0; c < dropped.size(); ++c) dropped[c].assign(m.chains[c].size(), false);
    dropDuplicates(m, [&](int j, const Entry& keeps, const Entry& loses) {
      warn(pointer(loses), "joint " + inQuotes(tree_.names[j]) + " is already mapped as " + entryName(keeps) + " (" +
                               pointer(keeps).substr(1) + "); dropped here");
      if (loses.chain >= 0) dropped[static_cast<std::size_t>(loses.chain)][static_cast<std::size_t>(loses.k)] = true;
    });
    for (std::size_t c = 0; c < dropped.size(); ++c) {
      std::vector<std::string> kept;
      for (std::size_t k = 0; k < dropped[c].size(); ++k)
        if (!dropped[c][k]) kept.push_back(chainPtr_[c][k]);
      chainPtr_[c] = std::move(kept);
    }
    const std::ptrdiff_t bonesAt = places_.value("/bones") >= 0 ? places_.value("/bones") : 0;
    // A required bone the file maps to "" is the author's statement that the skeleton has
    // none (RobotExpressive's arms end at the forearm): a note. One left out or whose name
    // did not resolve is an oversight: a warning.
    std::string missing, absent;
    for (Bone b : kRequired)
      if (m.joint(b) < 0) (declaredAbsent_[at(b)] ? absent : missing) += (", " + std::string(boneName(b)));
    if (!missing.empty()) warnAt(bonesAt, "required bones not mapped: " + missing.substr(2));
    if (!absent.empty())
      m.notes.push_back("required bones the file declares absent (\"\"): " + absent.substr(2) +
                        "; their limbs end one joint early");
    std::string unsaid;
    for (Bone b : kExpectedBones)
      if (bonePtr_[at(b)].empty()) unsaid += (unsaid.empty() ? "" : ", ") + std::string(boneName(b));
    for (Chain c : kExpectedChains)
      if (!chainListed_[at(c)]) unsaid += (unsaid.empty() ? "" : ", ") + std::string(chainName(c));
    if (!unsaid.empty())
      warnAt(bonesAt, "not in the file: " + unsaid + " (write \"\" or [] where the skeleton has none)");
    for (const Problem& p : topologyProblems(m, tree_, skeleton_)) warn(pointer(p.entry), p.message);
    m.notes.push_back("all entries from " + file_);
  }

 private:
  // The JSON pointer an entry was read from ("/bones" for one the file leaves out).
  std::string pointer(const Entry& e) const {
    if (e.bone >= 0) {
      const std::string& p = bonePtr_[static_cast<std::size_t>(e.bone)];
      return p.empty() ? "/bones" : p;
    }
    const auto& ps = chainPtr_[static_cast<std::size_t>(e.chain)];
    return static_cast<std::size_t>(e.k) < ps.size() ? ps[static_cast<std::size_t>(e.k)] : "/chains";
  }

  // A joint by name, or "#N" by index; -1 (with a warning) when the skeleton lacks it.
  int joint(const std::string& name, const std::string& ptr) {
    if (name.empty()) return -1;
    if (const int j = tree_.find(name); j >= 0) {
      const auto same = std::count(tree_.names.begin(), tree_.names.end(), name);
      if (same > 1)
        warn(ptr, std::to_string(same) + " joints are named '" + name + "': the first one (#" + std::to_string(j) +
                      ") is used; write \"#N\" to pick another");
      return j;
    }
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


  Tree tree_;
  const Skeleton& skeleton_;
  std::array<std::string, kBoneCount> bonePtr_;                // where each bone was read; "" when not
  std::array<std::vector<std::string>, kChainCount> chainPtr_;  // where each chain joint was read
  std::array<bool, kBoneCount> declaredAbsent_{};
  std::array<bool, kChainCount> chainListed_{};                 // the file has the chain (maybe [])
};

JointMapResult load(const std::string& path, const Asset& asset, const FileReader& files) {
  JointMapResult r;
  std::string text;
  if (!readTextFile(files, path, text, r.diagnostics, "cannot read the joint map '" + path + "'")) return r;
  Json doc;
  if (!json_detail::parseJsonText(path, text, doc, r.diagnostics)) return r;
  if (!doc.is_object()) {
    r.diagnostics.error(path, "expected an object with \"bones\" and \"chains\"", 1, 1);
    return r;
  }
  // Valid JSON of another kind (a profile, a scene) would otherwise map nothing and bind nothing.
  if (!doc.contains("bones") && !doc.contains("chains")) {
    r.diagnostics.error(path, "not a joint map: it has neither \"bones\" nor \"chains\"", 1, 1);
    return r;
  }
  MapReader reader(path, text, asset, r.diagnostics);
  reader.read(doc, r.map);
  std::stable_sort(r.diagnostics.items.begin(), r.diagnostics.items.end(), [](const Diagnostic& a, const Diagnostic& b) {
    return std::pair{a.line, a.column} < std::pair{b.line, b.column};
  });
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
  return valueOfIndexedName<Bone>(name, kBoneNames);
}

std::string_view chainName(Chain chain) noexcept {
  const auto i = static_cast<std::size_t>(chain);
  return i < kChainNames.size() ? kChainNames[i] : std::string_view();
}

std::optional<Chain> chainFromName(std::string_view name) noexcept {
  return valueOfIndexedName<Chain>(name, kChainNames);
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

JointMapResult loadJointMap(const std::string& path, const Asset& asset, const FileReader& files) {
  try {
    return load(path, asset, files);
  } catch (const std::exception& e) {  // never throws: a bad map is a diagnostic
    JointMapResult r;
    r.diagnostics.error(path, std::string("cannot load the joint map: ") + e.what());
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
