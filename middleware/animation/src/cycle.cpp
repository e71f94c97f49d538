#include "marionette/animation/cycle.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "marionette/animation/pose.hpp"
#include "marionette/animation/root_motion.hpp"
#include "marionette/animation/sampling.hpp"
#include "marionette/core/angles.hpp"

namespace marionette {

namespace {
glm::quat yawQuat(float yaw) noexcept { return glm::angleAxis(yaw, glm::vec3(0, 1, 0)); }

// The rotation of a 3x3 matrix with uniform scale (columns normalized).
glm::quat rotationOf(const glm::mat3& m) noexcept {
  glm::mat3 r(glm::normalize(m[0]), glm::normalize(m[1]), glm::normalize(m[2]));
  return glm::normalize(glm::quat_cast(r));
}

float angleBetween(const glm::quat& a, const glm::quat& b) noexcept {
  const float d = std::min(1.0f, std::fabs(glm::dot(glm::normalize(a), glm::normalize(b))));
  return 2.0f * std::acos(d);
}

// The root's model-space change from rest, as a rotation, for a local pose.
struct RootFrame {
  glm::mat4 parent{1.0f};  // the root's parent's model matrix (ancestors at rest)
  glm::mat3 restModel3{1.0f};
  int joint = -1;
  RootFrame(const Skeleton& s, int root) : joint(root) {
    if (root < 0) return;
    const int p = s.parents[static_cast<std::size_t>(root)];
    parent = p >= 0 ? modelMatrixOf(s, s.restPose, p) : s.rootTransform;
    restModel3 = glm::mat3(parent * s.restPose[static_cast<std::size_t>(root)].matrix());
  }
  [[nodiscard]] glm::quat change(const Transform& local) const noexcept {
    return rotationOf(glm::mat3(parent * local.matrix()) * glm::inverse(restModel3));
  }
  [[nodiscard]] glm::vec3 place(const Transform& local) const noexcept {
    return glm::vec3(parent * glm::vec4(local.translation, 1.0f));
  }
  // Local rotation and translation of the root after a model-space rotation g
  // about the origin and a model-space offset: model' = g * model + offset.
  void apply(Transform& local, const glm::quat& g, const glm::vec3& offset) const noexcept {
    const glm::mat3 p3(parent);
    const glm::quat k = rotationOf(glm::inverse(p3) * glm::mat3_cast(g) * p3);
    local.rotation = glm::normalize(k * local.rotation);
    const glm::vec3 model = g * place(local) + offset;
    local.translation = glm::vec3(glm::inverse(parent) * glm::vec4(model, 1.0f));
  }
};

int rootOf(const Clip& clip, const Skeleton& skeleton, int rootJoint) {
  if (rootJoint >= 0 && rootJoint < static_cast<int>(skeleton.jointCount())) return rootJoint;
  return pickRootMotionJoint(clip, skeleton);
}
}  // namespace

Clip cutClip(const Clip& clip, const Skeleton& skeleton, float start, float end, float rate) {
  Clip out;
  out.name = clip.name;
  start = std::clamp(start, 0.0f, clip.duration);
  end = std::clamp(end, start, clip.duration);
  if (!(rate > 0.0f)) rate = 60.0f;
  const int frames = std::max(2, static_cast<int>(std::lround((end - start) * rate)) + 1);
  std::vector<Transform> pose(skeleton.jointCount());
  for (const JointTrack& t : clip.tracks) {
    JointTrack o;
    o.joint = t.joint;
    out.tracks.push_back(std::move(o));
  }
  for (int f = 0; f < frames; ++f) {
    const float u = static_cast<float>(f) / static_cast<float>(frames - 1);
    const float local = u * (end - start);
    sampleClip(clip, start + local, skeleton.restPose, pose);
    for (std::size_t k = 0; k < clip.tracks.size(); ++k) {
      const JointTrack& src = clip.tracks[k];
      JointTrack& dst = out.tracks[k];
      if (src.joint < 0 || src.joint >= static_cast<int>(pose.size())) continue;
      const Transform& x = pose[static_cast<std::size_t>(src.joint)];
      if (!src.translation.empty()) dst.translation.times.push_back(local), dst.translation.values.push_back(x.translation);
      if (!src.rotation.empty()) dst.rotation.times.push_back(local), dst.rotation.values.push_back(x.rotation);
      if (!src.scale.empty()) dst.scale.times.push_back(local), dst.scale.values.push_back(x.scale);
    }
  }
  out.updateDuration();
  for (const ClipEvent& e : clip.events)  // the markers inside the cut, on its time
    if (e.time >= start && e.time <= end) out.events.push_back({std::min(e.time - start, out.duration), e.name});
  return out;
}

LoopMatch findBestLoop(const Clip& clip, const Skeleton& skeleton, float from, float to,
                       const LoopSearchOptions& options) {
  LoopMatch best;
  from = std::clamp(from, 0.0f, clip.duration);
  to = std::clamp(to, from, clip.duration);
  const float step = options.step > 1e-4f ? options.step : 1.0f / 120.0f;
  if (to - from < options.minDuration || clip.tracks.empty()) return best;
  const int root = rootOf(clip, skeleton, options.rootJoint);
  const RootFrame frame(skeleton, root);
  std::vector<int> joints;  // animated joints but the root (compared locally)
  for (const JointTrack& t : clip.tracks)
    if (!t.rotation.empty() && t.joint != root && t.joint >= 0 && t.joint < static_cast<int>(skeleton.jointCount()))
      joints.push_back(t.joint);
  const int n = static_cast<int>(std::floor((to - from) / step)) + 1;
  // Per frame: the compared rotations (root tilt first), the root's height and yaw.
  const std::size_t width = joints.size() + 1;
  std::vector<glm::quat> rot(static_cast<std::size_t>(n) * width);
  std::vector<float> height(static_cast<std::size_t>(n)), yaw(static_cast<std::size_t>(n));
  std::vector<Transform> pose(skeleton.jointCount());
  for (int f = 0; f < n; ++f) {
    sampleClip(clip, from + step * static_cast<float>(f), skeleton.restPose, pose);
    glm::quat* r = &rot[static_cast<std::size_t>(f) * width];
    if (root >= 0) {
      const Transform& x = pose[static_cast<std::size_t>(root)];
      const glm::quat c = frame.change(x);
      yaw[static_cast<std::size_t>(f)] = yawOf(c);
      r[0] = glm::inverse(yawQuat(yaw[static_cast<std::size_t>(f)])) * c;
      height[static_cast<std::size_t>(f)] = frame.place(x).y;
    }
    for (std::size_t j = 0; j < joints.size(); ++j) r[j + 1] = pose[static_cast<std::size_t>(joints[j])].rotation;
  }
  const int minGap = static_cast<int>(std::ceil(options.minDuration / step));
  const int maxGap = static_cast<int>(std::floor(options.maxDuration / step));
  const std::size_t first = root >= 0 ? 0 : 1;
  float bestScore = INFINITY;
  for (int a = 0; a < n; ++a)
    for (int b = a + minGap; b < n && b - a <= maxGap; ++b) {
      const glm::quat* ra = &rot[static_cast<std::size_t>(a) * width];
      const glm::quat* rb = &rot[static_cast<std::size_t>(b) * width];
      double sum = 0.0;
      for (std::size_t j = first; j < width; ++j) {
        const float d = angleBetween(ra[j], rb[j]);
        sum += static_cast<double>(d) * d;
      }
      const float score = static_cast<float>(std::sqrt(sum / static_cast<double>(width - first)));
      if (score < bestScore) {
        bestScore = score;
        best.found = true;
        best.start = from + step * static_cast<float>(a);
        best.end = from + step * static_cast<float>(b);
      }
    }
  if (!best.found) return best;
  const int a = static_cast<int>(std::lround((best.start - from) / step));
  const int b = static_cast<int>(std::lround((best.end - from) / step));
  best.residual = bestScore;
  for (std::size_t j = first; j < width; ++j) {
    const float d = angleBetween(rot[static_cast<std::size_t>(a) * width + j], rot[static_cast<std::size_t>(b) * width + j]);
    if (d > best.worstJoint) best.worstJoint = d, best.worstJointIndex = j == 0 ? root : joints[j - 1];
  }
  if (root >= 0) {
    best.rootHeight = height[static_cast<std::size_t>(b)] - height[static_cast<std::size_t>(a)];
    best.turn = wrapAngle(yaw[static_cast<std::size_t>(b)] - yaw[static_cast<std::size_t>(a)]);
  }
  return best;
}

float closeLoop(Clip& clip, const Skeleton& skeleton, int rootJoint) {
  const float T = clip.duration;
  if (!(T > 0.0f)) return 0.0f;
  const int root = rootOf(clip, skeleton, rootJoint);
  const RootFrame frame(skeleton, root);
  // Joints but the root: local rotation, the end-to-start difference spread over time.
  for (JointTrack& t : clip.tracks) {
    if (t.joint == root || t.rotation.values.size() < 2 || t.rotation.interpolation == Interpolation::CubicSpline)
      continue;
    const glm::quat delta = glm::normalize(glm::inverse(t.rotation.values.back()) * t.rotation.values.front());
    for (std::size_t k = 0; k < t.rotation.values.size(); ++k) {
      const float u = t.rotation.times[k] / T;
      t.rotation.values[k] = glm::normalize(t.rotation.values[k] * glm::slerp(glm::quat(1, 0, 0, 0), delta, u));
    }
  }
  if (root < 0) return 0.0f;
  JointTrack* rt = nullptr;
  for (JointTrack& t : clip.tracks)
    if (t.joint == root) rt = &t;
  if (!rt) return 0.0f;
  const Transform& rest = skeleton.restPose[static_cast<std::size_t>(root)];
  // Tilt (the change from rest without its yaw): its end-to-start difference spread.
  if (rt->rotation.values.size() >= 2 && rt->rotation.interpolation != Interpolation::CubicSpline) {
    Transform x0 = rest, x1 = rest;
    x0.rotation = rt->rotation.values.front();
    x1.rotation = rt->rotation.values.back();
    const glm::quat c0 = frame.change(x0), c1 = frame.change(x1);
    const glm::quat tilt0 = glm::inverse(yawQuat(yawOf(c0))) * c0, tilt1 = glm::inverse(yawQuat(yawOf(c1))) * c1;
    const glm::quat delta = glm::normalize(glm::inverse(tilt1) * tilt0);
    for (std::size_t k = 0; k < rt->rotation.values.size(); ++k) {
      Transform x = rest;
      x.rotation = rt->rotation.values[k];
      const glm::quat c = frame.change(x);
      const glm::quat y = yawQuat(yawOf(c));
      const glm::quat tilt = glm::inverse(y) * c;
      const glm::quat wanted = y * tilt * glm::slerp(glm::quat(1, 0, 0, 0), delta, rt->rotation.times[k] / T);
      frame.apply(x, glm::normalize(wanted * glm::inverse(c)), glm::vec3(0.0f));
      rt->rotation.values[k] = x.rotation;
    }
  }
  // Height: the end-to-start difference spread.
  if (rt->translation.values.size() >= 2 && rt->translation.interpolation != Interpolation::CubicSpline) {
    Transform x0 = rest, x1 = rest;
    x0.translation = rt->translation.values.front();
    x1.translation = rt->translation.values.back();
    const float dy = frame.place(x0).y - frame.place(x1).y;
    for (std::size_t k = 0; k < rt->translation.values.size(); ++k) {
      Transform x = rest;
      x.translation = rt->translation.values[k];
      const glm::vec3 model = frame.place(x) + glm::vec3(0.0f, dy * rt->translation.times[k] / T, 0.0f);
      rt->translation.values[k] = glm::vec3(glm::inverse(frame.parent) * glm::vec4(model, 1.0f));
    }
  }
  // Facing and place: turn about +Y so that the facing at time 0 is the rest's,
  // and start over the rest place.
  std::vector<Transform> pose(skeleton.restPose);
  sampleClipTracks(clip, 0.0f, pose);
  const Transform start = pose[static_cast<std::size_t>(root)];
  const float turn = -yawOf(frame.change(start));
  const glm::quat g = yawQuat(turn);
  const glm::vec3 p0 = g * frame.place(start), pr = frame.place(rest);
  const glm::vec3 offset(pr.x - p0.x, 0.0f, pr.z - p0.z);
  for (std::size_t k = 0; k < rt->rotation.values.size(); ++k) {
    Transform x = rest;
    x.rotation = rt->rotation.values[k];
    frame.apply(x, g, glm::vec3(0.0f));
    rt->rotation.values[k] = x.rotation;
  }
  for (std::size_t k = 0; k < rt->translation.values.size(); ++k) {
    Transform x = rest;
    x.rotation = glm::quat(1, 0, 0, 0);
    x.translation = rt->translation.values[k];
    frame.apply(x, g, offset);
    rt->translation.values[k] = x.translation;
  }
  return turn;
}

float groundClip(Clip& clip, const Skeleton& skeleton, std::span<const int> feet, int rootJoint) {
  const int root = rootOf(clip, skeleton, rootJoint);
  if (root < 0 || !(clip.duration > 0.0f)) return 0.0f;
  JointTrack* rt = nullptr;
  for (JointTrack& t : clip.tracks)
    if (t.joint == root) rt = &t;
  if (!rt || rt->translation.empty() || rt->translation.interpolation == Interpolation::CubicSpline) return 0.0f;
  const int n = static_cast<int>(skeleton.jointCount());
  const std::vector<glm::mat4> restModel = skeleton.restModelMatrices();
  std::vector<Transform> pose(skeleton.jointCount());
  std::vector<glm::mat4> model(skeleton.jointCount());
  float lowest = INFINITY;
  const int samples = std::max(2, static_cast<int>(std::ceil(clip.duration * 120.0f)) + 1);
  for (int k = 0; k < samples; ++k) {
    sampleClip(clip, clip.duration * static_cast<float>(k) / static_cast<float>(samples - 1), skeleton.restPose, pose);
    localToModel(skeleton, pose, model);
    for (int f : feet)
      if (f >= 0 && f < n)
        lowest = std::min(lowest, model[static_cast<std::size_t>(f)][3].y - restModel[static_cast<std::size_t>(f)][3].y);
  }
  if (!std::isfinite(lowest)) return 0.0f;
  const RootFrame frame(skeleton, root);
  for (glm::vec3& v : rt->translation.values) {
    Transform x;
    x.translation = v;
    const glm::vec3 m = frame.place(x) - glm::vec3(0.0f, lowest, 0.0f);
    v = glm::vec3(glm::inverse(frame.parent) * glm::vec4(m, 1.0f));
  }
  return -lowest;
}

}  // namespace marionette
