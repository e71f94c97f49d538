// Private to the retargeter: mirror handling that both binding
// (retarget_binding.cpp) and the per-frame apply (retargeter.cpp) need.
#pragma once
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace marionette::retarget::detail {

// Under a mirrored parent (sign pattern s, det d = sx*sy*sz), a local rotation R
// appears in model space as diag(s) R diag(s)^-1: the quaternion's vector part
// times d*s. The map is its own inverse.
inline glm::quat flipped(const glm::quat& q, const glm::vec3& f) noexcept {
  return glm::quat(q.w, q.x * f.x, q.y * f.y, q.z * f.z);
}
inline glm::vec3 flipOf(const glm::vec3& signs) noexcept { return signs * (signs.x * signs.y * signs.z); }
inline glm::vec3 signsOf(const glm::vec3& v) noexcept {
  return {v.x < 0.0f ? -1.0f : 1.0f, v.y < 0.0f ? -1.0f : 1.0f, v.z < 0.0f ? -1.0f : 1.0f};
}

}  // namespace marionette::retarget::detail
