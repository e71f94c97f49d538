// Hemisphere ray batches for the occlusion tests and benchmarks (the shape the shadowed
// transfer precompute sends: one vertex's rays at a time, one origin, random directions).
#pragma once
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <span>

#include "marionette/prt/ray_occlusion.hpp"

namespace marionette::prt::test {

// A unit direction uniform over the hemisphere around the unit vector n, from u1, u2 in [0, 1).
inline glm::vec3 hemisphereDirection(const glm::vec3& n, float u1, float u2) {
  // Orthonormal basis around n (Duff et al., "Building an Orthonormal Basis, Revisited").
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  const glm::vec3 t(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
  const glm::vec3 s(b, sign + n.y * n.y * a, -n.y);
  const float z = u1;  // uniform in solid angle: cos(theta) uniform
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const float phi = 2.0f * std::numbers::pi_v<float> * u2;
  return glm::normalize(r * std::cos(phi) * t + r * std::sin(phi) * s + z * n);
}

// Fills `rays` from origin + offset * n, uniform over n's hemisphere, t in [0, infinity).
inline void hemisphereRays(const glm::vec3& position, const glm::vec3& n, float offset, std::mt19937& rng,
                           std::span<OcclusionRay> rays) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const glm::vec3 origin = position + offset * n;
  for (OcclusionRay& r : rays) {
    const float u1 = u(rng), u2 = u(rng);
    r = {origin, 0.0f, hemisphereDirection(n, u1, u2), std::numeric_limits<float>::infinity()};
  }
}

}  // namespace marionette::prt::test
