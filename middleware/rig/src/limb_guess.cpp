#include "limb_guess.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <tuple>

namespace marionette::profile_detail {

namespace {

// ---- Names ------------------------------------------------------------------

enum class Role : int { LegUpper, LegLower, LegEnd, Toe, ArmUpper, ArmLower, ArmEnd, Count };
// A role's index into per-role arrays; a limb's three roles follow each other.
constexpr std::size_t index(Role role) noexcept { return static_cast<std::size_t>(role); }
constexpr std::size_t kRoleCount = index(Role::Count);

// Name keys (words joined, side and convention noise dropped) and the role they
// name. Rank 1 marks names that are that role in some conventions only: CMU's
// 3dsMax skeleton calls the upper arm "Shoulder", Mixamo calls the clavicle so
// (and has an "Arm" below it); "Hip" is the thigh in some BVH files, the pelvis
// bone above "LeftUpLeg" in others (LHipJoint); Mixamo's "Leg" is the shin.
struct LimbWord {
  std::string_view key;
  Role role;
  int rank;
};
constexpr LimbWord kLimbWords[] = {
    {"upleg", Role::LegUpper, 0},    {"upperleg", Role::LegUpper, 0}, {"thigh", Role::LegUpper, 0},
    {"femur", Role::LegUpper, 0},    {"hip", Role::LegUpper, 1},      {"lowerleg", Role::LegLower, 0},
    {"lowleg", Role::LegLower, 0},   {"shin", Role::LegLower, 0},     {"calf", Role::LegLower, 0},
    {"knee", Role::LegLower, 0},     {"tibia", Role::LegLower, 0},    {"leg", Role::LegLower, 1},
    {"foot", Role::LegEnd, 0},       {"ankle", Role::LegEnd, 0},      {"toebase", Role::Toe, 0},
    {"toe", Role::Toe, 0},           {"toes", Role::Toe, 0},          {"footthumb", Role::Toe, 0},
    {"ball", Role::Toe, 0},          {"upperarm", Role::ArmUpper, 0}, {"uparm", Role::ArmUpper, 0},
    {"arm", Role::ArmUpper, 0},      {"humerus", Role::ArmUpper, 0},  {"shoulder", Role::ArmUpper, 1},
    {"shldr", Role::ArmUpper, 1},    {"forearm", Role::ArmLower, 0},  {"lowerarm", Role::ArmLower, 0},
    {"lowarm", Role::ArmLower, 0},   {"elbow", Role::ArmLower, 0},    {"radius", Role::ArmLower, 0},
    {"hand", Role::ArmEnd, 0},       {"wrist", Role::ArmEnd, 0},
};

const LimbWord* limbWord(std::string_view key) {
  for (const LimbWord& w : kLimbWords)
    if (w.key == key) return &w;
  return nullptr;
}

// The side and limb word of a joint name; side 0 when it is none. A side glued
// to the part in lower case ("Lefthand" in Pab, "lhand" in CMU) is split off
// only when the rest is a limb word, so "leg" stays a leg.
std::pair<int, const LimbWord*> limbName(const std::string& name) {
  const NameParts np = parts(name, kJointNoise);
  const std::string key = np.key();
  if (np.side != 0) return {np.side, limbWord(key)};
  for (const auto& [prefix, side] : {std::pair<std::string_view, int>{"left", -1}, {"right", 1}, {"l", -1}, {"r", 1}})
    if (key.size() > prefix.size() && key.compare(0, prefix.size(), prefix) == 0)
      if (const LimbWord* w = limbWord(std::string_view(key).substr(prefix.size()))) return {side, w};
  return {0, nullptr};
}

struct Candidate {
  int joint, rank;
};
using Candidates = std::array<std::vector<Candidate>, kRoleCount>;  // per role, for one side

struct Chain {
  int upper = -1, lower = -1, end = -1;
  bool detached = false;  // a leg's end that does not descend from its lower joint
  [[nodiscard]] int found() const { return (upper >= 0) + (lower >= 0) + (end >= 0); }
};

// The best-named chain of one limb: as many of its three joints as the names
// give (two at least), each below the one before, lower ranks first, then the
// tightest chain (CMU's "LeftHip" is the knee's parent, "LHipJoint" is not),
// then the shallowest. A leg's end may sit elsewhere (RobotExpressive's feet
// are IK targets under the root) when its name is the only one of that side.
Chain pickChain(const Tree& t, const Candidates& c, Role upperRole, bool leg) {
  const auto& U = c[index(upperRole)];
  const auto& L = c[index(upperRole) + 1];
  const auto& E = c[index(upperRole) + 2];
  Chain best;
  std::tuple<int, int, int, int> bestKey{1, 0, 0, 0};
  auto each = [](const std::vector<Candidate>& v, auto&& f) {
    f(Candidate{-1, 0});
    for (const Candidate& x : v) f(x);
  };
  each(U, [&](Candidate u) {
    each(L, [&](Candidate l) {
      each(E, [&](Candidate e) {
        Chain ch{u.joint, l.joint, e.joint};
        if (ch.found() < 2) return;
        if (u.joint >= 0 && l.joint >= 0 && !t.above(u.joint, l.joint)) return;
        if (l.joint < 0 && !t.above(u.joint, e.joint)) return;
        int gaps = 0;
        if (u.joint >= 0 && l.joint >= 0) gaps += t.depth[l.joint] - t.depth[u.joint];
        if (l.joint < 0) gaps += t.depth[e.joint] - t.depth[u.joint];
        if (l.joint >= 0 && e.joint >= 0) {
          if (t.above(l.joint, e.joint)) {
            gaps += t.depth[e.joint] - t.depth[l.joint];
          } else {
            const bool elsewhere = !t.above(e.joint, l.joint) && (u.joint < 0 || !t.above(e.joint, u.joint));
            if (!leg || E.size() != 1 || u.joint < 0 || !elsewhere) return;
            ch.detached = true;
          }
        }
        const int first = u.joint >= 0 ? u.joint : l.joint;
        const std::tuple<int, int, int, int> key{-ch.found(), u.rank + l.rank + e.rank, gaps, t.depth[first]};
        if (key < bestKey) bestKey = key, best = ch;
      });
    });
  });
  return best;
}

// ---- Shapes of unnamed skeletons --------------------------------------------

bool sameShape(const Tree& t, int a, int b) {
  return t.size[a] == t.size[b] && t.height[a] == t.height[b] && t.leaves[a] == t.leaves[b];
}

// j, its only child, that one's only child... down to the first joint with no
// child or several (a hand with fingers).
std::vector<int> unbranchedFrom(const Tree& t, int j) {
  std::vector<int> out{j};
  while (t.children[j].size() == 1) out.push_back(j = t.children[j][0]);
  return out;
}

// The one pair of same-shaped children of `j`, leaving out `skip` (the way to the
// head); {-1, -1} when there is none or more than one.
std::pair<int, int> mirrorPair(const Tree& t, int j, int skip) {
  std::pair<int, int> found{-1, -1};
  const auto& ch = t.children[j];
  for (std::size_t a = 0; a < ch.size(); ++a)
    for (std::size_t b = a + 1; b < ch.size(); ++b) {
      if (ch[a] == skip || ch[b] == skip || !sameShape(t, ch[a], ch[b])) continue;
      if (found.first >= 0) return {-1, -1};
      found = {ch[a], ch[b]};
    }
  return found;
}

// ---- Facing -----------------------------------------------------------------

glm::vec3 horizontal(const glm::vec3& v, const glm::vec3& up) { return v - up * glm::dot(v, up); }

std::string axisName(const glm::vec3& v) {
  static const char* const names[] = {"X", "Y", "Z"};
  for (int i = 0; i < 3; ++i)
    if (std::fabs(v[i]) > 0.9f) return std::string(v[i] > 0 ? "+" : "-") + names[i];
  char buf[64];
  std::snprintf(buf, sizeof buf, "(%.2f, %.2f, %.2f)", static_cast<double>(v.x), static_cast<double>(v.y),
                static_cast<double>(v.z));
  return buf;
}

struct Facing {
  glm::vec3 up{0, 1, 0}, forward{0, 0, 1}, left{1, 0, 0};
  bool assumed = true;
  std::string how;
};

// Where the character faces in the rest pose: toes point forward, knees bend
// forward; else the glTF convention (+Z). Up is from the hips to the neck.
// Its left is up x forward (facing +Z with +Y up, the left is +X).
Facing findFacing(const std::vector<glm::vec3>& rest, const BodyChain& body, const std::array<Chain, 2>& legs,
                  const std::array<int, 2>& toes) {
  Facing f;
  const int top = body.neck >= 0 ? body.neck : body.head;
  if (body.hips >= 0 && top >= 0) {
    const glm::vec3 d = rest[top] - rest[body.hips];
    if (glm::length(d) > 1e-6f) f.up = glm::normalize(d);
  }
  glm::vec3 sum(0.0f);
  std::array<glm::vec3, 2> toeDir{glm::vec3(0.0f), glm::vec3(0.0f)};
  for (int i = 0; i < 2; ++i)
    if (legs[i].end >= 0 && toes[i] >= 0) {
      const glm::vec3 h = horizontal(rest[toes[i]] - rest[legs[i].end], f.up);
      if (glm::length(h) > 1e-6f) sum += toeDir[i] = glm::normalize(h);
    }
  // A motion file's rest pose may be its first frame: a foot kicked up behind
  // (pab_jog.fbx) points its toes backwards. Toes more than 60 degrees apart say
  // nothing; the knees, which bend forward in any pose, decide then.
  if (glm::dot(toeDir[0], toeDir[1]) < 0.5f && glm::length(toeDir[0]) > 0.5f && glm::length(toeDir[1]) > 0.5f)
    sum = glm::vec3(0.0f);
  if (glm::length(sum) > 1e-3f) {
    f.how = "from the toes";
  } else {
    sum = glm::vec3(0.0f);
    for (const Chain& leg : legs) {
      if (leg.found() < 3) continue;
      const glm::vec3 a = rest[leg.upper], b = rest[leg.lower], c = rest[leg.end];
      const float len = glm::length(c - a);
      if (len < 1e-6f) continue;
      const glm::vec3 d = (c - a) / len;
      const glm::vec3 off = horizontal((b - a) - d * glm::dot(b - a, d), f.up);
      if (glm::length(off) > 0.02f * len) sum += off / len;
    }
    if (glm::length(sum) > 1e-3f) f.how = "from the knees";
  }
  if (f.how.empty()) {
    sum = horizontal(glm::vec3(0, 0, 1), f.up);
    if (glm::length(sum) < 1e-3f) sum = horizontal(glm::vec3(0, -1, 0), f.up);  // a Z-up body
    f.how = "assumed: the glTF convention";
  } else {
    f.assumed = false;
  }
  f.forward = glm::normalize(sum);
  f.left = glm::normalize(glm::cross(f.up, f.forward));
  return f;
}

// +1 when `a` is on the character's left of `b`, -1 on its right, 0 when the
// rest pose cannot tell (both at one place).
int sideOf(const std::vector<glm::vec3>& rest, const Facing& f, int a, int b) {
  const glm::vec3 d = rest[a] - rest[b];
  const float along = glm::dot(d, f.left);
  if (!(std::fabs(along) > 1e-4f * glm::length(d)) || glm::length(d) < 1e-6f) return 0;
  return along > 0 ? 1 : -1;
}

std::string facingText(const Facing& f) {
  return "it faces " + axisName(f.forward) + ", " + f.how + "; its left is " + axisName(f.left);
}

Chain resolve(const Tree& t, const Limb& l) {
  return {t.find(l.upper), t.find(l.lower), t.find(l.end)};
}

int firstJoint(const Chain& c) { return c.upper >= 0 ? c.upper : c.lower >= 0 ? c.lower : c.end; }

Limb named(const Tree& t, const Chain& c) { return {t.name(c.upper), t.name(c.lower), t.name(c.end)}; }

}  // namespace

std::vector<glm::vec3> restPositions(const Skeleton& s, const Tree& t) {
  std::vector<glm::mat4> model(static_cast<std::size_t>(t.count()));
  std::vector<glm::vec3> out(model.size());
  for (int i = 0; i < t.count(); ++i) {
    const glm::mat4 local = static_cast<std::size_t>(i) < s.restPose.size() ? s.restPose[i].matrix() : glm::mat4(1.0f);
    model[i] = t.parent[i] >= 0 ? model[t.parent[i]] * local : s.rootTransform * local;
    out[i] = glm::vec3(model[i][3]);
    if (!std::isfinite(out[i].x) || !std::isfinite(out[i].y) || !std::isfinite(out[i].z)) out[i] = glm::vec3(0.0f);
  }
  return out;
}

int restSide(const std::vector<glm::vec3>& rest, const BodyChain& body, const std::array<LegJoints, 2>& legs, int a,
             int b, std::string* facing) {
  const int n = static_cast<int>(rest.size());
  auto valid = [n](int j) { return j >= 0 && j < n; };
  if (!valid(a) || !valid(b)) return 0;
  std::array<Chain, 2> chains;
  std::array<int, 2> toes{-1, -1};
  for (std::size_t s = 0; s < 2; ++s) {
    const LegJoints& l = legs[s];
    if (valid(l.upper) && valid(l.lower) && valid(l.end)) chains[s] = Chain{l.upper, l.lower, l.end};
    else if (valid(l.end)) chains[s].end = l.end;
    if (valid(l.toe) && valid(l.end)) toes[s] = l.toe;
  }
  const BodyChain checked{valid(body.hips) ? body.hips : -1, valid(body.neck) ? body.neck : -1,
                          valid(body.head) ? body.head : -1};
  const Facing f = findFacing(rest, checked, chains, toes);
  if (facing) *facing = facingText(f);
  return f.assumed ? 0 : sideOf(rest, f, a, b);
}

std::string describeLimb(const Limb& l) {
  auto one = [](const char* what, const std::string& n) { return std::string(what) + " " + (n.empty() ? "none" : inQuotes(n)); };
  return one("upper", l.upper) + ", " + one("lower", l.lower) + ", " + one("end", l.end);
}

std::string sidesNote(const Tree& t, const std::vector<glm::vec3>& rest, const BodyChain& body,
                      const CharacterProfile& p) {
  const std::array<Chain, 2> legs{resolve(t, p.leftLeg), resolve(t, p.rightLeg)};
  const Facing f = findFacing(rest, body, legs, {t.find(p.leftToe), t.find(p.rightToe)});
  std::string agree, disagree, unknown;
  auto check = [&](const char* what, const Chain& l, const Chain& r) {
    const int a = firstJoint(l), b = firstJoint(r);
    if (a < 0 || b < 0) return;
    std::string& list = [&]() -> std::string& {
      switch (sideOf(rest, f, a, b)) {
        case 1: return agree;
        case -1: return disagree;
        default: return unknown;
      }
    }();
    list += (list.empty() ? "the left " : " and ") + std::string(what);
  };
  check("leg", legs[0], legs[1]);
  check("arm", resolve(t, p.leftArm), resolve(t, p.rightArm));
  if (agree.empty() && disagree.empty() && unknown.empty()) return "sides: no left and right limbs to check";
  std::string out;
  auto add = [&](const std::string& text) { out += (out.empty() ? "sides: " : "; ") + text; };
  if (!agree.empty()) add(agree + " lie on the character's left in the rest pose");
  if (!disagree.empty())
    add(disagree + " lie on the character's right in the rest pose; kept as named" +
        (f.assumed ? " (right if the character faces the other way)" : ""));
  if (!unknown.empty()) add(unknown + ": the rest pose puts left and right at one place");
  return out + " (" + facingText(f) + ")";
}

void guessLimbs(const Asset& asset, const Tree& t, const BodyChain& body, CharacterProfile& p, Notes& notes) {
  const std::vector<glm::vec3> rest = restPositions(asset.skeleton, t);

  std::array<Candidates, 2> cand;  // [0] left, [1] right
  for (int j = 0; j < t.count(); ++j) {
    const auto [side, word] = limbName(t.names[j]);
    if (side != 0 && word) cand[side > 0][index(word->role)].push_back({j, word->rank});
  }

  // The VRM humanoid map's limb, when all three joints are there and chained.
  auto humanoid = [&](const char* prefix, const char* upper, const char* lower, const char* end) {
    if (!asset.hasHumanoid) return Chain{};
    auto bone = [&](const char* part) {
      auto it = asset.humanoid.bones.find(std::string(prefix) + part);
      return it == asset.humanoid.bones.end() ? -1 : t.find(it->second);
    };
    Chain c{bone(upper), bone(lower), bone(end)};
    return c.found() == 3 && t.above(c.upper, c.lower) && t.above(c.lower, c.end) ? c : Chain{};
  };

  std::array<Chain, 2> legs, arms;
  std::array<int, 2> toes{-1, -1};
  std::array<std::string, 2> legHow, armHow, toeHow;
  const char* sidePrefix[2] = {"left", "right"};
  for (int s = 0; s < 2; ++s) {
    if ((legs[s] = humanoid(sidePrefix[s], "UpperLeg", "LowerLeg", "Foot")).found() == 3) legHow[s] = "VRM humanoid";
    else if ((legs[s] = pickChain(t, cand[s], Role::LegUpper, true)).found() >= 2) legHow[s] = "name";
    if ((arms[s] = humanoid(sidePrefix[s], "UpperArm", "LowerArm", "Hand")).found() == 3) armHow[s] = "VRM humanoid";
    else if ((arms[s] = pickChain(t, cand[s], Role::ArmUpper, false)).found() >= 2) armHow[s] = "name";
    // Toes: below the foot, the humanoid map's first, else the shallowest named one.
    const int foot = legs[s].end;
    if (foot < 0) continue;
    if (legHow[s] == "VRM humanoid") {
      auto it = asset.humanoid.bones.find(std::string(sidePrefix[s]) + "Toes");
      if (it != asset.humanoid.bones.end() && t.above(foot, t.find(it->second))) {
        toes[s] = t.find(it->second), toeHow[s] = "VRM humanoid";
        continue;
      }
    }
    for (const Candidate& c : cand[s][index(Role::Toe)])
      if (t.above(foot, c.joint) && (toes[s] < 0 || t.depth[c.joint] < t.depth[toes[s]]))
        toes[s] = c.joint, toeHow[s] = "name";
  }

  // No limb named at all (Cesium Man): a mirror pair of chains below the hips
  // (legs: thigh, shin, foot, toe) and off the spine (arms: [clavicle,] upper arm,
  // forearm, hand); which one is left, from the rest pose.
  const bool noLegs = legs[0].found() < 2 && legs[1].found() < 2;
  const bool noArms = arms[0].found() < 2 && arms[1].found() < 2;
  const int top = body.neck >= 0 ? body.neck : body.head;
  std::array<Chain, 2> shapeLegs, shapeArms;
  std::array<int, 2> shapeToes{-1, -1};
  if (noLegs && body.hips >= 0) {
    const auto [a, b] = mirrorPair(t, body.hips, top >= 0 ? t.childToward(body.hips, top) : -1);
    if (a >= 0) {
      const std::vector<int> ca = unbranchedFrom(t, a), cb = unbranchedFrom(t, b);
      if (ca.size() == cb.size() && (ca.size() == 3 || ca.size() == 4)) {
        shapeLegs = {Chain{ca[0], ca[1], ca[2]}, Chain{cb[0], cb[1], cb[2]}};
        if (ca.size() == 4) shapeToes = {ca[3], cb[3]};
      }
    }
  }
  if (noArms && body.hips >= 0 && top >= 0 && t.above(body.hips, top)) {
    for (int j = top; j >= 0 && j != body.hips && shapeArms[0].found() == 0; j = t.parent[j]) {
      // Leave out the way up to the head (Pab's arms hang from the neck, beside the head).
      const int up = j != top ? t.childToward(j, top) : (t.above(top, body.head) ? t.childToward(top, body.head) : -1);
      const auto [a, b] = mirrorPair(t, j, up);
      if (a < 0) continue;
      const std::vector<int> ca = unbranchedFrom(t, a), cb = unbranchedFrom(t, b);
      if (ca.size() != cb.size() || ca.size() < 3 || ca.size() > 4) continue;
      const std::size_t k = ca.size() - 3;  // a clavicle first when there are four
      shapeArms = {Chain{ca[k], ca[k + 1], ca[k + 2]}, Chain{cb[k], cb[k + 1], cb[k + 2]}};
    }
  }
  if (shapeLegs[0].found() || shapeArms[0].found()) {
    const Facing f = findFacing(rest, body, noLegs ? shapeLegs : legs, noLegs ? shapeToes : toes);
    auto place = [&](std::array<Chain, 2>& pair, std::array<std::string, 2>& how, const char* where,
                     std::array<int, 2>* toePair) {
      if (!pair[0].found()) return;
      const int side = sideOf(rest, f, pair[0].upper, pair[1].upper);
      if (side == 0) {
        how[0] = how[1] = std::string("none (topology: a pair of chains ") + where +
                          ", but the rest pose does not tell left from right)";
        pair = {};
        return;
      }
      if (side < 0) {
        std::swap(pair[0], pair[1]);
        if (toePair) std::swap((*toePair)[0], (*toePair)[1]);
      }
      how[0] = how[1] = std::string("topology: a mirror pair of chains ") + where + "; side from the rest pose";
    };
    place(shapeLegs, legHow, "below the hips", &shapeToes);
    place(shapeArms, armHow, "off the spine", nullptr);
    if (noLegs && shapeLegs[0].found()) {
      legs = shapeLegs;
      toes = shapeToes;
      for (int s = 0; s < 2; ++s) toeHow[s] = toes[s] >= 0 ? "topology: the foot's only child" : "";
    }
    if (noArms && shapeArms[0].found()) arms = shapeArms;
  }

  auto noteLimb = [&](const char* field, Limb& out, const Chain& c, const std::string& how) {
    out = named(t, c);
    std::string line = std::string(field) + ": ";
    if (c.found() == 0) {
      line += how.empty() ? "none" : how;
    } else {
      line += describeLimb(out) + " (" + how + ")";
      if (c.detached)
        line += "; " + inQuotes(out.end) + " is not below " + inQuotes(out.lower) +
                " (an IK target?): the end point is its rest offset from the lower joint";
    }
    notes.emplace_back(field, line);
  };
  noteLimb("leftLeg", p.leftLeg, legs[0], legHow[0]);
  noteLimb("rightLeg", p.rightLeg, legs[1], legHow[1]);
  noteLimb("leftArm", p.leftArm, arms[0], armHow[0]);
  noteLimb("rightArm", p.rightArm, arms[1], armHow[1]);
  const char* toeField[2] = {"leftToe", "rightToe"};
  std::string* toeOut[2] = {&p.leftToe, &p.rightToe};
  for (int s = 0; s < 2; ++s) {
    *toeOut[s] = t.name(toes[s]);
    notes.emplace_back(toeField[s], std::string(toeField[s]) + ": " +
                                        (toes[s] >= 0 ? inQuotes(*toeOut[s]) + " (" + toeHow[s] + ")" : "none"));
  }
  notes.emplace_back("sides", sidesNote(t, rest, body, p));
}

}  // namespace marionette::profile_detail
