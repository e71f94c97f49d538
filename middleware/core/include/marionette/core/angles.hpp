// Angles in radians: one 2π for the whole library, and wrapping into [-π, π].
#pragma once
#include <cmath>

namespace marionette {

inline constexpr float kTwoPi = 6.28318530718f;

// The same direction as `radians`, in [-π, π] (IEEE remainder: exact, no loop).
[[nodiscard]] inline float wrapAngle(float radians) noexcept { return std::remainder(radians, kTwoPi); }

}  // namespace marionette
