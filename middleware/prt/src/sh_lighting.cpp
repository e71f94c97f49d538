#include "marionette/prt/sh_lighting.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <thread>

namespace marionette::prt {

namespace {
constexpr double kPi = std::numbers::pi;
// Normalisation constants of the real SH basis, bands 0..2.
const double kY0 = 0.5 * std::sqrt(1.0 / kPi);         // 0.282095
const double kY1 = std::sqrt(3.0 / (4.0 * kPi));       // 0.488603
const double kY2 = 0.5 * std::sqrt(15.0 / kPi);        // 1.092548 (m = +-1, -2)
const double kY20 = 0.25 * std::sqrt(5.0 / kPi);       // 0.315392
const double kY22 = 0.25 * std::sqrt(15.0 / kPi);      // 0.546274

constexpr int bandOf(int i) noexcept { return i == 0 ? 0 : (i < 4 ? 1 : 2); }
}  // namespace

ShBasis shBasis(const glm::dvec3& d) noexcept {
  const double x = d.x, y = d.y, z = d.z;
  return {kY0,
          kY1 * x, kY1 * y, kY1 * z,
          kY2 * x * z, kY2 * x * y, kY20 * (3.0 * y * y - 1.0), kY2 * y * z, kY22 * (z * z - x * x)};
}

double cosineLobeBand(int l) noexcept {
  if (l < 0) return 0.0;
  if (l == 0) return kPi;
  if (l == 1) return 2.0 * kPi / 3.0;
  if (l % 2 == 1) return 0.0;
  // Even l >= 2: 2 pi (-1)^(l/2 - 1) / ((l + 2)(l - 1)) * l! / (2^l ((l/2)!)^2).
  // l! / (2^l ((l/2)!)^2) = prod_{k=1}^{l/2} (2k - 1) / (2k), evaluated without overflow.
  double ratio = 1.0;
  for (int k = 1; k <= l / 2; ++k) ratio *= (2.0 * k - 1.0) / (2.0 * k);
  const double sign = (l / 2 - 1) % 2 == 0 ? 1.0 : -1.0;
  return 2.0 * kPi * sign / ((l + 2.0) * (l - 1.0)) * ratio;
}

glm::dvec3 ShCoefficients::evaluate(const glm::dvec3& direction) const noexcept {
  const ShBasis y = shBasis(direction);
  glm::dvec3 sum(0.0);
  for (int i = 0; i < kShCount; ++i) sum += c[i] * y[i];
  return sum;
}

namespace {
// Integrals over t = cos(theta) in [t1, t0] of a pixel row: dt, s, t, s^2, s t, 3t^2 - 1.
struct RowFactors {
  double dt, S, T, Q, P, Z;
};
RowFactors rowFactors(const EnvironmentMap& map, int row) noexcept {
  const double t0 = std::cos(kPi * row / map.height()), t1 = std::cos(kPi * (row + 1) / map.height());
  auto F = [&](auto f) { return f(t0) - f(t1); };
  return {t0 - t1,
          F([](double t) { return 0.5 * (t * std::sqrt(std::max(0.0, 1.0 - t * t)) + std::asin(t)); }),
          F([](double t) { return 0.5 * t * t; }),
          F([](double t) { return t - t * t * t / 3.0; }),
          F([](double t) { return -std::pow(std::max(0.0, 1.0 - t * t), 1.5) / 3.0; }),
          F([](double t) { return t * t * t - t; })};
}
// Integrals over psi = 2 pi (u - 0.5) in [p0, p1] of a pixel column: 1, sin, cos, sin cos, cos 2psi.
struct ColumnFactors {
  double dp, Is, Ic, Isc, Ic2;
};
ColumnFactors columnFactors(const EnvironmentMap& map, int column) noexcept {
  const double p0 = 2.0 * kPi * (static_cast<double>(column) / map.width() - 0.5);
  const double p1 = 2.0 * kPi * (static_cast<double>(column + 1) / map.width() - 0.5);
  return {p1 - p0, std::cos(p0) - std::cos(p1), std::sin(p1) - std::sin(p0),
          0.5 * (std::sin(p1) * std::sin(p1) - std::sin(p0) * std::sin(p0)),
          0.5 * (std::sin(2.0 * p1) - std::sin(2.0 * p0))};
}
// Pixel: x = s sin(psi), y = t, z = -s cos(psi) with s = sqrt(1 - t^2), dw = dt dpsi. Every
// basis function is a product of a function of t and one of psi.
ShBasis basisIntegrals(const RowFactors& r, const ColumnFactors& c) noexcept {
  return {kY0 * r.dt * c.dp,
          kY1 * r.S * c.Is, kY1 * r.T * c.dp, -kY1 * r.S * c.Ic,
          -kY2 * r.Q * c.Isc, kY2 * r.P * c.Is, kY20 * r.Z * c.dp, -kY2 * r.P * c.Ic, kY22 * r.Q * c.Ic2};
}
}  // namespace

ShBasis pixelBasisIntegrals(const EnvironmentMap& map, int column, int row) noexcept {
  return basisIntegrals(rowFactors(map, row), columnFactors(map, column));
}

ShCoefficients projectRadiance(const EnvironmentMap& map) {
  ShCoefficients result;
  const int w = map.width(), h = map.height();
  const float* px = map.pixels().data();
  std::vector<ColumnFactors> columns(static_cast<std::size_t>(std::max(w, 0)));
  for (int col = 0; col < w; ++col) columns[col] = columnFactors(map, col);
  for (int row = 0; row < h; ++row) {
    const RowFactors rf = rowFactors(map, row);
    std::array<glm::dvec3, kShCount> rowSum{};
    for (int col = 0; col < w; ++col) {
      const float* p = px + (static_cast<std::size_t>(row) * w + col) * 3;
      const glm::dvec3 radiance(p[0], p[1], p[2]);
      const ShBasis y = basisIntegrals(rf, columns[col]);
      for (int i = 0; i < kShCount; ++i) rowSum[i] += radiance * y[i];
    }
    for (int i = 0; i < kShCount; ++i) result.c[i] += rowSum[i];
  }
  return result;
}

ShCoefficients irradianceCoefficients(const ShCoefficients& radiance) noexcept {
  ShCoefficients out;
  for (int i = 0; i < kShCount; ++i) out.c[i] = radiance.c[i] * cosineLobeBand(bandOf(i));
  return out;
}

glm::dvec3 irradiance(const ShCoefficients& radiance, const glm::dvec3& normal) noexcept {
  return irradianceCoefficients(radiance).evaluate(normal);
}

ShCoefficients rotateAboutY(const ShCoefficients& in, double radians) noexcept {
  ShCoefficients out = in;
  // (cos index, sin index, m) pairs: band 1 (3, 1, 1); band 2 (7, 5, 1) and (8, 4, 2).
  constexpr int pairs[3][3] = {{3, 1, 1}, {7, 5, 1}, {8, 4, 2}};
  for (const auto& p : pairs) {
    const double cm = std::cos(p[2] * radians), sm = std::sin(p[2] * radians);
    const glm::dvec3 cc = in.c[p[0]], ss = in.c[p[1]];
    out.c[p[0]] = cc * cm - ss * sm;
    out.c[p[1]] = ss * cm + cc * sm;
  }
  return out;
}

std::vector<glm::dvec3> bruteForceIrradiance(const EnvironmentMap& map, const std::vector<glm::dvec3>& normals,
                                             unsigned threads) {
  const int w = map.width(), h = map.height();
  const std::size_t n = static_cast<std::size_t>(w) * h;
  // Structure of arrays: pixel directions and radiance times solid angle.
  std::vector<double> dx(n), dy(n), dz(n), lr(n), lg(n), lb(n);
  for (int row = 0; row < h; ++row) {
    const double dw = map.texelSolidAngle(row);
    for (int col = 0; col < w; ++col) {
      const std::size_t k = static_cast<std::size_t>(row) * w + col;
      const glm::dvec3 d = map.texelDirection(col, row);
      const glm::vec3 l = map.texel(col, row);
      dx[k] = d.x, dy[k] = d.y, dz[k] = d.z;
      lr[k] = l.r * dw, lg[k] = l.g * dw, lb[k] = l.b * dw;
    }
  }
  std::vector<glm::dvec3> result(normals.size());
  auto work = [&](std::size_t begin, std::size_t end) {
    for (std::size_t j = begin; j < end; ++j) {
      const glm::dvec3 nn = normals[j];
      double r = 0.0, g = 0.0, b = 0.0;
      for (std::size_t k = 0; k < n; ++k) {
        const double c = std::max(0.0, nn.x * dx[k] + nn.y * dy[k] + nn.z * dz[k]);
        r += c * lr[k], g += c * lg[k], b += c * lb[k];
      }
      result[j] = {r, g, b};
    }
  };
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  threads = static_cast<unsigned>(std::min<std::size_t>(threads, std::max<std::size_t>(normals.size(), 1)));
  std::vector<std::thread> pool;
  const std::size_t chunk = (normals.size() + threads - 1) / threads;
  for (unsigned t = 1; t < threads; ++t) {
    const std::size_t begin = std::min(normals.size(), t * chunk), end = std::min(normals.size(), begin + chunk);
    pool.emplace_back(work, begin, end);
  }
  work(0, std::min(normals.size(), chunk));
  for (auto& th : pool) th.join();
  return result;
}

}  // namespace marionette::prt
