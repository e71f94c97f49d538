#include "marionette/animation/root_motion.hpp"

#include <algorithm>
#include <cmath>

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
  if (t <= times.front()) {
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
  const glm::mat4 parentInv = glm::inverse(parent);
  const glm::quat parentRot = safeNormalize(glm::quat_cast(glm::mat3(parent)));
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
  auto removeAt = [&](float time, glm::vec3& translation, glm::quat& rotation, bool fixT, bool fixR) {
    glm::vec3 off;
    float yaw;
    rm.evaluate(time, off, yaw);
    const glm::quat unYaw = yawQuat(-yaw);
    if (fixT) {
      glm::vec3 model = glm::vec3(parent * glm::vec4(translation, 1.0f)) - off;
      // The remaining motion turns with the removed yaw about the start position.
      glm::vec3 start(pos[0].x, 0.0f, pos[0].z);
      model = start + unYaw * (model - start);
      translation = glm::vec3(parentInv * glm::vec4(model, 1.0f));
    }
    if (fixR) rotation = safeNormalize(glm::inverse(parentRot) * unYaw * parentRot * rotation);
  };
  // Cubic tangents are left as they are: they describe the motion around the key.
  const std::size_t tStride = jt.translation.interpolation == Interpolation::CubicSpline ? 3 : 1;
  const std::size_t tOff = tStride == 3 ? 1 : 0;
  for (std::size_t k = 0; k < jt.translation.times.size(); ++k) {
    glm::quat dummy(1, 0, 0, 0);
    removeAt(jt.translation.times[k], jt.translation.values[k * tStride + tOff], dummy, true, false);
  }
  const std::size_t rStride = jt.rotation.interpolation == Interpolation::CubicSpline ? 3 : 1;
  const std::size_t rOff = rStride == 3 ? 1 : 0;
  for (std::size_t k = 0; k < jt.rotation.times.size(); ++k) {
    glm::vec3 dummy(0.0f);
    removeAt(jt.rotation.times[k], dummy, jt.rotation.values[k * rStride + rOff], false, true);
  }
  return rm;
}

}  // namespace marionette
