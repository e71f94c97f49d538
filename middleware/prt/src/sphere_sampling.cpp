#include "marionette/prt/sphere_sampling.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace marionette::prt {

std::vector<glm::dvec3> fibonacciSphere(int n) {
  std::vector<glm::dvec3> out;
  out.reserve(static_cast<std::size_t>(std::max(n, 0)));
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double y = 1.0 - (i + 0.5) * 2.0 / n;
    const double r = std::sqrt(std::max(0.0, 1.0 - y * y));
    const double a = golden * i;
    out.push_back({r * std::cos(a), y, r * std::sin(a)});
  }
  return out;
}

}  // namespace marionette::prt
