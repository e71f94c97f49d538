#include "marionette/retarget/retarget_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "marionette/animation/pose.hpp"
#include "marionette/animation/sampling.hpp"

namespace marionette::retarget {
namespace {

glm::vec3 at(const std::vector<glm::mat4>& model, int j) { return glm::vec3(model[static_cast<std::size_t>(j)][3]); }

bool usable(const Skeleton& s, const JointMap& m) {
  if (!s.validate().empty()) return false;
  for (int j : m.bones)
    if (j >= static_cast<int>(s.jointCount())) return false;
  return true;
}

constexpr Bone kFeet[] = {Bone::LeftFoot, Bone::RightFoot, Bone::LeftToes, Bone::RightToes};

// Model positions of a clip sampled at `rate` (one vector of joint positions per frame).
struct Sampled {
  std::vector<std::vector<glm::mat4>> frames;
};
Sampled sample(const Skeleton& s, const Clip& clip, float rate, float duration) {
  Sampled out;
  const int n = std::max(1, static_cast<int>(std::floor(duration * rate)) + 1);
  std::vector<Transform> local(s.jointCount());
  SamplingCursor cursor;
  cursor.reset(clip);
  for (int k = 0; k < n; ++k) {
    sampleClip(clip, static_cast<float>(k) / rate, s.restPose, local, &cursor);
    std::vector<glm::mat4> model(s.jointCount());
    localToModel(s, local, model);
    out.frames.push_back(std::move(model));
  }
  return out;
}

}  // namespace

float characterHeight(const Skeleton& skeleton, const JointMap& map) {
  if (!usable(skeleton, map) || map.joint(Bone::Head) < 0) return 0.0f;
  const std::vector<glm::mat4> model = skeleton.restModelMatrices();
  float lowest = std::numeric_limits<float>::infinity();
  for (Bone b : kFeet)
    if (map.joint(b) >= 0) lowest = std::min(lowest, at(model, map.joint(b)).y);
  const float h = at(model, map.joint(Bone::Head)).y - lowest;
  return std::isfinite(h) && h > 0.0f ? h : 0.0f;
}

float restLegLength(const Skeleton& skeleton, const JointMap& map) {
  if (!usable(skeleton, map)) return 0.0f;
  const std::vector<glm::mat4> model = skeleton.restModelMatrices();
  float sum = 0.0f;
  int sides = 0;
  for (auto [u, l, f] : {std::array{Bone::LeftUpperLeg, Bone::LeftLowerLeg, Bone::LeftFoot},
                         std::array{Bone::RightUpperLeg, Bone::RightLowerLeg, Bone::RightFoot}}) {
    if (map.joint(u) < 0 || map.joint(l) < 0 || map.joint(f) < 0) continue;
    sum += glm::length(at(model, map.joint(u)) - at(model, map.joint(l))) +
           glm::length(at(model, map.joint(l)) - at(model, map.joint(f)));
    ++sides;
  }
  return sides && std::isfinite(sum) ? sum / static_cast<float>(sides) : 0.0f;
}

namespace {
// The lowest foot or toe joint of the rest pose, model +Y; +infinity without feet.
float restFeetHeight(const std::vector<glm::mat4>& rest, const JointMap& map) {
  float lowest = std::numeric_limits<float>::infinity();
  for (Bone b : kFeet)
    if (map.joint(b) >= 0) lowest = std::min(lowest, at(rest, map.joint(b)).y);
  return lowest;
}
}  // namespace

std::optional<glm::vec3> standingHipsReference(const Skeleton& skeleton, const JointMap& map, const Clip& clip,
                                               const Skeleton& target, const JointMap& targetMap) {
  const int hips = map.joint(Bone::Hips);
  if (!usable(skeleton, map) || hips < 0 || !clip.validate(skeleton.jointCount()).empty()) return std::nullopt;
  if (!usable(target, targetMap) || targetMap.joint(Bone::Hips) < 0) return std::nullopt;
  const std::vector<glm::mat4> targetRest = target.restModelMatrices();
  const float targetFeet = restFeetHeight(targetRest, targetMap);
  const float targetHipHeight = at(targetRest, targetMap.joint(Bone::Hips)).y - targetFeet;
  if (!std::isfinite(targetFeet) || !(targetHipHeight > 0.0f) || std::fabs(targetFeet) > 0.25f * targetHipHeight)
    return std::nullopt;
  const std::vector<glm::mat4> rest = skeleton.restModelMatrices();
  const float restLowest = restFeetHeight(rest, map);
  if (!std::isfinite(restLowest)) return std::nullopt;
  const Sampled s = sample(skeleton, clip, 30.0f, clip.duration);
  float ground = std::numeric_limits<float>::infinity();
  for (const auto& frame : s.frames)
    for (Bone b : kFeet)
      if (map.joint(b) >= 0) ground = std::min(ground, at(frame, map.joint(b)).y);
  if (!std::isfinite(ground)) return std::nullopt;
  glm::vec3 ref = at(rest, hips);
  ref.y += ground - restLowest;
  return ref;
}

EffectorError endEffectorError(const Skeleton& source, const JointMap& sourceMap, const Clip& sourceClip,
                               const Skeleton& target, const JointMap& targetMap, const Clip& targetClip,
                               const glm::quat& facing, float rate) {
  EffectorError e;
  const float hs = characterHeight(source, sourceMap), ht = characterHeight(target, targetMap);
  // (Without the heights, hips or valid clips nothing is measured: every effector is missing.)
  const int sh = sourceMap.joint(Bone::Hips), th = targetMap.joint(Bone::Hips);
  if (!(hs > 0.0f) || !(ht > 0.0f) || sh < 0 || th < 0 || !(rate > 0.0f) ||
      !sourceClip.validate(source.jointCount()).empty() || !targetClip.validate(target.jointCount()).empty()) {
    e.missing = {Bone::LeftHand, Bone::RightHand, Bone::LeftFoot, Bone::RightFoot, Bone::Head};
    return e;
  }
  constexpr Bone kEffectors[] = {Bone::LeftHand, Bone::RightHand, Bone::LeftFoot, Bone::RightFoot, Bone::Head};
  for (Bone eb : kEffectors) (sourceMap.joint(eb) >= 0 && targetMap.joint(eb) >= 0 ? e.effectors : e.missing).push_back(eb);
  const float duration = std::min(sourceClip.duration, targetClip.duration);
  const Sampled a = sample(source, sourceClip, rate, duration), b = sample(target, targetClip, rate, duration);
  double sum = 0.0;
  for (std::size_t f = 0; f < a.frames.size() && f < b.frames.size(); ++f)
    for (Bone eb : kEffectors) {
      const int js = sourceMap.joint(eb), jt = targetMap.joint(eb);
      if (js < 0 || jt < 0) continue;
      const glm::vec3 ps = facing * (at(a.frames[f], js) - at(a.frames[f], sh)) / hs;
      const glm::vec3 pt = (at(b.frames[f], jt) - at(b.frames[f], th)) / ht;
      const double d = glm::length(ps - pt);
      if (!std::isfinite(d)) continue;
      sum += d;
      e.max = std::max(e.max, d);
      ++e.samples;
    }
  e.mean = e.samples ? sum / e.samples : 0.0;
  return e;
}

SegmentDirectionError segmentDirectionError(const Skeleton& source, const JointMap& sourceMap, const Clip& sourceClip,
                                            const Skeleton& target, const JointMap& targetMap, const Clip& targetClip,
                                            const glm::quat& facing, float rate) {
  SegmentDirectionError out;
  if (!(rate > 0.0f) || !sourceClip.validate(source.jointCount()).empty() || !targetClip.validate(target.jointCount()).empty())
    return out;
  // Each segment's ends: a bone, or the first joint of a chain (the neck's base).
  auto end = [](const JointMap& m, Bone b, bool neckBase) {
    if (neckBase) return !m.chain(Chain::Neck).empty() ? m.chain(Chain::Neck).front() : -1;
    return m.joint(b);
  };
  struct Segment {
    Bone from, to;
    bool fromNeck, toNeck;
  };
  constexpr const char* kSegmentNames[] = {"spine", "neck", "leftUpperArm", "leftLowerArm", "rightUpperArm",
                                            "rightLowerArm", "leftUpperLeg", "leftLowerLeg", "rightUpperLeg",
                                            "rightLowerLeg"};
  constexpr Segment kSegments[] = {
      {Bone::Hips, Bone::Head, false, true},   {Bone::Head, Bone::Head, true, false},
      {Bone::LeftUpperArm, Bone::LeftLowerArm, false, false}, {Bone::LeftLowerArm, Bone::LeftHand, false, false},
      {Bone::RightUpperArm, Bone::RightLowerArm, false, false}, {Bone::RightLowerArm, Bone::RightHand, false, false},
      {Bone::LeftUpperLeg, Bone::LeftLowerLeg, false, false}, {Bone::LeftLowerLeg, Bone::LeftFoot, false, false},
      {Bone::RightUpperLeg, Bone::RightLowerLeg, false, false}, {Bone::RightLowerLeg, Bone::RightFoot, false, false},
  };
  for (std::size_t k = 0; k < std::size(kSegments); ++k) {
    const Segment& seg = kSegments[k];
    const int s0 = end(sourceMap, seg.from, seg.fromNeck), s1 = end(sourceMap, seg.to, seg.toNeck);
    const int t0 = end(targetMap, seg.from, seg.fromNeck), t1 = end(targetMap, seg.to, seg.toNeck);
    const bool both = s0 >= 0 && s1 >= 0 && t0 >= 0 && t1 >= 0 && s0 != s1 && t0 != t1;
    (both ? out.segments : out.missing).emplace_back(kSegmentNames[k]);
  }
  const float duration = std::min(sourceClip.duration, targetClip.duration);
  const Sampled a = sample(source, sourceClip, rate, duration), b = sample(target, targetClip, rate, duration);
  std::vector<double> angles;
  for (std::size_t f = 0; f < a.frames.size() && f < b.frames.size(); ++f)
    for (const Segment& seg : kSegments) {
      const int s0 = end(sourceMap, seg.from, seg.fromNeck), s1 = end(sourceMap, seg.to, seg.toNeck);
      const int t0 = end(targetMap, seg.from, seg.fromNeck), t1 = end(targetMap, seg.to, seg.toNeck);
      if (s0 < 0 || s1 < 0 || t0 < 0 || t1 < 0 || s0 == s1 || t0 == t1) continue;
      const glm::vec3 ds = facing * (at(a.frames[f], s1) - at(a.frames[f], s0));
      const glm::vec3 dt = at(b.frames[f], t1) - at(b.frames[f], t0);
      const float ls = glm::length(ds), lt = glm::length(dt);
      if (!(ls > 1e-6f) || !(lt > 1e-6f) || !std::isfinite(ls) || !std::isfinite(lt)) continue;
      const double c = std::clamp(static_cast<double>(glm::dot(ds, dt)) / (static_cast<double>(ls) * lt), -1.0, 1.0);
      angles.push_back(std::acos(c) * 180.0 / 3.14159265358979323846);
    }
  if (angles.empty()) return out;
  double sum = 0.0;
  for (double d : angles) sum += d;
  out.samples = static_cast<int>(angles.size());
  out.meanDegrees = sum / static_cast<double>(angles.size());
  std::sort(angles.begin(), angles.end());
  out.p95Degrees = angles[std::min(angles.size() - 1, static_cast<std::size_t>(0.95 * static_cast<double>(angles.size())))];
  out.maxDegrees = angles.back();
  return out;
}

SkatingComparison compareSkating(const Skeleton& source, const JointMap& sourceMap, const Clip& sourceClip,
                                 const Skeleton& target, const JointMap& targetMap, const Clip& targetClip, float rate,
                                 float contactHeight, float contactSpeed) {
  SkatingComparison out;
  const float ls = restLegLength(source, sourceMap), lt = restLegLength(target, targetMap);
  if (!(ls > 0.0f) || !(lt > 0.0f) || !(rate > 0.0f) || !sourceClip.validate(source.jointCount()).empty() ||
      !targetClip.validate(target.jointCount()).empty())
    return out;
  const float duration = std::min(sourceClip.duration, targetClip.duration);
  const Sampled a = sample(source, sourceClip, rate, duration), b = sample(target, targetClip, rate, duration);
  const std::size_t n = std::min(a.frames.size(), b.frames.size());
  if (n < 3) return out;
  auto speed = [&](const Sampled& s, int j, std::size_t f) {  // central difference, per second
    const glm::vec3 d = at(s.frames[f + 1], j) - at(s.frames[f - 1], j);
    return glm::length(glm::vec2(d.x, d.z)) * rate * 0.5f;
  };
  double sumS = 0.0, sumT = 0.0;
  int contacts = 0, total = 0;
  for (Bone foot : {Bone::LeftFoot, Bone::RightFoot}) {
    const int js = sourceMap.joint(foot), jt = targetMap.joint(foot);
    if (js < 0 || jt < 0) continue;
    ++out.feet;
    float lowest = std::numeric_limits<float>::infinity();
    for (std::size_t f = 0; f < n; ++f) lowest = std::min(lowest, at(a.frames[f], js).y);
    for (std::size_t f = 1; f + 1 < n; ++f) {
      ++total;
      const float vs = speed(a, js, f) / ls;
      if (at(a.frames[f], js).y - lowest > contactHeight * ls || !(vs <= contactSpeed)) continue;
      const float vt = speed(b, jt, f) / lt;
      if (!std::isfinite(vt)) continue;
      sumS += vs;
      sumT += vt;
      ++contacts;
    }
  }
  out.contacts = contacts;
  if (contacts == 0) return out;
  out.source = sumS / contacts;
  out.target = sumT / contacts;
  out.ratio = out.source > 0.0 ? out.target / out.source : 0.0;
  out.contactFraction = static_cast<double>(contacts) / total;
  return out;
}

}  // namespace marionette::retarget
