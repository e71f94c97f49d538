// Blending local poses: N weighted layers with optional per-joint masks, then
// additive layers. Per-frame code: no allocation, no exceptions, never NaN.
// Spans: the span contract of pose.hpp (the shortest span decides; nothing past it is touched).
#pragma once
#include <span>
#include <vector>

#include "marionette/core/allocator.hpp"
#include "marionette/core/transform.hpp"

namespace marionette {

struct BlendLayer {
  std::span<const Transform> pose;        // one transform per joint
  float weight = 1.0f;                    // layer weight, >= 0 (negative and NaN count as 0)
  std::span<const float> jointWeights{};  // optional per-joint mask in [0, 1]; empty = all 1
  bool additive = false;                  // pose is a delta made by makeAdditiveDelta()
};

// Normal layers: per joint, the weighted mean of the layers' transforms with
// weights w = layer.weight * mask[j]. Weights are relative when they sum to 1 or
// more; below 1 the rest pose fills the remainder (a single layer fading in goes
// from rest to the clip; all weights 0 gives the rest pose, never NaN).
// Rotations: sign-aligned to the rest rotation before summing (q and -q are one
// rotation), then normalized.
// Additive layers are applied after, in order: rotation r = r * slerp(1, d, w),
// translation t += w * dt, scale s *= mix(1, ds, w).
void blendPoses(std::span<const BlendLayer> layers, std::span<const Transform> rest,
                std::span<Transform> out) noexcept;

// Layer-at-a-time form of blendPoses, what the runtime uses: sample a layer into
// any scratch pose, add it, reuse the scratch for the next layer. The same
// result as blendPoses (tested) with one scratch pose for all layers and all
// characters of a scene, instead of one pose per layer per character.
// The sums are kept as structure of arrays (one stream per component), and on x86-64
// four joints are summed and finished at a time with SSE2, bit-identical to the scalar
// form (simd4.hpp says why).
class BlendAccumulator {
 public:
  void reset(std::size_t joints);  // allocates only when `joints` grows
  // `rest` must be the same pose (same span, same values) from reset to finish: its
  // rotations are turned into streams once, on the first addNormal.
  void addNormal(std::span<const Transform> pose, float weight, std::span<const float> jointWeights,
                 std::span<const Transform> rest) noexcept;
  // Weighted mean, rest filling the remainder below total weight 1 (as blendPoses).
  void finish(std::span<const Transform> rest, std::span<Transform> out) const noexcept;

  // Streams of the sums: translation x, y, z, rotation x, y, z, w, scale x, y, z, weight.
  static constexpr std::size_t kStreams = 11;

 private:
  [[nodiscard]] float* stream(std::size_t s) noexcept { return sums_.data() + s * stride_; }
  [[nodiscard]] const float* stream(std::size_t s) const noexcept { return sums_.data() + s * stride_; }
  void addJoint(std::size_t j, const Transform& pose, const Transform& rest, float w) noexcept;
  [[nodiscard]] Transform finishJoint(std::size_t j, const Transform& rest) const noexcept;

  std::size_t joints_ = 0;
  std::size_t stride_ = 0;  // joints rounded up to 4
  // Through the runtime allocator (core/allocator.hpp): a scene's blend scratch holds one.
  RuntimeVector<float> sums_;  // kStreams * stride_
  RuntimeVector<float> restRotation_;  // 4 * stride_: x, y, z, w streams of the rest pose's rotations
  const Transform* restOf_ = nullptr;  // the rest pose restRotation_ holds, since reset
};

// Applies an additive delta layer to `pose` in place (as blendPoses does).
void applyAdditive(std::span<const Transform> delta, float weight, std::span<const float> jointWeights,
                   std::span<Transform> pose) noexcept;

// Blends `layer` over `pose` in place: per joint, pose = mix(pose, layer, w) with
// w = min(weight * mask[j], 1) (slerp on the shortest arc for rotations); at w = 1 the
// joint takes the layer's transform as it is (a copy, not a renormalized slerp). Layers blended
// over one another in order give "the later wins at full weight", which is how
// behaviors on one body channel hand over smoothly.
void blendOver(std::span<Transform> pose, std::span<const Transform> layer, float weight,
               std::span<const float> jointWeights) noexcept;

// Delta that, applied additively at weight 1 on `reference`, gives `pose`.
void makeAdditiveDelta(std::span<const Transform> pose, std::span<const Transform> reference,
                       std::span<Transform> outDelta) noexcept;

}  // namespace marionette
