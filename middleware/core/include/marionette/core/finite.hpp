// isFinite: true when no component is NaN or infinite. One definition for the
// scalars, GLM vectors, quaternions and matrices that every reader and solver
// checks before using a value (bad input never reaches a frame as NaN).
#pragma once
#include <cmath>
#include <concepts>
#include <ranges>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>

namespace marionette {

template <std::floating_point T>
[[nodiscard]] constexpr bool isFinite(T v) noexcept {
  return std::isfinite(v);
}
template <glm::length_t N, typename T, glm::qualifier Q>
[[nodiscard]] constexpr bool isFinite(const glm::vec<N, T, Q>& v) noexcept {
  for (glm::length_t i = 0; i < N; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}
template <typename T, glm::qualifier Q>
[[nodiscard]] constexpr bool isFinite(const glm::qua<T, Q>& q) noexcept {
  return std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z) && std::isfinite(q.w);
}
template <glm::length_t C, glm::length_t R, typename T, glm::qualifier Q>
[[nodiscard]] constexpr bool isFinite(const glm::mat<C, R, T, Q>& m) noexcept {
  for (glm::length_t c = 0; c < C; ++c)
    if (!isFinite(m[c])) return false;
  return true;
}
// Every element of a range (of any of the above).
template <std::ranges::input_range Range>
[[nodiscard]] constexpr bool allFinite(const Range& values) noexcept {
  for (const auto& v : values)
    if (!isFinite(v)) return false;
  return true;
}

}  // namespace marionette
