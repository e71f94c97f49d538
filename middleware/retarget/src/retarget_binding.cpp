// Retargeter::bind, at command time: which source joints drive which target
// joints, the rest-pose frames and rest-shape corrections, the hips translation
// and its scale, detached limb ends and the IK effectors, all worked out once so
// that the per-frame apply() (retargeter.cpp) is a few quaternion products.
// The method itself is described in retargeter.hpp.
#include "marionette/core/finite.hpp"
#include "marionette/retarget/retargeter.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "retarget_detail.hpp"

namespace marionette::retarget {
namespace {

using detail::flipOf;
using detail::flipped;
using detail::signsOf;

// Model rotations (true rotation part, mirrors tracked as sign patterns) of a pose.
struct ModelRotations {
  std::vector<glm::quat> rotation;
  std::vector<glm::vec3> flip;  // per joint, for its local rotation
};

ModelRotations modelRotations(const Skeleton& s, const glm::quat& rootQ, const glm::vec3& rootSigns) {
  const std::size_t n = s.jointCount();
  ModelRotations m;
  m.rotation.resize(n);
  m.flip.resize(n);
  std::vector<glm::vec3> signs(n);
  for (std::size_t i = 0; i < n; ++i) {
    const int p = s.parents[i];
    const glm::vec3 ps = p < 0 ? rootSigns : signs[static_cast<std::size_t>(p)];
    const glm::quat pq = p < 0 ? rootQ : m.rotation[static_cast<std::size_t>(p)];
    m.flip[i] = flipOf(ps);
    m.rotation[i] = safeNormalize(pq * flipped(safeNormalize(s.restPose[i].rotation), m.flip[i]));
    signs[i] = ps * signsOf(s.restPose[i].scale);
  }
  return m;
}

float distance(const std::vector<glm::mat4>& model, int a, int b) {
  if (a < 0 || b < 0) return 0.0f;
  const float d = glm::length(glm::vec3(model[static_cast<std::size_t>(a)][3]) - glm::vec3(model[static_cast<std::size_t>(b)][3]));
  return std::isfinite(d) ? d : 0.0f;
}

glm::vec3 positionOf(const std::vector<glm::mat4>& model, int j) { return glm::vec3(model[static_cast<std::size_t>(j)][3]); }

// Middle of each chain bone as a fraction of the chain's rest length. A chain
// joint's bone runs to the next chain joint; the last one to `end` (or, without
// it, as long as the previous bone). Zero total length: evenly spaced.
std::vector<float> boneMiddles(const std::vector<int>& chain, int end, const std::vector<glm::mat4>& model) {
  const std::size_t n = chain.size();
  std::vector<float> len(n, 0.0f);
  for (std::size_t k = 0; k + 1 < n; ++k) len[k] = distance(model, chain[k], chain[k + 1]);
  if (n > 0) len[n - 1] = end >= 0 ? distance(model, chain[n - 1], end) : (n > 1 ? len[n - 2] : 0.0f);
  float total = 0.0f;
  for (float l : len) total += l;
  std::vector<float> mid(n);
  if (!(total > 1e-6f)) {
    for (std::size_t k = 0; k < n; ++k) mid[k] = (static_cast<float>(k) + 0.5f) / static_cast<float>(n);
    return mid;
  }
  float cum = 0.0f;
  for (std::size_t k = 0; k < n; ++k) {
    mid[k] = (cum + 0.5f * len[k]) / total;
    cum += len[k];
  }
  return mid;
}

float legLength(const JointMap& m, const std::vector<glm::mat4>& model) {
  float sum = 0.0f;
  int sides = 0;
  for (auto [u, l, f] : {std::array{Bone::LeftUpperLeg, Bone::LeftLowerLeg, Bone::LeftFoot},
                         std::array{Bone::RightUpperLeg, Bone::RightLowerLeg, Bone::RightFoot}}) {
    if (m.joint(u) < 0 || m.joint(l) < 0 || m.joint(f) < 0) continue;
    sum += distance(model, m.joint(u), m.joint(l)) + distance(model, m.joint(l), m.joint(f));
    ++sides;
  }
  return sides ? sum / static_cast<float>(sides) : 0.0f;
}

// Hip height at rest: the hip joints (where the legs attach, the upper-leg
// joints) above the lowest foot or toe joint, model +Y up; the hips joint when
// there are no upper legs. The legs' own height, not the pelvis joint's: a
// pelvis joint placed high above the thighs (Godette) would make the hips sink
// and rise more than the legs can follow.
float hipHeight(const JointMap& m, const std::vector<glm::mat4>& model) {
  float top = 0.0f;
  int n = 0;
  for (Bone b : {Bone::LeftUpperLeg, Bone::RightUpperLeg})
    if (m.joint(b) >= 0) top += positionOf(model, m.joint(b)).y, ++n;
  if (n == 0 && m.joint(Bone::Hips) < 0) return 0.0f;
  top = n ? top / static_cast<float>(n) : positionOf(model, m.joint(Bone::Hips)).y;
  float lowest = top;
  bool any = false;
  for (Bone b : {Bone::LeftFoot, Bone::RightFoot, Bone::LeftToes, Bone::RightToes}) {
    if (m.joint(b) < 0) continue;
    lowest = std::min(lowest, positionOf(model, m.joint(b)).y);
    any = true;
  }
  const float h = top - lowest;
  return any && std::isfinite(h) ? h : 0.0f;
}

// Horizontal (XZ) left-right axis of the rest pose: from the right upper leg to
// the left one (else the arms, shoulders). Zero when none is usable.
glm::vec2 lateralAxis(const JointMap& m, const std::vector<glm::mat4>& model) {
  for (auto [l, r] : {std::pair{Bone::LeftUpperLeg, Bone::RightUpperLeg}, std::pair{Bone::LeftUpperArm, Bone::RightUpperArm},
                      std::pair{Bone::LeftShoulder, Bone::RightShoulder}}) {
    if (m.joint(l) < 0 || m.joint(r) < 0) continue;
    const glm::vec3 d = positionOf(model, m.joint(l)) - positionOf(model, m.joint(r));
    const glm::vec2 h(d.x, d.z);
    const float len = glm::length(h);
    if (len > 1e-6f && std::isfinite(len)) return h / len;
  }
  return glm::vec2(0.0f);
}

// The mapped child that gives a canonical bone its direction (-1: none).
int boneChild(const JointMap& m, Bone b) {
  switch (b) {
    case Bone::LeftShoulder: return m.joint(Bone::LeftUpperArm);
    case Bone::RightShoulder: return m.joint(Bone::RightUpperArm);
    case Bone::LeftUpperArm: return m.joint(Bone::LeftLowerArm);
    case Bone::RightUpperArm: return m.joint(Bone::RightLowerArm);
    case Bone::LeftLowerArm: return m.joint(Bone::LeftHand);
    case Bone::RightLowerArm: return m.joint(Bone::RightHand);
    case Bone::LeftHand: return !m.chain(Chain::LeftMiddle).empty() ? m.chain(Chain::LeftMiddle).front() : -1;
    case Bone::RightHand: return !m.chain(Chain::RightMiddle).empty() ? m.chain(Chain::RightMiddle).front() : -1;
    case Bone::LeftUpperLeg: return m.joint(Bone::LeftLowerLeg);
    case Bone::RightUpperLeg: return m.joint(Bone::RightLowerLeg);
    case Bone::LeftLowerLeg: return m.joint(Bone::LeftFoot);
    case Bone::RightLowerLeg: return m.joint(Bone::RightFoot);
    case Bone::LeftFoot: return m.joint(Bone::LeftToes);
    case Bone::RightFoot: return m.joint(Bone::RightToes);
    default: return -1;
  }
}

// Unit direction from a to b, or zero when shorter than `eps` (zero-length bones).
glm::vec3 direction(const glm::vec3& a, const glm::vec3& b, float eps) {
  const glm::vec3 d = b - a;
  const float len = glm::length(d);
  return len > eps && std::isfinite(len) ? d / len : glm::vec3(0.0f);
}

// The minimal rotation taking unit `from` onto unit `to`; identity when either is
// zero. Antiparallel: a half turn about an axis perpendicular to `from`.
glm::quat minimalArc(const glm::vec3& from, const glm::vec3& to) {
  if (glm::dot(from, from) < 0.5f || glm::dot(to, to) < 0.5f) return glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
  const float c = glm::dot(from, to);
  if (c < -0.999999f) {
    glm::vec3 axis = glm::cross(glm::vec3(1.0f, 0.0f, 0.0f), from);
    if (glm::dot(axis, axis) < 1e-6f) axis = glm::cross(glm::vec3(0.0f, 1.0f, 0.0f), from);
    return glm::angleAxis(3.14159265f, glm::normalize(axis));
  }
  const glm::vec3 axis = glm::cross(from, to);
  return safeNormalize(glm::quat(1.0f + c, axis.x, axis.y, axis.z));
}

// A chain as a polyline of rest positions (its joints, then `end` when there is
// one) and the point at fraction f of its length.
struct Polyline {
  std::vector<glm::vec3> points;
  std::vector<float> at;  // cumulative length fraction of each point
  [[nodiscard]] glm::vec3 point(float f) const {
    if (points.empty()) return glm::vec3(0.0f);
    for (std::size_t k = 0; k + 1 < points.size(); ++k)
      if (f <= at[k + 1]) {
        const float span = at[k + 1] - at[k];
        return glm::mix(points[k], points[k + 1], span > 0.0f ? (f - at[k]) / span : 0.0f);
      }
    return points.back();
  }
};
Polyline chainPolyline(const std::vector<int>& chain, int end, const std::vector<glm::mat4>& model) {
  Polyline p;
  for (int j : chain) p.points.push_back(glm::vec3(model[static_cast<std::size_t>(j)][3]));
  if (end >= 0) p.points.push_back(glm::vec3(model[static_cast<std::size_t>(end)][3]));
  p.at.assign(p.points.size(), 0.0f);
  float total = 0.0f;
  for (std::size_t k = 1; k < p.points.size(); ++k) {
    const float d = glm::length(p.points[k] - p.points[k - 1]);
    total += std::isfinite(d) ? d : 0.0f;
    p.at[k] = total;
  }
  for (float& a : p.at) a = total > 1e-6f ? a / total : 0.0f;
  return p;
}

bool mapInRange(const JointMap& m, std::size_t n) {
  for (int j : m.bones)
    if (j >= static_cast<int>(n)) return false;
  for (const auto& c : m.chains)
    for (int j : c)
      if (j < 0 || j >= static_cast<int>(n)) return false;
  return true;
}

std::string jointLabel(const Skeleton& s, int j) {
  return "'" + (static_cast<std::size_t>(j) < s.names.size() && !s.names[static_cast<std::size_t>(j)].empty()
                    ? s.names[static_cast<std::size_t>(j)]
                    : "#" + std::to_string(j)) +
         "'";
}

// Source joints that are neither a bone nor in a chain of its map, as a
// comma-separated list of labels (empty when there are none).
std::string jointsOutsideMap(const Skeleton& source, const JointMap& sourceMap) {
  const std::size_t ns = source.jointCount();
  std::vector<std::uint8_t> inSource(ns, 0);
  for (int j : sourceMap.bones)
    if (j >= 0) inSource[static_cast<std::size_t>(j)] = 1;
  for (const auto& c : sourceMap.chains)
    for (int j : c) inSource[static_cast<std::size_t>(j)] = 1;
  std::string list;
  int count = 0;
  for (std::size_t i = 0; i < ns; ++i)
    if (!inSource[i]) {
      list += (count++ ? ", " : "") + jointLabel(source, static_cast<int>(i));
    }
  return list;
}

}  // namespace

// Both skeletons at rest: true model rotations (with the flips their local
// rotations need) and model matrices. Directions shorter than a millionth of a
// skeleton's extent are zero-length bones: no rest-shape alignment for them.
struct Retargeter::RestFrames {
  ModelRotations source, target;
  std::vector<glm::mat4> sourceModel, targetModel;
  float sourceEps = 0.0f, targetEps = 0.0f;
};

// Rest shapes: C per target joint, the rotation that turns its rest bone
// direction onto the source's (turned by A). Gathered while the joints are
// paired, applied once all are (applyRestShapes).
struct Retargeter::RestShapes {
  std::vector<glm::quat> rest;
  std::vector<std::uint8_t> hasRest;
  void align(int t, const glm::vec3& targetDir, const glm::vec3& sourceDir, const glm::quat& facing) {
    if (glm::dot(targetDir, targetDir) < 0.5f || glm::dot(sourceDir, sourceDir) < 0.5f) return;
    rest[static_cast<std::size_t>(t)] = minimalArc(targetDir, facing * sourceDir);
    hasRest[static_cast<std::size_t>(t)] = 1;
  }
};

Retargeter Retargeter::bind(const Skeleton& source, const JointMap& sourceMap, const Skeleton& target,
                            const JointMap& targetMap, const RetargetOptions& options) {
  Retargeter r;
  const std::size_t nt = target.jointCount();
  // The fallback binding writes the target's rest pose.
  r.target_.resize(nt);
  for (std::size_t j = 0; j < nt && j < target.restPose.size(); ++j) {
    r.target_[j].parent = target.parents[j];
    r.target_[j].rest = target.restPose[j];
  }
  if (!checkBindInputs(r, source, sourceMap, target, targetMap)) return r;

  const RestFrames frames = bindRestFrames(r, source, target);
  if (options.alignFacing) bindFacing(r, sourceMap, targetMap, frames);
  bindJointRests(r, source, frames);

  // A bone without a direction on both sides (no mapped child: RobotExpressive's
  // forearm has no hand joint; finger tips; zero-length bones) turns with its
  // nearest driven ancestor's C, so a T-pose arm brought down to an arms-down
  // source keeps its straight elbow and the hand follows the forearm.
  RestShapes shapes{std::vector<glm::quat>(nt, glm::quat(1.0f, 0.0f, 0.0f, 0.0f)), std::vector<std::uint8_t>(nt, 0)};
  pairBones(r, source, sourceMap, target, targetMap, frames, shapes);
  pairChains(r, source, sourceMap, target, targetMap, frames, shapes);
  applyRestShapes(r, frames, shapes);

  // Joints outside the maps, named so a user can see what is lost.
  if (std::string list = jointsOutsideMap(source, sourceMap); !list.empty())
    r.notes_.push_back("source joints outside the joint map (their motion is not transferred): " + list);

  bindHips(r, source, sourceMap, target, targetMap, frames, options);
  r.targetSkeleton_ = target;
  bindDetachedEnds(r, target, targetMap, frames);
  r.bindIk(source, sourceMap, target, targetMap, frames.sourceModel, options.ik);
  foldPerFrameShortcuts(r);

  r.valid_ = true;
  return r;
}

// Bad data gives the fallback binding, with a note saying why.
bool Retargeter::checkBindInputs(Retargeter& r, const Skeleton& source, const JointMap& sourceMap,
                                 const Skeleton& target, const JointMap& targetMap) {
  if (std::string e = source.validate(); !e.empty()) {
    r.notes_.push_back("source skeleton invalid: " + e + "; the target keeps its rest pose");
    return false;
  }
  if (std::string e = target.validate(); !e.empty()) {
    r.notes_.push_back("target skeleton invalid: " + e + "; the target keeps its rest pose");
    r.target_.clear();
    return false;
  }
  if (!mapInRange(sourceMap, source.jointCount()) || !mapInRange(targetMap, target.jointCount())) {
    r.notes_.push_back("a joint map names joints outside its skeleton; the target keeps its rest pose");
    return false;
  }
  return true;
}

// The skeletons' root spaces (kept for apply) and their rest poses in model space.
Retargeter::RestFrames Retargeter::bindRestFrames(Retargeter& r, const Skeleton& source, const Skeleton& target) {
  const Transform srcRoot = decompose(source.rootTransform), tgtRoot = decompose(target.rootTransform);
  r.sourceRoot_ = srcRoot.rotation;
  r.targetRoot_ = tgtRoot.rotation;
  r.sourceRootFlip_ = flipOf(signsOf(srcRoot.scale));
  r.targetRootFlip_ = flipOf(signsOf(tgtRoot.scale));
  r.sourceRootTransform_ = source.rootTransform;
  RestFrames frames{modelRotations(source, r.sourceRoot_, signsOf(srcRoot.scale)),
                    modelRotations(target, r.targetRoot_, signsOf(tgtRoot.scale)), source.restModelMatrices(),
                    target.restModelMatrices()};
  auto extent = [](const std::vector<glm::mat4>& model) {
    float e = 0.0f;
    for (const glm::mat4& m : model) e = std::max(e, glm::length(glm::vec3(m[3]) - glm::vec3(model.front()[3])));
    return std::isfinite(e) ? e : 0.0f;
  };
  frames.sourceEps = 1e-6f * extent(frames.sourceModel);
  frames.targetEps = 1e-6f * extent(frames.targetModel);
  return frames;
}

// Facing: the yaw taking the source's rest left-right axis onto the target's.
void Retargeter::bindFacing(Retargeter& r, const JointMap& sourceMap, const JointMap& targetMap,
                            const RestFrames& frames) {
  const glm::vec2 a = lateralAxis(sourceMap, frames.sourceModel), b = lateralAxis(targetMap, frames.targetModel);
  if (glm::length(a) > 0.5f && glm::length(b) > 0.5f) {
    // Rotation about +Y by angle t maps (x, z) to (x cos t + z sin t, -x sin t + z cos t).
    const float angle = std::atan2(a.y * b.x - a.x * b.y, a.x * b.x + a.y * b.y);
    r.align_ = glm::angleAxis(angle, glm::vec3(0.0f, 1.0f, 0.0f));
    if (std::fabs(angle) > 1e-3f)
      r.notes_.push_back("facing: the target's rest faces " + std::to_string(angle * 57.29578f) +
                         " degrees about +Y from the source's; the motion is turned by that");
  } else {
    r.notes_.push_back("facing: no left-right axis (upper legs, arms) on both sides; rests taken to face alike");
  }
}

// Per joint: parents, mirror flips, the source's inverse rest rotation (with A
// folded in) and the target's rest model rotation.
void Retargeter::bindJointRests(Retargeter& r, const Skeleton& source, const RestFrames& frames) {
  const std::size_t ns = source.jointCount(), nt = r.target_.size();
  const glm::quat alignInv = glm::conjugate(r.align_);
  r.sourceParents_ = source.parents;
  r.source_.resize(ns);
  r.sourceRest_ = source.restPose;
  for (std::size_t i = 0; i < ns; ++i) {
    r.source_[i].parent = source.parents[i];
    r.source_[i].flip = frames.source.flip[i];
    r.source_[i].pre = glm::conjugate(frames.source.rotation[i]) * alignInv;
  }
  for (std::size_t j = 0; j < nt; ++j) {
    r.target_[j].flip = frames.target.flip[j];
    r.target_[j].restModel = frames.target.rotation[j];
  }
}

// Target joint t follows source joint a, or the slerp from a to b by w (w > 0).
void Retargeter::driveJoint(Retargeter& r, int t, int a, int b, float w) {
  TargetJoint& tj = r.target_[static_cast<std::size_t>(t)];
  tj.srcA = a;
  tj.srcB = w > 0.0f ? b : -1;
  tj.weight = w > 0.0f ? w : 0.0f;
  r.source_[static_cast<std::size_t>(a)].used = true;
  if (tj.srcB >= 0) r.source_[static_cast<std::size_t>(b)].used = true;
}

// Single bones: joint to joint, aligned along the bone to its mapped child.
void Retargeter::pairBones(Retargeter& r, const Skeleton& source, const JointMap& sourceMap, const Skeleton& target,
                           const JointMap& targetMap, const RestFrames& frames, RestShapes& shapes) {
  const std::vector<glm::mat4>& srcModel = frames.sourceModel;
  const std::vector<glm::mat4>& tgtModel = frames.targetModel;
  for (int b = 0; b < kBoneCount; ++b) {
    const Bone bone = static_cast<Bone>(b);
    const int s = sourceMap.joint(bone), t = targetMap.joint(bone);
    if (s >= 0 && t >= 0) {
      driveJoint(r, t, s, -1, 0.0f);
      const int sc = boneChild(sourceMap, bone), tc = boneChild(targetMap, bone);
      if (sc >= 0 && tc >= 0)
        shapes.align(t, direction(positionOf(tgtModel, t), positionOf(tgtModel, tc), frames.targetEps),
                     direction(positionOf(srcModel, s), positionOf(srcModel, sc), frames.sourceEps), r.align_);
    } else if (s >= 0) {
      r.notes_.push_back("unmapped in target: " + std::string(boneName(bone)) + " (source joint " +
                         jointLabel(source, s) + " has no counterpart)");
    } else if (t >= 0) {
      r.notes_.push_back("unmapped in source: " + std::string(boneName(bone)) + " (target joint " +
                         jointLabel(target, t) + " keeps its rest rotation)");
    }
  }
}

// Chains: by bone middles along the rest length.
void Retargeter::pairChains(Retargeter& r, const Skeleton& source, const JointMap& sourceMap, const Skeleton& target,
                            const JointMap& targetMap, const RestFrames& frames, RestShapes& shapes) {
  auto chainEnd = [](const JointMap& m, Chain c) {
    if (c == Chain::Spine) return !m.chain(Chain::Neck).empty() ? m.chain(Chain::Neck).front() : m.joint(Bone::Head);
    if (c == Chain::Neck) return m.joint(Bone::Head);
    return -1;
  };
  for (int c = 0; c < kChainCount; ++c) {
    const Chain chain = static_cast<Chain>(c);
    const std::vector<int>& sc = sourceMap.chain(chain);
    const std::vector<int>& tc = targetMap.chain(chain);
    if (sc.empty() || tc.empty()) {
      if (!sc.empty())
        r.notes_.push_back("unmapped in target: chain " + std::string(chainName(chain)) + " (" +
                           std::to_string(sc.size()) + " source joints from " + jointLabel(source, sc.front()) + ")");
      else if (!tc.empty())
        r.notes_.push_back("unmapped in source: chain " + std::string(chainName(chain)) + " (" +
                           std::to_string(tc.size()) + " target joints from " + jointLabel(target, tc.front()) +
                           " keep their rest rotations)");
      continue;
    }
    const std::vector<float> sm = boneMiddles(sc, chainEnd(sourceMap, chain), frames.sourceModel);
    const std::vector<float> tm = boneMiddles(tc, chainEnd(targetMap, chain), frames.targetModel);
    if (sc.size() != tc.size())
      r.notes_.push_back("chain " + std::string(chainName(chain)) + ": " + std::to_string(sc.size()) +
                         " source joints onto " + std::to_string(tc.size()) +
                         " target joints, interpolated along the rest length");
    const Polyline sp = chainPolyline(sc, chainEnd(sourceMap, chain), frames.sourceModel);
    const Polyline tp = chainPolyline(tc, chainEnd(targetMap, chain), frames.targetModel);
    for (std::size_t k = 0; k < tc.size(); ++k) {
      if (k + 1 < tp.points.size())
        shapes.align(tc[k], direction(tp.points[k], tp.points[k + 1], frames.targetEps),
                     direction(sp.point(tp.at[k]), sp.point(tp.at[k + 1]), frames.sourceEps), r.align_);
      const float f = tm[k];
      if (f <= sm.front()) {
        driveJoint(r, tc[k], sc.front(), -1, 0.0f);
      } else if (f >= sm.back()) {
        driveJoint(r, tc[k], sc.back(), -1, 0.0f);
      } else {
        std::size_t i = 0;
        while (i + 2 < sm.size() && f >= sm[i + 1]) ++i;
        const float span = sm[i + 1] - sm[i];
        const float w = span > 0.0f ? (f - sm[i]) / span : 0.0f;
        driveJoint(r, tc[k], sc[i], sc[i + 1], std::clamp(w, 0.0f, 1.0f));
      }
    }
  }
}

// Driven target joints take C * QtRest; a joint without its own C inherits its
// nearest ancestor's.
void Retargeter::applyRestShapes(Retargeter& r, const RestFrames& frames, RestShapes& shapes) {
  std::vector<glm::quat>& rest = shapes.rest;
  std::vector<std::uint8_t>& hasRest = shapes.hasRest;
  int aligned = 0;
  for (std::size_t j = 0; j < r.target_.size(); ++j) {
    TargetJoint& tj = r.target_[j];
    if (!hasRest[j])  // parents come first: an ancestor's C is final here
      for (int a = tj.parent; a >= 0; a = r.target_[static_cast<std::size_t>(a)].parent)
        if (hasRest[static_cast<std::size_t>(a)]) {
          rest[j] = rest[static_cast<std::size_t>(a)];
          hasRest[j] = 1;
          break;
        }
    if (tj.srcA < 0) continue;
    tj.restModel = safeNormalize(rest[j] * frames.target.rotation[j]);
    if (std::fabs(rest[j].w) < 0.99999f) ++aligned;
  }
  if (aligned > 0)
    r.notes_.push_back("rest shapes differ: " + std::to_string(aligned) +
                       " target bones turned to the source's rest directions (T-pose / A-pose, bone axes)");
}

// Hips translation: the source's reference, the target's rest hips and parent
// space, and the scale factors of the displacement.
void Retargeter::bindHips(Retargeter& r, const Skeleton& source, const JointMap& sourceMap, const Skeleton& target,
                          const JointMap& targetMap, const RestFrames& frames, const RetargetOptions& options) {
  const std::vector<glm::mat4>& srcModel = frames.sourceModel;
  const std::vector<glm::mat4>& tgtModel = frames.targetModel;
  r.sourceHips_ = sourceMap.joint(Bone::Hips);
  r.targetHips_ = targetMap.joint(Bone::Hips);
  r.translateHips_ = options.translateHips && r.sourceHips_ >= 0 && r.targetHips_ >= 0;
  if (options.translateHips && !r.translateHips_)
    r.notes_.push_back("hips unmapped on a side: the target's hips stay at their rest translation");
  if (!r.translateHips_) return;
  for (int j = r.sourceHips_; j >= 0; j = source.parents[static_cast<std::size_t>(j)]) r.hipsPath_.push_back(j);
  std::reverse(r.hipsPath_.begin(), r.hipsPath_.end());
  r.sourceHipsRef_ = options.sourceHipsReference && isFinite(*options.sourceHipsReference)
                         ? *options.sourceHipsReference
                         : positionOf(srcModel, r.sourceHips_);
  r.targetHipsRest_ = positionOf(tgtModel, r.targetHips_);
  const int p = target.parents[static_cast<std::size_t>(r.targetHips_)];
  const glm::mat4 parentModel = p < 0 ? target.rootTransform : tgtModel[static_cast<std::size_t>(p)];
  const float det = glm::determinant(glm::mat3(parentModel));
  if (std::fabs(det) > 1e-12f && std::isfinite(det)) {
    r.targetHipsParentInverse_ = glm::inverse(parentModel);
  } else {
    r.translateHips_ = false;
    r.notes_.push_back("the target hips' parent space is degenerate (zero scale): hips stay at rest");
  }
  const float sl = legLength(sourceMap, srcModel), tl = legLength(targetMap, tgtModel);
  const float sh = hipHeight(sourceMap, srcModel), th = hipHeight(targetMap, tgtModel);
  r.hScale_ = sl > 1e-6f && tl > 1e-6f ? tl / sl : 1.0f;
  r.vScale_ = sh > 1e-6f && th > 1e-6f ? th / sh : r.hScale_;
  if (!(sl > 1e-6f && tl > 1e-6f)) r.notes_.push_back("no leg length on a side: horizontal hips scale 1");
  if (!(sh > 1e-6f && th > 1e-6f)) r.notes_.push_back("no hip height on a side: vertical hips scale = horizontal");
  if (options.horizontalScale && std::isfinite(*options.horizontalScale)) r.hScale_ = *options.horizontalScale;
  if (options.verticalScale && std::isfinite(*options.verticalScale)) r.vScale_ = *options.verticalScale;
  r.notes_.push_back("hips displacement scaled " + std::to_string(r.hScale_) + " horizontally, " +
                     std::to_string(r.vScale_) + " vertically");
}

// Driven target feet and hands that do not hang from their lower limb.
void Retargeter::bindDetachedEnds(Retargeter& r, const Skeleton& target, const JointMap& targetMap,
                                  const RestFrames& frames) {
  const std::vector<glm::mat4>& tgtModel = frames.targetModel;
  for (auto [lower, end] : {std::pair{Bone::LeftLowerLeg, Bone::LeftFoot}, std::pair{Bone::RightLowerLeg, Bone::RightFoot},
                            std::pair{Bone::LeftLowerArm, Bone::LeftHand}, std::pair{Bone::RightLowerArm, Bone::RightHand}}) {
    const int l = targetMap.joint(lower), e = targetMap.joint(end);
    if (l < 0 || e < 0 || r.target_[static_cast<std::size_t>(e)].srcA < 0) continue;
    bool below = false;
    for (int j = target.parents[static_cast<std::size_t>(e)]; j >= 0 && !below; j = target.parents[static_cast<std::size_t>(j)])
      below = j == l;
    if (below) continue;
    const glm::mat4& lm = tgtModel[static_cast<std::size_t>(l)];
    if (!(std::fabs(glm::determinant(glm::mat3(lm))) > 1e-30f)) continue;
    r.detached_.push_back({e, l, glm::vec3(glm::inverse(lm) * tgtModel[static_cast<std::size_t>(e)][3])});
    r.notes_.push_back("target joint " + jointLabel(target, e) + " (" + std::string(boneName(end)) +
                       ") does not hang from " + jointLabel(target, l) + ": placed at its end every frame");
  }
}

// Per-frame shortcuts: constant products folded, and only the model rotations
// that are read get computed.
void Retargeter::foldPerFrameShortcuts(Retargeter& r) {
  const std::size_t ns = r.source_.size(), nt = r.target_.size();
  r.alignIdentity_ = std::fabs(r.align_.w) >= 1.0f - 1e-7f;
  for (std::size_t i = ns; i-- > 0;) {
    SourceJoint& sj = r.source_[i];
    sj.needed = sj.needed || sj.used;
    if (sj.needed && sj.parent >= 0) r.source_[static_cast<std::size_t>(sj.parent)].needed = true;
  }
  for (std::size_t j = 0; j < nt; ++j) {
    TargetJoint& tj = r.target_[j];
    tj.restFlipped = flipped(tj.rest.rotation, tj.flip);
    if (tj.srcA >= 0 && tj.srcB < 0) tj.direct = safeNormalize(r.source_[static_cast<std::size_t>(tj.srcA)].pre * tj.restModel);
    tj.needsModel = r.anyIk_;
  }
  for (std::size_t j = nt; j-- > 0;) {
    const TargetJoint& tj = r.target_[j];
    if ((tj.srcA >= 0 || tj.needsModel) && tj.parent >= 0) r.target_[static_cast<std::size_t>(tj.parent)].needsModel = true;
  }
}

void Retargeter::bindIk(const Skeleton& source, const JointMap& sourceMap, const Skeleton& target,
                        const JointMap& targetMap, const std::vector<glm::mat4>& sourceRestModel, const RetargetIk& ik) {
  ik_ = ik;
  if (!ik.feet && !ik.hands) return;
  struct Limb {
    Bone upper, lower, end;
    const char* name;
  };
  static constexpr std::array<Limb, 4> kLimbs{{{Bone::LeftUpperLeg, Bone::LeftLowerLeg, Bone::LeftFoot, "left leg"},
                                               {Bone::RightUpperLeg, Bone::RightLowerLeg, Bone::RightFoot, "right leg"},
                                               {Bone::LeftUpperArm, Bone::LeftLowerArm, Bone::LeftHand, "left arm"},
                                               {Bone::RightUpperArm, Bone::RightLowerArm, Bone::RightHand, "right arm"}}};
  for (std::size_t k = 0; k < kLimbs.size(); ++k) {
    const bool foot = k < 2;
    if (foot ? !ik.feet : !ik.hands) continue;
    const Limb& l = kLimbs[k];
    const RigJoints::LimbJoints joints{targetMap.joint(l.upper), targetMap.joint(l.lower), targetMap.joint(l.end)};
    const int sourceEnd = sourceMap.joint(l.end);
    if (joints.upper < 0 || joints.lower < 0 || joints.end < 0 || sourceEnd < 0) {
      notes_.push_back(std::string("ik: the ") + l.name + " is not mapped on both sides: no IK on it");
      continue;
    }
    const LimbIk limb = makeLimbIk(target, joints);
    if (limb.upper < 0) {
      notes_.push_back(std::string("ik: the target's ") + l.name +
                       " is unusable for IK (zero-length bone, or joints not chained): no IK on it");
      continue;
    }
    effectors_[k] = IkEffector{limb, sourceEnd, foot};
    anyIk_ = true;
  }
  if (!anyIk_) return;
  sourceSkeleton_ = source;
  sourceLegLength_ = legLength(sourceMap, sourceRestModel);
  if (!(sourceLegLength_ > 0.0f)) {
    // No legs: contact thresholds from the skeleton's size instead.
    float e = 0.0f;
    for (const glm::mat4& m : sourceRestModel)
      e = std::max(e, glm::length(glm::vec3(m[3]) - glm::vec3(sourceRestModel.front()[3])));
    sourceLegLength_ = std::isfinite(e) && e > 0.0f ? 0.5f * e : 1.0f;
    notes_.push_back("ik: the source has no leg length; contact thresholds use half its size");
  }
  // The ground under the source's feet: their rest height, moved with the hips
  // reference (BVH rests keep the hips at the origin while the motion stands).
  const float lift = sourceHips_ >= 0 ? sourceHipsRef_.y - positionOf(sourceRestModel, sourceHips_).y : 0.0f;
  for (std::size_t k = 0; k < 2; ++k)
    if (effectors_[k].sourceEnd >= 0)
      sourceFootRestY_[k] = positionOf(sourceRestModel, effectors_[k].sourceEnd).y + lift;
}

}  // namespace marionette::retarget
