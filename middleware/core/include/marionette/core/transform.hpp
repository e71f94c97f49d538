// Joint-local transform as translation, rotation, scale (TRS) and the math the
// runtime needs on it. Uses GLM: vectors are glm::vec3, rotations unit glm::quat.
#pragma once
#include <cmath>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "marionette/core/glm_abi.hpp"

namespace marionette {

struct Transform {
  glm::vec3 translation{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};  // w, x, y, z
  glm::vec3 scale{1.0f};

  [[nodiscard]] static Transform identity() noexcept { return {}; }
  [[nodiscard]] glm::mat4 matrix() const noexcept;  // T * R * S, column-major
};

// Inline: these run once per joint per frame.

// Unit quaternion, or identity when q is zero or not finite.
[[nodiscard]] inline glm::quat safeNormalize(const glm::quat& q) noexcept {
  const float len2 = q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
  // One test catches zero, NaN and infinity (NaN compares false).
  if (!(len2 > 1e-30f && len2 < 1e30f)) return glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
  const float inv = 1.0f / std::sqrt(len2);
  return glm::quat(q.w * inv, q.x * inv, q.y * inv, q.z * inv);
}

// Normalized lerp on the shortest arc (q and -q are the same rotation).
[[nodiscard]] inline glm::quat nlerpShortest(const glm::quat& a, const glm::quat& b, float t) noexcept {
  const float d = a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
  const float s = d < 0.0f ? -t : t;
  const float u = 1.0f - t;
  return safeNormalize(glm::quat(u * a.w + s * b.w, u * a.x + s * b.x, u * a.y + s * b.y, u * a.z + s * b.z));
}

inline glm::mat4 Transform::matrix() const noexcept {
  const float x = rotation.x, y = rotation.y, z = rotation.z, w = rotation.w;
  const float xx = x * x, yy = y * y, zz = z * z, xy = x * y, xz = x * z, yz = y * z, wx = w * x, wy = w * y,
              wz = w * z;
  glm::mat4 m;
  m[0] = glm::vec4((1.0f - 2.0f * (yy + zz)) * scale.x, 2.0f * (xy + wz) * scale.x, 2.0f * (xz - wy) * scale.x, 0.0f);
  m[1] = glm::vec4(2.0f * (xy - wz) * scale.y, (1.0f - 2.0f * (xx + zz)) * scale.y, 2.0f * (yz + wx) * scale.y, 0.0f);
  m[2] = glm::vec4(2.0f * (xz + wy) * scale.z, 2.0f * (yz - wx) * scale.z, (1.0f - 2.0f * (xx + yy)) * scale.z, 0.0f);
  m[3] = glm::vec4(translation, 1.0f);
  return m;
}

// Decompose an affine matrix into TRS (scale may be non-uniform; a negative
// determinant is folded into scale.x). Shear is dropped.
[[nodiscard]] Transform decompose(const glm::mat4& m) noexcept;

// Spherical lerp on the shortest arc, for unit a and b, stable for nearly equal inputs.
// For t in [0, 1] it uses no acos or sin (whose bits differ between C libraries):
// sin(u θ) / sin θ comes from a 5-term series in cos θ (below), on the arc or, past
// 90 degrees of rotation, on its half that holds t (the arc halved at its exact
// midpoint); weights within 1e-7 of the exact ones, the same bits on every x86-64
// (docs/accuracy.md). Outside [0, 1] (extrapolation, as additive layers over
// full weight ask) it takes the exact formula.
[[nodiscard]] glm::quat slerpShortest(const glm::quat& a, const glm::quat& b, float t) noexcept;

namespace slerp_series {
// sin(u θ) / sin θ = u (1 + c1 y (1 + c2 y (1 + ... (1 + c5 y)))), y = cos θ - 1,
// c_i = (u² - i²) / (i (2i + 1)) = u² kScale[i] - kOffset[i] (Eberly, "A fast and
// accurate algorithm for computing SLERP", 2011). The last term is scaled by 1.1468,
// fitted so that the truncated series' largest error over u in [0, 1] and
// cos θ in [cos 45°, 1] is 7.2e-8; below kHalveBelow the arc is halved first. slerpShortest and the 4-wide
// blendOver (animation/src/simd4.hpp) evaluate it in the same order.
inline constexpr int kTerms = 5;
inline constexpr float kHalveBelow = 0.70710678f;  // cos 45°
inline constexpr double kLastTermScale = 1.1468;
constexpr float scaleOf(int i) { return static_cast<float>((i == kTerms ? kLastTermScale : 1.0) / (i * (2.0 * i + 1.0))); }
constexpr float offsetOf(int i) { return static_cast<float>((i == kTerms ? kLastTermScale : 1.0) * i / (2.0 * i + 1.0)); }
inline constexpr float kScale[kTerms + 1] = {0.0f, scaleOf(1), scaleOf(2), scaleOf(3), scaleOf(4), scaleOf(5)};
inline constexpr float kOffset[kTerms + 1] = {0.0f, offsetOf(1), offsetOf(2), offsetOf(3), offsetOf(4), offsetOf(5)};
}  // namespace slerp_series

}  // namespace marionette
