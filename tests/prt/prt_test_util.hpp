// Shared by the AR core tests and marionette_sh_lighting_error.
#pragma once
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "marionette/prt/sphere_sampling.hpp"

namespace marionette::prt::test {

using marionette::prt::fibonacciSphere;

// Relative error of one normal: the largest over R, G, B of |approx - reference| / reference.
inline double relativeError(const glm::dvec3& approx, const glm::dvec3& reference) {
  double e = 0.0;
  for (int c = 0; c < 3; ++c) e = std::max(e, std::abs(approx[c] - reference[c]) / reference[c]);
  return e;
}

struct ErrorStats {
  double mean = 0.0, max = 0.0;
};
inline ErrorStats errorStats(const std::vector<glm::dvec3>& approx, const std::vector<glm::dvec3>& reference) {
  ErrorStats s;
  for (std::size_t i = 0; i < approx.size(); ++i) {
    const double e = relativeError(approx[i], reference[i]);
    s.mean += e;
    s.max = std::max(s.max, e);
  }
  if (!approx.empty()) s.mean /= static_cast<double>(approx.size());
  return s;
}

}  // namespace marionette::prt::test
