#include "marionette/prt/sh_lighting.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <thread>

#include "marionette/prt/sphere_sampling.hpp"

namespace marionette::prt {

namespace {
constexpr double kPi = std::numbers::pi;
constexpr double kSqrt2 = std::numbers::sqrt2;
constexpr int kRowNodes = 8;  // Gauss-Legendre points per row (in theta)

int clampBands(int bands) noexcept { return std::clamp(bands, kMinShBands, kMaxShBands); }

// Column integrals over the map's azimuth phi = 2 pi (u - 0.5) of cos(m psi) and sin(m psi),
// psi = atan2(x, z) = pi - phi, so cos(m psi) = (-1)^m cos(m phi), sin(m psi) = -(-1)^m sin(m phi).
struct ColumnFactors {
  std::array<double, kMaxShBands> cosine{}, sine{};  // [m]; cosine[0] = the column's width in phi
};
ColumnFactors columnFactors(const EnvironmentMap& map, int column, int bands) noexcept {
  ColumnFactors f;
  const double p0 = 2.0 * kPi * (static_cast<double>(column) / map.width() - 0.5);
  const double p1 = 2.0 * kPi * (static_cast<double>(column + 1) / map.width() - 0.5);
  f.cosine[0] = p1 - p0;
  for (int m = 1; m < bands; ++m) {
    const double sign = m % 2 == 0 ? 1.0 : -1.0;
    f.cosine[m] = sign * (std::sin(m * p1) - std::sin(m * p0)) / m;
    f.sine[m] = -sign * (std::cos(m * p0) - std::cos(m * p1)) / m;
  }
  return f;
}

// Row integrals int Pbar_l^m(cos theta) sin(theta) dtheta over the row's theta range, [l][m].
using RowFactors = std::array<std::array<double, kMaxShBands>, kMaxShBands>;
RowFactors rowFactors(const EnvironmentMap& map, int row, int bands, const GaussLegendre& gl) noexcept {
  RowFactors f{};
  const double th0 = kPi * row / map.height(), th1 = kPi * (row + 1) / map.height();
  const double mid = 0.5 * (th0 + th1), half = 0.5 * (th1 - th0);
  for (std::size_t k = 0; k < gl.nodes.size(); ++k) {
    const double theta = mid + half * gl.nodes[k];
    const double w = half * gl.weights[k] * std::sin(theta), t = std::cos(theta);
    for (int l = 0; l < bands; ++l)
      for (int m = 0; m <= l; ++m) f[l][m] += w * normalizedLegendre(l, m, t);
  }
  return f;
}

// Adds row sums A_m = sum_col L C_m, B_m = sum_col L S_m times the row factors into `out`.
void accumulateRow(const RowFactors& rf, const std::array<glm::dvec3, kMaxShBands>& a,
                   const std::array<glm::dvec3, kMaxShBands>& b, int bands, ShBasis* basisOut,
                   ShCoefficients* out) noexcept {
  for (int l = 0; l < bands; ++l) {
    if (out) out->c[shIndex(l, 0)] += rf[l][0] * a[0];
    if (basisOut) (*basisOut)[shIndex(l, 0)] = rf[l][0] * a[0].x;
    for (int m = 1; m <= l; ++m) {
      if (out) {
        out->c[shIndex(l, m)] += kSqrt2 * rf[l][m] * a[m];
        out->c[shIndex(l, -m)] += kSqrt2 * rf[l][m] * b[m];
      }
      if (basisOut) {
        (*basisOut)[shIndex(l, m)] = kSqrt2 * rf[l][m] * a[m].x;
        (*basisOut)[shIndex(l, -m)] = kSqrt2 * rf[l][m] * b[m].x;
      }
    }
  }
}
}  // namespace

glm::dvec3 ShCoefficients::evaluate(const glm::dvec3& direction) const noexcept {
  ShBasis y{};
  shBasis(bands, direction, y);
  glm::dvec3 sum(0.0);
  for (int i = 0; i < count(); ++i) sum += c[i] * y[i];
  return sum;
}

ShBasis pixelBasisIntegrals(const EnvironmentMap& map, int column, int row, int bands) {
  bands = clampBands(bands);
  const GaussLegendre gl = gaussLegendre(kRowNodes);
  const ColumnFactors cf = columnFactors(map, column, bands);
  std::array<glm::dvec3, kMaxShBands> a{}, b{};
  for (int m = 0; m < bands; ++m) a[m] = glm::dvec3(cf.cosine[m]), b[m] = glm::dvec3(cf.sine[m]);
  ShBasis out{};
  accumulateRow(rowFactors(map, row, bands, gl), a, b, bands, &out, nullptr);
  return out;
}

ShCoefficients projectRadiance(const EnvironmentMap& map, int bands) {
  ShCoefficients result;
  result.bands = bands = clampBands(bands);
  const int w = map.width(), h = map.height();
  if (w <= 0 || h <= 0) return result;
  const GaussLegendre gl = gaussLegendre(kRowNodes);
  // Column factors once, as [column][m] arrays.
  std::vector<ColumnFactors> columns(static_cast<std::size_t>(w));
  for (int col = 0; col < w; ++col) columns[static_cast<std::size_t>(col)] = columnFactors(map, col, bands);
  const float* px = map.pixels().data();
  for (int row = 0; row < h; ++row) {
    std::array<glm::dvec3, kMaxShBands> a{}, b{};
    const float* p = px + static_cast<std::size_t>(row) * w * 3;
    for (int col = 0; col < w; ++col, p += 3) {
      const glm::dvec3 radiance(p[0], p[1], p[2]);
      const ColumnFactors& cf = columns[static_cast<std::size_t>(col)];
      a[0] += radiance * cf.cosine[0];
      for (int m = 1; m < bands; ++m) a[m] += radiance * cf.cosine[m], b[m] += radiance * cf.sine[m];
    }
    accumulateRow(rowFactors(map, row, bands, gl), a, b, bands, nullptr, &result);
  }
  return result;
}

ShCoefficients irradianceCoefficients(const ShCoefficients& radiance) noexcept {
  ShCoefficients out;
  out.bands = radiance.bands;
  for (int i = 0; i < radiance.count(); ++i) out.c[i] = radiance.c[i] * cosineLobeBand(shBandOf(i));
  return out;
}

glm::dvec3 irradiance(const ShCoefficients& radiance, const glm::dvec3& normal) noexcept {
  return irradianceCoefficients(radiance).evaluate(normal);
}

ShCoefficients applyWindow(const ShCoefficients& in, const std::array<double, kMaxShBands>& weights) noexcept {
  ShCoefficients out = in;
  for (int i = 0; i < in.count(); ++i) out.c[i] = in.c[i] * weights[static_cast<std::size_t>(shBandOf(i))];
  return out;
}

ShCoefficients windowRadiance(const ShCoefficients& radiance, ShWindow window, double* cutoff) {
  if (cutoff) *cutoff = std::numeric_limits<double>::infinity();
  if (window != ShWindow::Sinc4) return applyWindow(radiance, windowWeights(window, radiance.bands));
  // Sinc4: the least blur that leaves no negative irradiance over a dense set of directions.
  static const std::vector<glm::dvec3> directions = fibonacciSphere(2562);
  auto nonNegative = [&](double h) {
    const ShCoefficients e = irradianceCoefficients(applyWindow(radiance, windowWeights(ShWindow::Sinc4, radiance.bands, h)));
    for (const auto& d : directions) {
      const glm::dvec3 v = e.evaluate(d);
      if (std::min({v.x, v.y, v.z}) < 0.0) return false;
    }
    return true;
  };
  double lo = 0.5, hi = 1000.0 * radiance.bands;  // lo: DC only (non-negative for a non-negative map)
  if (nonNegative(std::numeric_limits<double>::infinity())) return radiance;
  if (!nonNegative(lo)) return applyWindow(radiance, windowWeights(ShWindow::Sinc4, radiance.bands, lo));
  for (int i = 0; i < 40; ++i) {  // bisection in log h: largest h that is still non-negative
    const double mid = std::sqrt(lo * hi);
    (nonNegative(mid) ? lo : hi) = mid;
  }
  if (cutoff) *cutoff = lo;
  return applyWindow(radiance, windowWeights(ShWindow::Sinc4, radiance.bands, lo));
}

ShCoefficients rotateAboutY(const ShCoefficients& in, double radians) noexcept {
  ShCoefficients out = in;
  for (int m = 1; m < in.bands; ++m) {
    const double cm = std::cos(m * radians), sm = std::sin(m * radians);
    for (int l = m; l < in.bands; ++l) {
      const glm::dvec3 cc = in.c[shIndex(l, m)], ss = in.c[shIndex(l, -m)];
      out.c[shIndex(l, m)] = cc * cm - ss * sm;
      out.c[shIndex(l, -m)] = ss * cm + cc * sm;
    }
  }
  return out;
}

std::vector<glm::dvec3> bruteForceIrradiance(const EnvironmentMap& map, const std::vector<glm::dvec3>& normals,
                                             unsigned threads) {
  const int w = map.width(), h = map.height();
  const std::size_t n = static_cast<std::size_t>(std::max(w, 0)) * std::max(h, 0);
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

IrradianceError irradianceError(const std::vector<glm::dvec3>& approx, const std::vector<glm::dvec3>& reference) {
  IrradianceError s;
  const std::size_t n = std::min(approx.size(), reference.size());
  if (n == 0) return s;
  glm::dvec3 mean(0.0);
  for (std::size_t i = 0; i < n; ++i) mean += reference[i] / static_cast<double>(n);
  const double floorValue = std::max(1e-9 * std::max({mean.x, mean.y, mean.z}), std::numeric_limits<double>::min());
  for (std::size_t i = 0; i < n; ++i) {
    double e = 0.0;
    for (int c = 0; c < 3; ++c)
      e = std::max(e, std::abs(approx[i][c] - reference[i][c]) / std::max(reference[i][c], floorValue));
    s.mean += e;
    s.max = std::max(s.max, e);
  }
  s.mean /= static_cast<double>(n);
  return s;
}

IrradianceError lightingError(const EnvironmentMap& map, int bands, ShWindow window, int normalCount) {
  const std::vector<glm::dvec3> normals = fibonacciSphere(normalCount);
  const ShCoefficients e = irradianceCoefficients(windowRadiance(projectRadiance(map, bands), window));
  std::vector<glm::dvec3> approx;
  approx.reserve(normals.size());
  for (const auto& n : normals) approx.push_back(e.evaluate(n));
  return irradianceError(approx, bruteForceIrradiance(map, normals));
}

}  // namespace marionette::prt
