#include "marionette/prt/spherical_harmonics.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <type_traits>

namespace marionette::prt {

namespace {
constexpr double kPi = std::numbers::pi;

// Pbar_m^m / s^m: 1 / sqrt(4 pi) * prod_{k=1}^{m} sqrt((2k + 1) / (2k)).
double sectoralFactor(int m) noexcept {
  double q = 0.5 / std::sqrt(kPi);
  for (int k = 1; k <= m; ++k) q *= std::sqrt((2.0 * k + 1.0) / (2.0 * k));
  return q;
}
// The recurrence Pbar_l^m = a (t Pbar_{l-1}^m - b Pbar_{l-2}^m), l >= m + 2.
double recurrenceA(int l, int m) noexcept {
  return std::sqrt((4.0 * l * l - 1.0) / (static_cast<double>(l) * l - static_cast<double>(m) * m));
}
double recurrenceB(int l, int m) noexcept {
  const double lm1 = l - 1.0;
  return std::sqrt((lm1 * lm1 - static_cast<double>(m) * m) / (4.0 * lm1 * lm1 - 1.0));
}

// The coefficients for bands <= kMaxShBands, computed once (the basis is evaluated per ray).
struct BasisTables {
  std::array<double, kMaxShBands> sectoral{};                            // Q_m^m
  std::array<std::array<double, kMaxShBands>, kMaxShBands> a{}, b{};     // [l][m]
  BasisTables() noexcept {
    for (int m = 0; m < kMaxShBands; ++m) {
      sectoral[m] = sectoralFactor(m);
      for (int l = m + 1; l < kMaxShBands; ++l) {
        a[l][m] = l == m + 1 ? std::sqrt(2.0 * m + 3.0) : recurrenceA(l, m);
        b[l][m] = l == m + 1 ? 0.0 : recurrenceB(l, m);
      }
    }
  }
};
// A function-local static (not a namespace-scope one): safe to use from other static
// initialisers; the guard is one well-predicted branch.
const BasisTables& tables() noexcept {
  static const BasisTables t;
  return t;
}

// Out(index, value) receives every basis function; `Bands` may be a compile-time constant
// (the transfer's inner loop: fully unrolled) or a run-time int.
template <class T, class BandsT, class Out>
inline void basis(BandsT bands, T x, T y, T z, Out&& out) noexcept {
  const BasisTables& tb = tables();
  const T sqrt2 = static_cast<T>(std::numbers::sqrt2);
  T cm = 1, sm = 0;  // s^m cos(m psi), s^m sin(m psi): (z + i x)^m
  for (int m = 0; m < bands; ++m) {
    T q2 = 0, q1 = static_cast<T>(tb.sectoral[m]);  // Q_{l-2}, Q_{l-1}, starting at l = m
    for (int l = m; l < bands; ++l) {
      T q = q1;
      if (l > m) {
        q = static_cast<T>(tb.a[l][m]) * (y * q1 - static_cast<T>(tb.b[l][m]) * q2);
        q2 = q1;
        q1 = q;
      }
      if (m == 0) {
        out(shIndex(l, 0), q);
      } else {
        out(shIndex(l, m), sqrt2 * q * cm);
        out(shIndex(l, -m), sqrt2 * q * sm);
      }
    }
    const T c = cm * z - sm * x;
    sm = sm * z + cm * x;
    cm = c;
  }
}
}  // namespace

double normalizedLegendre(int l, int m, double t) noexcept {
  if (m < 0 || l < m) return 0.0;
  t = std::clamp(t, -1.0, 1.0);
  const double s = std::sqrt(std::max(0.0, (1.0 - t) * (1.0 + t)));
  double pmm = 0.5 / std::sqrt(kPi);
  for (int k = 1; k <= m; ++k) pmm *= std::sqrt((2.0 * k + 1.0) / (2.0 * k)) * s;
  if (l == m) return pmm;
  double p2 = pmm, p1 = std::sqrt(2.0 * m + 3.0) * t * pmm;
  for (int k = m + 2; k <= l; ++k) {
    const double p = recurrenceA(k, m) * (t * p1 - recurrenceB(k, m) * p2);
    p2 = p1;
    p1 = p;
  }
  return p1;
}

void shBasis(int bands, const glm::dvec3& d, std::span<double> out) noexcept {
  bands = std::clamp(bands, kMinShBands, kMaxShBands);
  if (static_cast<int>(out.size()) < shCount(bands)) return;
  basis<double>(bands, d.x, d.y, d.z, [p = out.data()](int i, double v) { p[i] = v; });
}
void shBasis(int bands, const glm::vec3& d, std::span<float> out) noexcept {
  bands = std::clamp(bands, kMinShBands, kMaxShBands);
  if (static_cast<int>(out.size()) < shCount(bands)) return;
  basis<float>(bands, d.x, d.y, d.z, [p = out.data()](int i, float v) { p[i] = v; });
}

namespace {
template <int Bands>
void addBasis(const glm::vec3& d, float* sum) noexcept {
  basis<float>(std::integral_constant<int, Bands>{}, d.x, d.y, d.z, [sum](int i, float v) { sum[i] += v; });
}
}  // namespace

void addShBasis(int bands, const glm::vec3& d, float* sum) noexcept {
  switch (bands) {
    case 1: return addBasis<1>(d, sum);
    case 2: return addBasis<2>(d, sum);
    case 3: return addBasis<3>(d, sum);
    case 4: return addBasis<4>(d, sum);
    case 5: return addBasis<5>(d, sum);
    case 6: return addBasis<6>(d, sum);
    case 7: return addBasis<7>(d, sum);
    case 8: return addBasis<8>(d, sum);
    default: return;
  }
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

GaussLegendre gaussLegendre(int points) {
  GaussLegendre g;
  if (points < 1) return g;
  g.nodes.resize(static_cast<std::size_t>(points));
  g.weights.resize(static_cast<std::size_t>(points));
  for (int i = 0; i < points; ++i) {
    double x = std::cos(kPi * (i + 0.75) / (points + 0.5));  // Tricomi's first guess
    double dp = 1.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1.0, p1 = x;  // P_0, P_1, then up to P_n by Bonnet's recurrence
      for (int k = 2; k <= points; ++k) {
        const double p = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p;
      }
      dp = points * (x * p1 - p0) / (x * x - 1.0);
      const double dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    g.nodes[static_cast<std::size_t>(i)] = x;
    g.weights[static_cast<std::size_t>(i)] = 2.0 / ((1.0 - x * x) * dp * dp);
  }
  return g;
}

const char* windowName(ShWindow window) noexcept {
  switch (window) {
    case ShWindow::None: return "none";
    case ShWindow::Hann: return "hann";
    case ShWindow::Lanczos: return "lanczos";
    case ShWindow::Sinc4: return "sinc4";
  }
  return "none";
}

std::array<double, kMaxShBands> windowWeights(ShWindow window, int bands, double cutoff) noexcept {
  std::array<double, kMaxShBands> w{};
  w.fill(1.0);
  const double n = std::max(bands, 1);
  auto sinc = [](double x) { return x == 0.0 ? 1.0 : std::sin(kPi * x) / (kPi * x); };
  for (int l = 0; l < kMaxShBands; ++l) {
    switch (window) {
      case ShWindow::None: break;
      case ShWindow::Hann: w[l] = 0.5 * (1.0 + std::cos(kPi * l / n)); break;
      case ShWindow::Lanczos: w[l] = sinc(l / n); break;
      case ShWindow::Sinc4:
        w[l] = std::isfinite(cutoff) && cutoff > 0.0 ? std::pow(sinc(std::min(l / cutoff, 1.0)), 4.0) : 1.0;
        break;
    }
  }
  return w;
}

}  // namespace marionette::prt
