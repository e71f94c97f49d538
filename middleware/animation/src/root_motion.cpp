#include "marionette/animation/root_motion.hpp"

#include <algorithm>
#include <cmath>

#include "marionette/animation/clip_optimizer.hpp"  // rotationAngle

namespace marionette {

namespace {
constexpr float kPi = 3.14159265358979f;

glm::quat yawQuat(float yaw) noexcept { return glm::angleAxis(yaw, glm::vec3(0, 1, 0)); }
glm::vec3 rotateY(const glm::quat& q, const glm::vec3& v) noexcept { return q * v; }

// Model-space matrix of the root's parent at rest (the chain above is not animated here).
glm::mat4 parentRestModel(const Skeleton& s, int joint) {
  const int p = s.parents[joint];
  if (p < 0) return s.rootTransform;
  return s.restModelMatrices()[p];
}

// The root motion at `time` taken out of a model-space placement: the offset
// removed, then the yaw about the start position (where the clip stays): one
// rigid motion, applied to the root's keys.
struct Removal {
  const RootMotion& rm;
  glm::vec3 start;  // the root's model-space position at the first key, y = 0

  [[nodiscard]] glm::vec3 position(float time, const glm::vec3& model) const noexcept {
    glm::vec3 off;
    float yaw;
    rm.evaluate(time, off, yaw);
    return start + yawQuat(-yaw) * (model - off - start);
  }
  [[nodiscard]] glm::quat unYaw(float time) const noexcept {
    glm::vec3 off;
    float yaw;
    rm.evaluate(time, off, yaw);
    return yawQuat(-yaw);
  }
};

// The rotation of a model matrix without its scale. quat_cast assumes no scale:
// on a frame that scales by 100 and turns Z-up to Y-up (RobotExpressive's root
// transform) it gives a 126-degree turn instead of 90, and the yaw would be
// taken out about a tilted axis. (No asset here has both above its root-motion
// joint: RobotExpressive's `Bone` undoes the turn.)
glm::quat rotationOf(const glm::mat4& m) noexcept { return decompose(m).rotation; }

// The root's local values with the removal applied through its parent's rest frame.
struct JointFrame {
  glm::mat4 parent, parentInv;
  glm::quat parentRot;
  JointFrame(const Skeleton& s, int joint)
      : parent(parentRestModel(s, joint)), parentInv(glm::inverse(parent)), parentRot(rotationOf(parent)) {}

  [[nodiscard]] glm::vec3 translation(const Removal& r, float time, const glm::vec3& local) const noexcept {
    return glm::vec3(parentInv * glm::vec4(r.position(time, glm::vec3(parent * glm::vec4(local, 1.0f))), 1.0f));
  }
  [[nodiscard]] glm::quat rotation(const Removal& r, float time, const glm::quat& local) const noexcept {
    return safeNormalize(glm::inverse(parentRot) * r.unYaw(time) * parentRot * local);
  }
};

// How far a carried joint's linear track may stray from the exact correction
// between keys. A joint held still while the root travels and turns follows the
// removed offset turned by the removed yaw, which bends between the root's keys:
// with keys only there, RobotExpressive's feet in Punch (0.2 m and 9 degrees in
// one 42 ms interval) moved up to 9 mm against the shins; keys are added instead.
constexpr float kCarriedTranslationTolerance = 1e-4f;  // metres
constexpr float kCarriedRotationTolerance = 1e-3f;     // radians (0.1 mm at 10 cm)
constexpr int kMaxHalvings = 8;                        // at most 256 keys per interval

float distance(const glm::vec3& a, const glm::vec3& b) noexcept { return glm::length(a - b); }
float distance(const glm::quat& a, const glm::quat& b) noexcept { return rotationAngle(a, b); }
glm::vec3 halfway(const glm::vec3& a, const glm::vec3& b) noexcept { return 0.5f * (a + b); }
glm::quat halfway(const glm::quat& a, const glm::quat& b) noexcept { return nlerpShortest(a, b, 0.5f); }

// Appends keys over (a, b], halving the interval while its midpoint is off the line.
template <class T, class Exact>
void appendRefined(Track<T>& out, float a, const T& va, float b, const T& vb, Exact& exact, float tolerance,
                   int halvings) {
  const float m = 0.5f * (a + b);
  if (halvings > 0 && m > a && m < b) {
    const T vm = exact(m);
    if (distance(halfway(va, vb), vm) > tolerance) {
      appendRefined(out, a, va, m, vm, exact, tolerance, halvings - 1);
      appendRefined(out, m, vm, b, vb, exact, tolerance, halvings - 1);
      return;
    }
  }
  out.times.push_back(b);
  out.values.push_back(vb);
}

// The track of a carried joint: `source` (null: its rest value) with `fix(t, v)`
// applied, `sample(t)` being the source's value at t. Linear, with keys at the
// source's and the root's times (the correction is exact there) and wherever
// needed in between. (A cubic source's tangents would carry the travel that
// is taken out, so it is resampled too.)
template <class T, class Sample, class Fix>
Track<T> carriedTrack(const Track<T>* source, const std::vector<float>& rootTimes, float tolerance, Sample sample,
                      Fix fix) {
  std::vector<float> times = source ? source->times : std::vector<float>{};
  times.insert(times.end(), rootTimes.begin(), rootTimes.end());
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  auto exact = [&](float t) { return fix(t, sample(t)); };
  Track<T> out;
  out.interpolation = Interpolation::Linear;
  out.times.push_back(times.front());
  out.values.push_back(exact(times.front()));
  for (std::size_t k = 1; k < times.size(); ++k) {
    const T prev = out.values.back();
    appendRefined(out, times[k - 1], prev, times[k], exact(times[k]), exact, tolerance, kMaxHalvings);
  }
  return out;
}

// What the root loses at time t, as a model-space rigid motion: its in-place
// model transform times the inverse of its authored one. At the root's keys this
// is the Removal; between them it follows the root's own interpolation (the yaw
// of nlerped keys is not RootMotion's linear yaw), so that what is carried stays
// with the body at every time, not only at keys.
class RootLoss {
 public:
  RootLoss(const Skeleton& s, int root, const JointTrack& authored, const JointTrack& inPlace)
      : root_(root), rest_(s.restPose[static_cast<std::size_t>(root)]), parent_(parentRestModel(s, root)),
        scratch_(s.jointCount()) {
    authored_.tracks = {authored};
    inPlace_.tracks = {inPlace};
  }
  [[nodiscard]] glm::mat4 at(float t) {
    const glm::mat4 loss = model(inPlace_, t) * glm::inverse(model(authored_, t));
    for (int c = 0; c < 4; ++c)  // a degenerate root (zero scale, NaN keys): carry nothing
      for (int r = 0; r < 4; ++r)
        if (!std::isfinite(loss[c][r])) return glm::mat4(1.0f);
    return loss;
  }

 private:
  glm::mat4 model(const Clip& c, float t) {
    Transform& r = scratch_[static_cast<std::size_t>(root_)];
    r = rest_;
    sampleClipTracks(c, t, scratch_);
    return parent_ * r.matrix();
  }
  int root_;
  Transform rest_;
  glm::mat4 parent_;
  Clip authored_, inPlace_;  // the root's track alone, before and after
  std::vector<Transform> scratch_;
};

// Takes what the root loses out of the joints beside it (the rule is in the
// header): a carried joint's model transform becomes loss * model, i.e. its
// local one (parent's rest frame P) P^-1 * loss * P * local.
void carryWithRoot(Clip& clip, const Skeleton& s, RootMotion& rm, RootLoss& loss) {
  const std::size_t n = s.jointCount();
  std::vector<char> lineage(n, 0);  // the root and its ancestors
  for (int j = rm.joint; j >= 0; j = s.parents[static_cast<std::size_t>(j)]) lineage[static_cast<std::size_t>(j)] = 1;
  const bool turns = std::any_of(rm.yaw.begin(), rm.yaw.end(), [](float y) { return y != 0.0f; });
  std::vector<Transform> scratch(n);
  for (std::size_t j = 0; j < n; ++j) {
    const int p = s.parents[j];
    if (lineage[j] || (p >= 0 && (!lineage[static_cast<std::size_t>(p)] || p == rm.joint))) continue;
    const int joint = static_cast<int>(j);
    auto it = std::find_if(clip.tracks.begin(), clip.tracks.end(),
                           [&](const JointTrack& jt) { return jt.joint == joint; });
    Clip own;  // the joint's tracks alone, to sample between its keys
    if (it != clip.tracks.end()) own.tracks.push_back(*it);
    auto local = [&](float t) -> const Transform& {
      scratch[j] = s.restPose[j];
      sampleClipTracks(own, t, scratch);
      return scratch[j];
    };
    const glm::mat4 parent = parentRestModel(s, joint), parentInv = glm::inverse(parent);
    auto inParent = [&](float t) { return parentInv * loss.at(t) * parent; };  // the loss in the joint's parent frame
    // The tolerance is in metres; the parent frame may scale (RobotExpressive's by 100).
    const float metresPerUnit = std::max({glm::length(glm::vec3(parent[0])), glm::length(glm::vec3(parent[1])),
                                          glm::length(glm::vec3(parent[2])), 1e-12f});
    JointTrack carried;
    carried.joint = joint;
    const JointTrack* src = own.tracks.empty() ? nullptr : &own.tracks.front();
    carried.translation = carriedTrack<glm::vec3>(
        src && !src->translation.empty() ? &src->translation : nullptr, rm.times,
        kCarriedTranslationTolerance / metresPerUnit, [&](float t) { return local(t).translation; },
        [&](float t, const glm::vec3& v) { return glm::vec3(inParent(t) * glm::vec4(v, 1.0f)); });
    if (turns)
      carried.rotation = carriedTrack<glm::quat>(
          src && !src->rotation.empty() ? &src->rotation : nullptr, rm.times, kCarriedRotationTolerance,
          [&](float t) { return local(t).rotation; },
          [&](float t, const glm::quat& q) { return safeNormalize(rotationOf(inParent(t)) * q); });
    if (it != clip.tracks.end()) {
      it->translation = std::move(carried.translation);
      if (turns) it->rotation = std::move(carried.rotation);
    } else {  // tracks stay sorted by joint
      auto at = std::find_if(clip.tracks.begin(), clip.tracks.end(),
                             [&](const JointTrack& jt) { return jt.joint > joint; });
      clip.tracks.insert(at, std::move(carried));
    }
    rm.carried.push_back(joint);
  }
}

}  // namespace

int pickRootMotionJoint(const Clip& clip, const Skeleton& skeleton) {
  // The translated joint with the most descendants: the hips or the armature
  // root, not an IK target that happens to come first (RobotExpressive lists
  // Foot.L before Body).
  const std::size_t n = skeleton.jointCount();
  std::vector<int> descendants(n, 0);
  for (std::size_t i = n; i-- > 0;)
    if (skeleton.parents[i] >= 0) descendants[skeleton.parents[i]] += descendants[i] + 1;
  int best = -1;
  for (const JointTrack& jt : clip.tracks) {
    if (jt.translation.empty() || jt.joint < 0 || static_cast<std::size_t>(jt.joint) >= n) continue;
    if (best < 0 || descendants[jt.joint] > descendants[best]) best = jt.joint;
  }
  return best;
}

float yawOf(const glm::quat& q) noexcept {
  // Twist about Y: project the quaternion onto (w, 0, y, 0).
  const float w = q.w, y = q.y;
  if (w * w + y * y < 1e-12f) return 0.0f;  // a pure 180° swing: yaw undefined, take 0
  return 2.0f * std::atan2(y, w);
}

void RootMotion::evaluate(float t, glm::vec3& outOffset, float& outYaw) const noexcept {
  if (times.empty()) {
    outOffset = glm::vec3(0.0f);
    outYaw = 0.0f;
    return;
  }
  if (!(t > times.front())) {  // NaN included
    outOffset = offset.front();
    outYaw = yaw.front();
    return;
  }
  if (t >= times.back()) {
    outOffset = offset.back();
    outYaw = yaw.back();
    return;
  }
  const std::uint32_t i = findKeyInterval(times, t, 0);
  const float u = (t - times[i]) / (times[i + 1] - times[i]);
  outOffset = offset[i] + (offset[i + 1] - offset[i]) * u;
  outYaw = yaw[i] + (yaw[i + 1] - yaw[i]) * u;
}

void RootMotion::between(double t0, double t1, WrapMode mode, glm::vec3& delta, float& turn) const noexcept {
  delta = glm::vec3(0.0f);
  turn = 0.0f;
  if (times.empty() || !(t1 > t0) || !(duration > 0.0f)) return;
  glm::vec3 o0, o1;
  float y0, y1;
  if (mode == WrapMode::Clamp) {
    evaluate(wrapClipTime(t0, duration, mode), o0, y0);
    evaluate(wrapClipTime(t1, duration, mode), o1, y1);
    delta = rotateY(yawQuat(-y0), o1 - o0);
    turn = y1 - y0;
    return;
  }
  // Loop: whole cycles between the two times each add the full-cycle motion.
  const double d = duration;
  const double c0 = std::floor(t0 / d), c1 = std::floor(t1 / d);
  evaluate(static_cast<float>(t0 - c0 * d), o0, y0);
  evaluate(static_cast<float>(t1 - c1 * d), o1, y1);
  const glm::vec3 cycleOffset = offset.back();
  const float cycleYaw = yaw.back();
  // Walk from t0 to the cycle end, through full cycles, to t1; each piece in the
  // heading frame where it starts.
  glm::vec3 pos(0.0f);
  float heading = 0.0f;
  const double cycles = c1 - c0;
  if (cycles <= 0.0) {
    pos = rotateY(yawQuat(-y0), o1 - o0);
    heading = y1 - y0;
  } else {
    pos = rotateY(yawQuat(-y0), cycleOffset - o0);
    heading = cycleYaw - y0;
    // Full cycles (capped: a 10 s step of a 1 s clip is 10 cycles; a huge dt is
    // summed in closed form only if it would loop absurdly often).
    const double full = std::min(cycles - 1.0, 1.0e6);
    for (double k = 0; k < full; k += 1.0) {
      pos += rotateY(yawQuat(heading), cycleOffset);
      heading += cycleYaw;
    }
    pos += rotateY(yawQuat(heading), o1);
    heading += y1;
  }
  delta = pos;
  turn = heading;
}

RootMotion extractRootMotion(Clip& clip, const Skeleton& skeleton, int rootJoint) {
  RootMotion rm;
  if (rootJoint < 0) rootJoint = pickRootMotionJoint(clip, skeleton);
  if (rootJoint < 0 || static_cast<std::size_t>(rootJoint) >= skeleton.jointCount()) return rm;
  auto it = std::find_if(clip.tracks.begin(), clip.tracks.end(),
                         [&](const JointTrack& jt) { return jt.joint == rootJoint; });
  if (it == clip.tracks.end()) return rm;
  JointTrack& jt = *it;
  rm.joint = rootJoint;
  rm.duration = clip.duration;
  const glm::mat4 parent = parentRestModel(skeleton, rootJoint);
  const glm::quat parentRot = rotationOf(parent);
  const Transform& rest = skeleton.restPose[rootJoint];

  // Key times: union of the translation and rotation keys.
  std::vector<float> times = jt.translation.times;
  times.insert(times.end(), jt.rotation.times.begin(), jt.rotation.times.end());
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  if (times.empty()) return rm;

  // Model-space root position and yaw at each key.
  std::vector<glm::vec3> pos(times.size());
  std::vector<float> yaws(times.size());
  std::vector<Transform> scratch(skeleton.jointCount());
  for (std::size_t k = 0; k < times.size(); ++k) {
    scratch[rootJoint] = rest;
    sampleClipTracks(clip, times[k], scratch);
    const Transform& t = scratch[rootJoint];
    pos[k] = glm::vec3(parent * glm::vec4(t.translation, 1.0f));
    yaws[k] = yawOf(parentRot * t.rotation);
    if (k > 0) {  // unwrap so that a turning clip accumulates past ±π
      while (yaws[k] - yaws[k - 1] > kPi) yaws[k] -= 2 * kPi;
      while (yaws[k] - yaws[k - 1] < -kPi) yaws[k] += 2 * kPi;
    }
  }
  rm.times = times;
  rm.offset.resize(times.size());
  rm.yaw.resize(times.size());
  for (std::size_t k = 0; k < times.size(); ++k) {
    rm.offset[k] = glm::vec3(pos[k].x - pos[0].x, 0.0f, pos[k].z - pos[0].z);
    rm.yaw[k] = yaws[k] - yaws[0];
  }

  // Rewrite the root's tracks in place: remove the horizontal offset and the yaw.
  const JointTrack authored = jt;  // for what the carried joints lose (RootLoss)
  const Removal removal{rm, glm::vec3(pos[0].x, 0.0f, pos[0].z)};
  const JointFrame frame(skeleton, rootJoint);
  // Cubic tangents are left as they are: they describe the motion around the key.
  const std::size_t tStride = jt.translation.interpolation == Interpolation::CubicSpline ? 3 : 1;
  const std::size_t tOff = tStride == 3 ? 1 : 0;
  for (std::size_t k = 0; k < jt.translation.times.size(); ++k) {
    glm::vec3& v = jt.translation.values[k * tStride + tOff];
    v = frame.translation(removal, jt.translation.times[k], v);
  }
  const std::size_t rStride = jt.rotation.interpolation == Interpolation::CubicSpline ? 3 : 1;
  const std::size_t rOff = rStride == 3 ? 1 : 0;
  for (std::size_t k = 0; k < jt.rotation.times.size(); ++k) {
    glm::quat& q = jt.rotation.values[k * rStride + rOff];
    q = frame.rotation(removal, jt.rotation.times[k], q);
  }
  const bool travels =
      std::any_of(rm.offset.begin(), rm.offset.end(), [](const glm::vec3& o) { return o != glm::vec3(0.0f); });
  const bool moves = travels || std::any_of(rm.yaw.begin(), rm.yaw.end(), [](float y) { return y != 0.0f; });
  if (moves) {
    RootLoss loss(skeleton, rootJoint, authored, jt);
    carryWithRoot(clip, skeleton, rm, loss);  // may insert tracks: `jt` is not used after this
  }
  return rm;
}

}  // namespace marionette
