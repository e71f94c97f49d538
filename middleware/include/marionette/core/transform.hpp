// Joint-local transform as translation, rotation, scale (TRS) and the math the
// runtime needs on it. Uses GLM: vectors are glm::vec3, rotations unit glm::quat.
#pragma once
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

// Decompose an affine matrix into TRS (scale may be non-uniform; a negative
// determinant is folded into scale.x). Shear is dropped.
[[nodiscard]] Transform decompose(const glm::mat4& m) noexcept;

// Normalized lerp on the shortest arc (q and -q are the same rotation).
[[nodiscard]] glm::quat nlerpShortest(const glm::quat& a, const glm::quat& b, float t) noexcept;
// Spherical lerp on the shortest arc, stable for nearly equal inputs.
[[nodiscard]] glm::quat slerpShortest(const glm::quat& a, const glm::quat& b, float t) noexcept;
// Unit quaternion, or identity when q is zero or not finite.
[[nodiscard]] glm::quat safeNormalize(const glm::quat& q) noexcept;

}  // namespace marionette
