// Easing for blend weights and procedural shapes.
#pragma once
#include <algorithm>

namespace marionette {

// 3u^2 - 2u^3 on [0, 1], clamped: C1, no velocity jump where a blend begins or ends.
[[nodiscard]] inline double smoothstep(double u) noexcept {
  u = std::clamp(u, 0.0, 1.0);
  return u * u * (3.0 - 2.0 * u);
}

}  // namespace marionette
