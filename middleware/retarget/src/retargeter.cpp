// Retargeter per frame: apply() from the binding worked out by bind()
// (retarget_binding.cpp), and the offline retargetClip() built on it.
#include "marionette/retarget/retargeter.hpp"

#include <algorithm>
#include <cmath>

#include "marionette/core/finite.hpp"
#include "marionette/animation/pose.hpp"
#include "marionette/core/easing.hpp"
#include "marionette/animation/sampling.hpp"
#include "retarget_detail.hpp"

namespace marionette::retarget {

using detail::flipped;

RetargetScratch Retargeter::makeScratch() const {
  RetargetScratch s;
  s.source.resize(source_.size());
  s.target.resize(target_.size());
  if (anyIk_) {
    s.sourceModel.resize(source_.size());
    s.targetModel.resize(target_.size());
  }
  return s;
}

std::vector<int> Retargeter::drivenJoints() const {
  std::vector<int> out;
  for (std::size_t j = 0; j < target_.size(); ++j)
    if (target_[j].srcA >= 0) out.push_back(static_cast<int>(j));
  return out;
}

void Retargeter::apply(std::span<const Transform> sourceLocal, std::span<Transform> targetLocal,
                       RetargetScratch& scratch, float dt) const noexcept {
  applyImpl(sourceLocal, targetLocal, scratch, dt);
}

void Retargeter::applyImpl(std::span<const Transform> sourceLocal, std::span<Transform> targetLocal,
                           RetargetScratch& scratch, float dt) const noexcept {
  const std::size_t ns = source_.size(), nt = target_.size();
  const bool usable = valid_ && sourceLocal.size() >= ns && targetLocal.size() >= nt &&
                      scratch.source.size() >= ns && scratch.target.size() >= nt &&
                      (!anyIk_ || (scratch.sourceModel.size() >= ns && scratch.targetModel.size() >= nt));
  if (!usable) {
    for (std::size_t j = 0; j < nt && j < targetLocal.size(); ++j) targetLocal[j] = target_[j].rest;
    return;
  }
  glm::quat* qs = scratch.source.data();
  glm::quat* qt = scratch.target.data();
  for (std::size_t i = 0; i < ns; ++i) {
    const SourceJoint& sj = source_[i];
    if (!sj.needed) continue;
    const glm::quat& parent = sj.parent < 0 ? sourceRoot_ : qs[sj.parent];
    qs[i] = parent * flipped(safeNormalize(sourceLocal[i].rotation), sj.flip);
  }
  // D' = A * Qs * inverse(QsRest) * inverse(A) for source joint i.
  auto delta = [&](int i) noexcept { return align_ * qs[i] * source_[static_cast<std::size_t>(i)].pre; };
  for (std::size_t j = 0; j < nt; ++j) {
    const TargetJoint& tj = target_[j];
    Transform& out = targetLocal[j];
    if (tj.srcA < 0) {
      out = tj.rest;
      if (tj.needsModel) qt[j] = (tj.parent < 0 ? targetRoot_ : qt[tj.parent]) * tj.restFlipped;
      continue;
    }
    const glm::quat& parent = tj.parent < 0 ? targetRoot_ : qt[tj.parent];
    out.translation = tj.rest.translation;
    out.scale = tj.rest.scale;
    if (tj.srcB < 0) {
      qt[j] = (alignIdentity_ ? qs[tj.srcA] : align_ * qs[tj.srcA]) * tj.direct;
    } else {
      qt[j] = slerpShortest(delta(tj.srcA), delta(tj.srcB), tj.weight) * tj.restModel;
    }
    out.rotation = safeNormalize(flipped(glm::conjugate(parent) * qt[j], tj.flip));
  }
  if (translateHips_) {
    glm::mat4 m = sourceRootTransform_;
    for (int i : hipsPath_) m = affineMultiply(m, sourceLocal[static_cast<std::size_t>(i)].matrix());
    const glm::vec3 disp = align_ * (glm::vec3(m[3]) - sourceHipsRef_);
    const glm::vec3 p = targetHipsRest_ + glm::vec3(hScale_ * disp.x, vScale_ * disp.y, hScale_ * disp.z);
    const glm::vec3 local = glm::vec3(targetHipsParentInverse_ * glm::vec4(p, 1.0f));
    if (isFinite(local)) targetLocal[static_cast<std::size_t>(targetHips_)].translation = local;
  }
  placeDetached(targetLocal);
  if (anyIk_) {
    applyIk(sourceLocal, targetLocal, scratch, dt);
    placeDetached(targetLocal);
  }
}

void Retargeter::placeDetached(std::span<Transform> targetLocal) const noexcept {
  for (const DetachedEnd& d : detached_) {
    const glm::vec3 p = glm::vec3(modelMatrixOf(targetSkeleton_, targetLocal, d.lower) * glm::vec4(d.offsetInLower, 1.0f));
    const int parent = target_[static_cast<std::size_t>(d.end)].parent;
    const glm::mat4 pm = parent < 0 ? targetSkeleton_.rootTransform : modelMatrixOf(targetSkeleton_, targetLocal, parent);
    const glm::vec3 local = glm::vec3(glm::inverse(pm) * glm::vec4(p, 1.0f));
    if (isFinite(local)) targetLocal[static_cast<std::size_t>(d.end)].translation = local;
  }
}

void Retargeter::applyIk(std::span<const Transform> sourceLocal, std::span<Transform> targetLocal,
                         RetargetScratch& scratch, float dt) const noexcept {
  const std::size_t ns = source_.size(), nt = target_.size();
  localToModel(sourceSkeleton_, sourceLocal.first(ns), std::span<glm::mat4>(scratch.sourceModel).first(ns));
  localToModel(targetSkeleton_, targetLocal.first(nt), std::span<glm::mat4>(scratch.targetModel).first(nt));
  const bool timed = dt > 0.0f && std::isfinite(dt);
  for (std::size_t k = 0; k < effectors_.size(); ++k) {
    const IkEffector& e = effectors_[k];
    if (e.limb.upper < 0) continue;
    RetargetScratch::Effector& st = scratch.effectors[k];
    if (!timed) st = {};
    const glm::vec3 ps = glm::vec3(scratch.sourceModel[static_cast<std::size_t>(e.sourceEnd)][3]);
    if (!isFinite(ps)) {
      st = {};
      continue;
    }
    const float speed = timed && st.havePrevious
                            ? glm::length(glm::vec2(ps.x - st.previousSource.x, ps.z - st.previousSource.z)) / dt
                            : 0.0f;
    const bool contact =
        e.foot ? ps.y - sourceFootRestY_[k] < ik_.contactHeight * sourceLegLength_ &&
                     speed < ik_.contactSpeed * sourceLegLength_
               : timed && st.havePrevious && speed < ik_.handContactSpeed * sourceLegLength_;
    st.previousSource = ps;
    st.havePrevious = true;

    const glm::mat4& lower = scratch.targetModel[static_cast<std::size_t>(e.limb.lower)];
    const glm::vec3 fk = e.limb.endIsDescendant ? glm::vec3(scratch.targetModel[static_cast<std::size_t>(e.limb.end)][3])
                                                : glm::vec3(lower * glm::vec4(e.limb.endOffsetInLower, 1.0f));
    // Where the effector is drawn now: FK plus what is left of a released hold.
    if (timed && !st.inContact) st.sinceRelease += dt;
    const float ease = ik_.blendTime > 0.0f ? 1.0f - static_cast<float>(smoothstep(st.sinceRelease / ik_.blendTime)) : 0.0f;
    glm::vec3 goal = fk + glm::vec3(st.offset.x, 0.0f, st.offset.y) * ease;
    if (contact && !st.inContact) st.held = goal;  // touch-down: hold it here
    if (contact) goal = glm::vec3(st.held.x, fk.y, st.held.z);
    if (!contact && st.inContact) {  // lift-off: ease the hold out
      st.offset = glm::vec2(st.held.x - fk.x, st.held.z - fk.z);
      st.sinceRelease = 0.0f;
      goal = glm::vec3(st.held.x, fk.y, st.held.z);
    }
    st.inContact = contact;
    if (glm::dot(goal - fk, goal - fk) < 1e-12f) continue;

    // The knee (elbow) bends where it bends now: pole pushed out from the hip-ankle line.
    const glm::vec3 upperPos = glm::vec3(scratch.targetModel[static_cast<std::size_t>(e.limb.upper)][3]);
    const glm::vec3 knee = glm::vec3(lower[3]);
    const glm::vec3 pole = knee + (knee - 0.5f * (upperPos + fk));
    solveTwoBoneIk(targetSkeleton_, targetLocal, e.limb, goal, pole, 1.0f);
    // Keep the end's model rotation (the foot flat as in the motion): recompute
    // model rotations from the upper joint down to the end's parent.
    if (!e.limb.endIsDescendant) continue;
    const int endParent = targetSkeleton_.parents[static_cast<std::size_t>(e.limb.end)];
    std::array<int, 16> path{};
    std::size_t depth = 0;
    for (int j = endParent; j >= 0 && depth < path.size(); j = target_[static_cast<std::size_t>(j)].parent) {
      path[depth++] = j;
      if (j == e.limb.upper) break;
    }
    if (depth == 0 || path[depth - 1] != e.limb.upper) continue;  // deeper than 16 joints: leave the end as IK left it
    glm::quat* qt = scratch.target.data();
    for (std::size_t d = depth; d-- > 0;) {
      const TargetJoint& tj = target_[static_cast<std::size_t>(path[d])];
      const glm::quat& parent = tj.parent < 0 ? targetRoot_ : qt[tj.parent];
      qt[path[d]] = safeNormalize(parent * flipped(targetLocal[static_cast<std::size_t>(path[d])].rotation, tj.flip));
    }
    const TargetJoint& ej = target_[static_cast<std::size_t>(e.limb.end)];
    targetLocal[static_cast<std::size_t>(e.limb.end)].rotation =
        safeNormalize(flipped(glm::conjugate(qt[endParent]) * qt[e.limb.end], ej.flip));
  }
}

Clip Retargeter::retargetClip(const Clip& sourceClip, float sampleRate) const {
  Clip out;
  out.name = sourceClip.name;
  if (!valid_ || !sourceClip.validate(source_.size()).empty()) return out;
  std::vector<float> times;
  if (sampleRate > 0.0f && std::isfinite(sampleRate)) {
    const auto frames = static_cast<std::size_t>(std::floor(sourceClip.duration * sampleRate + 1e-3f));
    for (std::size_t k = 0; k <= frames; ++k) times.push_back(static_cast<float>(k) / sampleRate);
    if (times.back() < sourceClip.duration - 1e-6f) times.push_back(sourceClip.duration);
  } else {
    for (const JointTrack& t : sourceClip.tracks) {
      times.insert(times.end(), t.translation.times.begin(), t.translation.times.end());
      times.insert(times.end(), t.rotation.times.begin(), t.rotation.times.end());
      times.insert(times.end(), t.scale.times.begin(), t.scale.times.end());
    }
    std::sort(times.begin(), times.end());
    // Keys a microsecond apart are one key (tracks exported with rounding differences).
    times.erase(std::unique(times.begin(), times.end(), [](float a, float b) { return b - a < 1e-6f; }), times.end());
    if (times.empty()) times.push_back(0.0f);
  }

  const std::vector<int> driven = drivenJoints();
  std::vector<int> trackOf(target_.size(), -1);
  for (int j : driven) trackOf[static_cast<std::size_t>(j)] = 0;
  std::vector<std::uint8_t> moves(target_.size(), 0);  // joints with a translation track
  if (translateHips_) moves[static_cast<std::size_t>(targetHips_)] = 1;
  for (const DetachedEnd& d : detached_) moves[static_cast<std::size_t>(d.end)] = 1;
  for (std::size_t j = 0; j < target_.size(); ++j)
    if (moves[j]) trackOf[j] = 0;
  for (std::size_t j = 0; j < target_.size(); ++j) {
    if (trackOf[j] < 0) continue;
    trackOf[j] = static_cast<int>(out.tracks.size());
    JointTrack& t = out.tracks.emplace_back();
    t.joint = static_cast<int>(j);
    if (target_[j].srcA >= 0) {
      t.rotation.times = times;
      t.rotation.values.reserve(times.size());
    }
    if (moves[j]) {
      t.translation.times = times;
      t.translation.values.reserve(times.size());
    }
  }

  std::vector<Transform> src(source_.size()), tgt(target_.size());
  RetargetScratch scratch = makeScratch();
  SamplingCursor cursor;
  cursor.reset(sourceClip);
  float previousTime = -1.0f;
  for (float time : times) {
    sampleClip(sourceClip, time, sourceRest_, src, &cursor);
    applyImpl(src, tgt, scratch, previousTime >= 0.0f ? time - previousTime : 0.0f);
    previousTime = time;
    for (JointTrack& t : out.tracks) {
      const Transform& x = tgt[static_cast<std::size_t>(t.joint)];
      if (!t.rotation.times.empty()) {
        glm::quat q = x.rotation;
        // Keep neighbouring keys in one hemisphere so that linear keys interpolate the short way.
        if (!t.rotation.values.empty() && glm::dot(t.rotation.values.back(), q) < 0.0f) q = -q;
        t.rotation.values.push_back(q);
      }
      if (!t.translation.times.empty()) t.translation.values.push_back(x.translation);
    }
  }
  out.updateDuration();
  for (const ClipEvent& e : sourceClip.events)  // the markers travel with the motion
    if (e.time <= out.duration) out.events.push_back(e);
  return out;
}

}  // namespace marionette::retarget
