// Shared by the AR core tests and marionette_sh_lighting_error.
#pragma once
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace marionette::prt::test {

// n unit vectors spread evenly over the sphere (Fibonacci lattice).
inline std::vector<glm::dvec3> fibonacciSphere(int n) {
  std::vector<glm::dvec3> out;
  out.reserve(n);
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double y = 1.0 - (i + 0.5) * 2.0 / n;
    const double r = std::sqrt(std::max(0.0, 1.0 - y * y));
    const double a = golden * i;
    out.push_back({r * std::cos(a), y, r * std::sin(a)});
  }
  return out;
}

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
