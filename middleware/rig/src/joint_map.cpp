#include "marionette/core/text_file.hpp"
#include "marionette/rig/joint_map.hpp"

#include <algorithm>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <utility>

#include <nlohmann/json.hpp>

#include "marionette/rig/character_profile.hpp"
#include "marionette/rig/detail/json_places.hpp"
#include "limb_guess.hpp"
#include "profile_skeleton.hpp"

namespace marionette::retarget {

namespace {
using Json = nlohmann::json;
using json_detail::JsonPlaces;
using json_detail::JsonReaderBase;
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

// An entry of a map: a bone, or joint k of a chain.
struct Entry {
  int bone = -1, chain = -1, k = -1;
};
std::string entryName(const Entry& e) {
  if (e.bone >= 0) return std::string(kBoneNames[static_cast<std::size_t>(e.bone)]);
  return std::string(kChainNames[static_cast<std::size_t>(e.chain)]) + "[" + std::to_string(e.k) + "]";
}
Entry entryOf(Bone b) { return {static_cast<int>(b), -1, -1}; }

// Drops every later mention of a joint already mapped (bones first, in enum
// order, then chains), so that a map never names a joint twice; calls `dropped`
// with the joint, the entry that keeps it and the one that loses it (its index
// in the chain before any drop).
template <class F>
void dropDuplicates(JointMap& m, F&& dropped) {
  std::map<int, Entry> owner;
  for (int b = 0; b < kBoneCount; ++b) {
    int& j = m.bones[static_cast<std::size_t>(b)];
    if (j < 0) continue;
    const Entry e{b, -1, -1};
    if (auto [it, fresh] = owner.emplace(j, e); !fresh) dropped(j, it->second, e), j = -1;
  }
  for (int c = 0; c < kChainCount; ++c) {
    auto& chain = m.chains[static_cast<std::size_t>(c)];
    std::vector<int> kept;
    for (std::size_t k = 0; k < chain.size(); ++k) {
      const Entry e{-1, c, static_cast<int>(k)};
      if (auto [it, fresh] = owner.emplace(chain[k], e); fresh) kept.push_back(chain[k]);
      else dropped(chain[k], it->second, e);
    }
    chain = std::move(kept);
  }
}

std::string missingRequired(const JointMap& m) {
  std::string missing;
  for (Bone b : kRequired)
    if (m.joint(b) < 0) missing += (missing.empty() ? "" : ", ") + std::string(boneName(b));
  return missing;
}

// In the canonical set but absent from some real skeletons (CesiumMan has no
// clavicles, RobotExpressive and pirouette.bvh no toes): a file must say "" or
// [] for them, so that an absence is a decision, not an oversight.
constexpr Bone kExpectedBones[] = {Bone::LeftShoulder, Bone::RightShoulder, Bone::LeftToes, Bone::RightToes};
constexpr Chain kExpectedChains[] = {Chain::Spine, Chain::Neck};

struct Problem {
  Entry entry;
  std::string message;
};

// What the topology and the rest pose say against a map: each limb joint below
// the one before it, the legs and arms below the hips, the spine between the
// hips and the neck and not above the legs (turning a spine joint must not turn
// the legs), the neck above the head, eyes and jaw below it, fingers below the
// hand, and left joints on the character's left of the right ones.
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

// The finger chains below a hand (or a forearm): per finger, its named joints
// root to tip. Joints of a finger that branch away from its first chain are left
// out with a note.
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
    m.notes.push_back(sideName + " fingers: joints below " + inQuotes(t.names[hand]) + " not named after a finger (" +
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

// The lowest joint above both `a` and `b` (or one of them), or -1.
int commonAncestor(const Tree& t, int a, int b) {
  for (int j = a; j >= 0; j = t.parent[j])
    if (j == b || t.above(j, b)) return j;
  return -1;
}

// The hips are the joint the upper legs and the upper body share: turning it
// turns both. When the names point elsewhere, topology decides, with a note, and
// the spine becomes the path from there up to the neck.
void settleHips(const Tree& t, JointMap& m) {
  const int left = m.joint(Bone::LeftUpperLeg), right = m.joint(Bone::RightUpperLeg);
  const auto& neck = m.chain(Chain::Neck);
  auto& spine = m.chains[at(Chain::Spine)];
  const int top = !neck.empty() ? neck.front() : m.joint(Bone::Head) >= 0 ? m.joint(Bone::Head)
                                                 : !spine.empty() ? spine.back() : -1;
  if (left < 0 || right < 0 || top < 0) return;
  const int shared = commonAncestor(t, commonAncestor(t, left, right), top);
  const int old = m.joint(Bone::Hips);
  if (shared < 0 || shared == old || shared == top) return;  // the last: no body above the legs; the checks report it
  std::vector<int> path;  // from above `shared` up to below `top`
  for (int j = t.parent[top]; j >= 0 && j != shared; j = t.parent[j]) path.push_back(j);
  std::reverse(path.begin(), path.end());
  m.bones[at(Bone::Hips)] = shared;
  if (neck.empty() && !spine.empty() && top == spine.back()) path.push_back(top);  // the spine's end was the top
  spine = std::move(path);
  const std::string was = old >= 0 ? inQuotes(t.names[old]) : std::string("none");
  m.notes.push_back("hips: " + inQuotes(t.names[shared]) + ", not " + was + " (topology: the joint the upper legs " +
                    inQuotes(t.names[left]) + ", " + inQuotes(t.names[right]) + " and the upper body share" +
                    (old >= 0 && t.above(old, shared) ? "; the legs hang from " + inQuotes(t.names[shared]) + ", below " + was
                     : t.above(shared, old) ? "; " + was + " turns the upper body only" : std::string()) +
                    "); spine now " + std::to_string(spine.size()) + " joints");
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

  // The hips are where the legs and the spine part. Pab's legs hang from "Spine"
  // (below "Hips" and "Pelvis"), RobotExpressive's from "Body" (above "Hips").
  settleHips(t, m);

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
    const int forearm = m.joint(side == 0 ? Bone::LeftLowerArm : Bone::RightLowerArm);
    const std::string sideName = side == 0 ? "left" : "right";
    if (hand >= 0) {
      guessFingers(t, hand, side, m);
    } else if (forearm >= 0) {
      // RobotExpressive: palms and the thumb hang from the forearm, no joint turns the whole hand.
      m.notes.push_back(sideName + " fingers: no hand joint; searched below the forearm " + inQuotes(t.names[forearm]));
      guessFingers(t, forearm, side, m);
    } else {
      m.notes.push_back(sideName + " fingers: none (no hand or forearm)");
    }
  }
  return m;
}

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
    if (const std::string missing = missingRequired(m); !missing.empty())
      warnAt(bonesAt, "required bones not mapped: " + missing);
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
  std::array<bool, kChainCount> chainListed_{};                 // the file has the chain (maybe [])
};

JointMapResult load(const std::string& path, const Asset& asset) {
  JointMapResult r;
  std::string text, why;
  if (!readTextFile(path, text, why)) {
    r.diagnostics.error(path, "cannot read the joint map '" + path + "': " + why);
    return r;
  }
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
  const std::string& file = asset.sourcePath;
  const bool vrm = asset.hasHumanoid && asset.humanoid.bones.count("hips") &&
                   t.find(asset.humanoid.bones.at("hips")) >= 0;
  r.map = vrm ? fromHumanoid(asset, t) : fromNames(asset, t);
  dropDuplicates(r.map, [&](int j, const Entry& keeps, const Entry& loses) {
    r.diagnostics.warning(file, "joint map guess: " + entryName(loses) + ": joint " + inQuotes(t.name(j)) + " is already " +
                                    entryName(keeps) + "; dropped");
  });
  if (const std::string missing = missingRequired(r.map); !missing.empty())
    r.diagnostics.warning(file, "joint map guess: required bones not found: " + missing);
  std::string absent;
  for (Bone b : kExpectedBones)
    if (r.map.joint(b) < 0) absent += (absent.empty() ? "" : ", ") + std::string(boneName(b));
  for (Chain c : kExpectedChains)
    if (r.map.chain(c).empty()) absent += (absent.empty() ? "" : ", ") + std::string(chainName(c));
  if (!absent.empty()) r.map.notes.push_back("not found (the skeleton may have none): " + absent);
  // The guess keeps what the names say and reports what the topology contradicts.
  for (const Problem& p : topologyProblems(r.map, t, asset.skeleton))
    r.diagnostics.warning(file, "joint map guess: " + p.message);
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
