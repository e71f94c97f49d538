// Joint-local transform as translation, rotation, scale (TRS) and the math the
// runtime needs on it. Uses GLM: vectors are glm::vec3, rotations unit glm::quat.
#pragma once
#include <cmath>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

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

// Spherical lerp on the shortest arc, stable for nearly equal inputs.
[[nodiscard]] glm::quat slerpShortest(const glm::quat& a, const glm::quat& b, float t) noexcept;

}  // namespace marionette
