// The joint map guessed from the asset alone: its VRM humanoid map, else the
// character profile's guess from names and topology plus clavicles and fingers.
#include "marionette/rig/joint_map.hpp"

#include <algorithm>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "marionette/rig/character_profile.hpp"
#include "joint_map_detail.hpp"
#include "profile_guess.hpp"
#include "profile_skeleton.hpp"

namespace marionette::retarget {

namespace {
using profile_detail::inQuotes;
using profile_detail::Tree;
using namespace joint_map_detail;

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

// From the body joints guessed by names and topology (profile_detail::guessBodyJoints).
JointMap fromNames(const Tree& t, const CharacterProfile& p, const profile_detail::Notes& found) {
  JointMap m;
  // How each joint was found, for the record.
  for (const auto& [field, n] : found) m.notes.push_back("profile " + n);
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

}  // namespace

JointMapResult joint_map_detail::guessFromBody(const Asset& asset, const Tree& t, const CharacterProfile* body,
                                                 const profile_detail::Notes* found) {
  JointMapResult r;
  const std::string& file = asset.sourcePath;
  const bool vrm = asset.hasHumanoid && asset.humanoid.bones.count("hips") &&
                   t.find(asset.humanoid.bones.at("hips")) >= 0;
  if (vrm) {
    r.map = fromHumanoid(asset, t);
  } else if (body && found) {
    r.map = fromNames(t, *body, *found);
  } else {
    CharacterProfile p;
    profile_detail::Notes notes;
    profile_detail::guessBodyJoints(asset, t, p, notes);
    r.map = fromNames(t, p, notes);
  }
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

JointMapResult guessJointMap(const Asset& asset) {
  try {
    return guessFromBody(asset, Tree(asset.skeleton), nullptr, nullptr);
  } catch (const std::exception& e) {  // only std::bad_alloc can get here
    JointMapResult r;
    r.diagnostics.error(asset.sourcePath, std::string("cannot guess the joint map: ") + e.what());
    return r;
  }
}

}  // namespace marionette::retarget
