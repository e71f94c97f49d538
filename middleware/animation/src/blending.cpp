#include "marionette/animation/blending.hpp"

#include <algorithm>
#include <cmath>

namespace marionette {

namespace {
float sanitizeWeight(float w) noexcept { return (w > 0.0f && std::isfinite(w)) ? w : 0.0f; }

float dot(const glm::quat& a, const glm::quat& b) noexcept {
  return a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
}

// Weight of joint j in a layer: layer weight times its mask (missing mask entries count as 0).
float jointWeight(float layerWeight, std::span<const float> mask, std::size_t j) noexcept {
  if (mask.empty()) return layerWeight;
  return j < mask.size() ? layerWeight * sanitizeWeight(mask[j]) : 0.0f;
}

// Per-joint sums shared by blendPoses and BlendAccumulator.
struct JointSum {
  glm::vec3 t{0.0f}, s{0.0f};
  glm::quat q{0.0f, 0.0f, 0.0f, 0.0f};
  float w = 0.0f;
};

// Rotations are sign-aligned to the rest rotation, so the sum does not depend on layer order.
inline void accumulate(JointSum& sum, const Transform& p, const Transform& rest, float w) noexcept {
  const float sw = dot(p.rotation, rest.rotation) < 0.0f ? -w : w;
  sum.t += p.translation * w;
  sum.s += p.scale * w;
  sum.q = glm::quat(sum.q.w + p.rotation.w * sw, sum.q.x + p.rotation.x * sw, sum.q.y + p.rotation.y * sw,
                    sum.q.z + p.rotation.z * sw);
  sum.w += w;
}

inline Transform finishJoint(JointSum sum, const Transform& rest) noexcept {
  if (sum.w < 1.0f) accumulate(sum, rest, rest, 1.0f - sum.w);  // rest fills the remainder
  const float inv = 1.0f / sum.w;
  Transform o;
  o.translation = sum.t * inv;
  o.scale = sum.s * inv;
  // Opposite rotations at equal weight cancel to zero: fall back to rest.
  o.rotation = dot(sum.q, sum.q) > 1e-12f ? safeNormalize(sum.q) : rest.rotation;
  return o;
}

inline void addDelta(Transform& o, const Transform& d, float w) noexcept {
  o.rotation = safeNormalize(o.rotation * slerpShortest(glm::quat(1, 0, 0, 0), d.rotation, w));
  o.translation += d.translation * w;
  o.scale *= glm::mix(glm::vec3(1.0f), d.scale, w);
}
}  // namespace

void blendPoses(std::span<const BlendLayer> layers, std::span<const Transform> rest,
                std::span<Transform> out) noexcept {
  const std::size_t n = std::min(rest.size(), out.size());
  for (std::size_t j = 0; j < n; ++j) {
    JointSum sum;
    for (const BlendLayer& layer : layers) {
      if (layer.additive || j >= layer.pose.size()) continue;
      const float w = jointWeight(sanitizeWeight(layer.weight), layer.jointWeights, j);
      if (w > 0.0f) accumulate(sum, layer.pose[j], rest[j], w);
    }
    out[j] = finishJoint(sum, rest[j]);
  }
  for (const BlendLayer& layer : layers)
    if (layer.additive) applyAdditive(layer.pose, layer.weight, layer.jointWeights, out.first(n));
}

void BlendAccumulator::reset(std::size_t joints) {
  joints_ = joints;
  translation_.assign(joints, glm::vec3(0.0f));
  scale_.assign(joints, glm::vec3(0.0f));
  rotation_.assign(joints, glm::quat(0.0f, 0.0f, 0.0f, 0.0f));
  weight_.assign(joints, 0.0f);
}

void BlendAccumulator::addNormal(std::span<const Transform> pose, float weight, std::span<const float> jointWeights,
                                 std::span<const Transform> rest) noexcept {
  const float lw = sanitizeWeight(weight);
  if (lw <= 0.0f) return;
  const std::size_t n = std::min({joints_, pose.size(), rest.size()});
  for (std::size_t j = 0; j < n; ++j) {
    const float w = jointWeight(lw, jointWeights, j);
    if (w <= 0.0f) continue;
    JointSum sum{translation_[j], scale_[j], rotation_[j], weight_[j]};
    accumulate(sum, pose[j], rest[j], w);
    translation_[j] = sum.t;
    scale_[j] = sum.s;
    rotation_[j] = sum.q;
    weight_[j] = sum.w;
  }
}

void BlendAccumulator::finish(std::span<const Transform> rest, std::span<Transform> out) const noexcept {
  const std::size_t n = std::min({joints_, rest.size(), out.size()});
  for (std::size_t j = 0; j < n; ++j)
    out[j] = finishJoint({translation_[j], scale_[j], rotation_[j], weight_[j]}, rest[j]);
}

void applyAdditive(std::span<const Transform> delta, float weight, std::span<const float> jointWeights,
                   std::span<Transform> pose) noexcept {
  const float lw = sanitizeWeight(weight);
  if (lw <= 0.0f) return;
  const std::size_t n = std::min(delta.size(), pose.size());
  for (std::size_t j = 0; j < n; ++j) {
    const float w = jointWeight(lw, jointWeights, j);
    if (w > 0.0f) addDelta(pose[j], delta[j], w);
  }
}

void makeAdditiveDelta(std::span<const Transform> pose, std::span<const Transform> reference,
                       std::span<Transform> outDelta) noexcept {
  const std::size_t n = std::min({pose.size(), reference.size(), outDelta.size()});
  for (std::size_t j = 0; j < n; ++j) {
    const Transform& p = pose[j];
    const Transform& r = reference[j];
    Transform& d = outDelta[j];
    d.rotation = safeNormalize(glm::inverse(r.rotation) * p.rotation);
    d.translation = p.translation - r.translation;
    d.scale = glm::vec3(r.scale.x != 0.0f ? p.scale.x / r.scale.x : 1.0f, r.scale.y != 0.0f ? p.scale.y / r.scale.y : 1.0f,
                        r.scale.z != 0.0f ? p.scale.z / r.scale.z : 1.0f);
  }
}

void blendOver(std::span<Transform> pose, std::span<const Transform> layer, float weight,
               std::span<const float> jointWeights) noexcept {
  const float lw = std::min(sanitizeWeight(weight), 1.0f);
  if (lw <= 0.0f) return;
  const std::size_t n = std::min(pose.size(), layer.size());
  for (std::size_t j = 0; j < n; ++j) {
    const float w = std::min(jointWeight(lw, jointWeights, j), 1.0f);
    if (w <= 0.0f) continue;
    Transform& p = pose[j];
    const Transform& l = layer[j];
    p.translation = glm::mix(p.translation, l.translation, w);
    p.scale = glm::mix(p.scale, l.scale, w);
    p.rotation = slerpShortest(p.rotation, l.rotation, w);
  }
}

}  // namespace marionette
