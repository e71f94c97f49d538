// Small hand-made skeletons and clips whose poses are known exactly.
#pragma once
#include <cmath>
#include <string>

#include "marionette/animation/clip.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette::test {

// A chain of `n` joints, each 1 unit above its parent along +Y.
inline Skeleton makeChain(int n, float boneLength = 1.0f) {
  Skeleton s;
  for (int i = 0; i < n; ++i) {
    Transform t;
    t.translation = i == 0 ? glm::vec3(0.0f) : glm::vec3(0.0f, boneLength, 0.0f);
    s.addJoint("j" + std::to_string(i), i - 1, t, glm::mat4(1.0f), true);
  }
  // Inverse bind = inverse of the rest model matrix, as an exporter writes it.
  auto model = s.restModelMatrices();
  for (int i = 0; i < n; ++i) s.inverseBind[i] = glm::inverse(model[i]);
  return s;
}

// Rotation about `axis` by `angles[k]` radians at `times[k]`, on joint `joint`.
inline JointTrack rotationTrack(int joint, std::vector<float> times, std::vector<float> angles,
                                glm::vec3 axis = {0, 0, 1}, Interpolation mode = Interpolation::Linear) {
  JointTrack jt;
  jt.joint = joint;
  jt.rotation.interpolation = mode;
  jt.rotation.times = std::move(times);
  for (float a : angles) jt.rotation.values.push_back(glm::angleAxis(a, axis));
  return jt;
}

inline bool finite(const Transform& t) {
  return std::isfinite(t.translation.x) && std::isfinite(t.translation.y) && std::isfinite(t.translation.z) &&
         std::isfinite(t.rotation.w) && std::isfinite(t.rotation.x) && std::isfinite(t.rotation.y) &&
         std::isfinite(t.rotation.z) && std::isfinite(t.scale.x) && std::isfinite(t.scale.y) &&
         std::isfinite(t.scale.z);
}

// Angle between two rotations in radians (q and -q are the same).
inline float angleBetween(const glm::quat& a, const glm::quat& b) {
  float d = std::fabs(a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z);
  return 2.0f * std::acos(std::min(1.0f, d));
}

}  // namespace marionette::test
