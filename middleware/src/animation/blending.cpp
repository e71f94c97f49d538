#include "marionette/animation/blending.hpp"

#include <algorithm>
#include <cmath>

namespace marionette {

namespace {
float sanitizeWeight(float w) noexcept { return (w > 0.0f && std::isfinite(w)) ? w : 0.0f; }

float dot(const glm::quat& a, const glm::quat& b) noexcept {
  return a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
}
}  // namespace

void blendPoses(std::span<const BlendLayer> layers, std::span<const Transform> rest,
                std::span<Transform> out) noexcept {
  const std::size_t n = std::min(rest.size(), out.size());
  for (std::size_t j = 0; j < n; ++j) {
    const Transform& r = rest[j];
    glm::vec3 t(0.0f), s(0.0f);
    glm::quat q(0.0f, 0.0f, 0.0f, 0.0f);
    float total = 0.0f;
    for (const BlendLayer& layer : layers) {
      if (layer.additive || j >= layer.pose.size()) continue;
      float w = sanitizeWeight(layer.weight);
      if (!layer.jointWeights.empty()) w *= j < layer.jointWeights.size() ? sanitizeWeight(layer.jointWeights[j]) : 0.0f;
      if (w <= 0.0f) continue;
      const Transform& p = layer.pose[j];
      const float sw = dot(p.rotation, r.rotation) < 0.0f ? -w : w;
      t += p.translation * w;
      s += p.scale * w;
      q = glm::quat(q.w + p.rotation.w * sw, q.x + p.rotation.x * sw, q.y + p.rotation.y * sw,
                    q.z + p.rotation.z * sw);
      total += w;
    }
    if (total < 1.0f) {  // rest fills the remainder
      const float w = 1.0f - total;
      t += r.translation * w;
      s += r.scale * w;
      q = glm::quat(q.w + r.rotation.w * w, q.x + r.rotation.x * w, q.y + r.rotation.y * w, q.z + r.rotation.z * w);
      total = 1.0f;
    }
    const float inv = 1.0f / total;
    Transform& o = out[j];
    o.translation = t * inv;
    o.scale = s * inv;
    // Opposite rotations at equal weight cancel to zero: fall back to rest.
    const float len2 = dot(q, q);
    o.rotation = len2 > 1e-12f ? safeNormalize(q) : r.rotation;
  }
  for (const BlendLayer& layer : layers) {
    if (!layer.additive) continue;
    const float lw = sanitizeWeight(layer.weight);
    if (lw <= 0.0f) continue;
    const std::size_t m = std::min(n, layer.pose.size());
    for (std::size_t j = 0; j < m; ++j) {
      float w = lw;
      if (!layer.jointWeights.empty()) w *= j < layer.jointWeights.size() ? sanitizeWeight(layer.jointWeights[j]) : 0.0f;
      if (w <= 0.0f) continue;
      const Transform& d = layer.pose[j];
      Transform& o = out[j];
      o.rotation = safeNormalize(o.rotation * slerpShortest(glm::quat(1, 0, 0, 0), d.rotation, w));
      o.translation += d.translation * w;
      o.scale *= glm::mix(glm::vec3(1.0f), d.scale, w);
    }
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

}  // namespace marionette
