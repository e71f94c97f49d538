// Real spherical harmonics with n bands (l = 0 .. n-1, n*n functions), +Y as the polar axis.
//
// Basis. Index i = l (l + 1) + m. With t = y = cos(theta), the azimuth psi = atan2(x, z) and
// the normalised associated Legendre functions Pbar_l^m (below):
//   Y_l0 = Pbar_l^0(t),  Y_lm = sqrt(2) Pbar_l^m(t) cos(m psi),  Y_l,-m = sqrt(2) Pbar_l^m(t) sin(m psi)
// for m > 0, with no Condon-Shortley phase. Bands 0..2 are the familiar polynomials
// (0.282095; 0.488603 x, y, z; 1.092548 xz, xy; 0.315392 (3y^2 - 1); 1.092548 yz;
// 0.546274 (z^2 - x^2)): the textbook z-up basis with (x, y, z) renamed (z, x, y), a cyclic
// permutation that keeps handedness, so that turning the environment about +Y (the renderer's
// up) only mixes the two functions of each (l, |m|) pair.
//
// Evaluation never divides by sin(theta): Pbar_l^m(t) = s^m Q_l^m(t) with s = sin(theta), and
// s^m cos(m psi), s^m sin(m psi) are the real and imaginary parts of (z + i x)^m, polynomials in
// the direction. So the poles are as accurate as anywhere else.
//
// Pbar_l^m is normalised so that 2 pi * int_{-1}^{1} Pbar_l^m Pbar_l'^m dt = delta_ll' (the
// zonal Y_l0 is orthonormal on the sphere). It comes from the three-term recurrence in l, in
// double, with the normalisation folded into the coefficients, so nothing like (l + m)!
// appears: accurate to machine precision well past l = 40 (tests/prt/spherical_harmonics_test).
#pragma once
#include <glm/vec3.hpp>

#include <array>
#include <span>
#include <vector>

namespace marionette::prt {

inline constexpr int kMinShBands = 1;
inline constexpr int kMaxShBands = 8;  // lighting and transfer: n = 2 .. 8 (1 is the DC term alone)
inline constexpr int kMaxShCoefficients = kMaxShBands * kMaxShBands;

using ShBasis = std::array<double, kMaxShCoefficients>;

[[nodiscard]] constexpr int shIndex(int l, int m) noexcept { return l * (l + 1) + m; }
[[nodiscard]] constexpr int shCount(int bands) noexcept { return bands * bands; }
[[nodiscard]] constexpr int shBandOf(int index) noexcept {
  int l = 0;
  while ((l + 1) * (l + 1) <= index) ++l;
  return l;
}

// Pbar_l^m(t) for one (l, m), 0 <= m <= l, |t| <= 1 (any l; the cost is O(l)).
[[nodiscard]] double normalizedLegendre(int l, int m, double t) noexcept;

// The n*n basis functions at a unit direction, in index order. `out` holds at least n*n
// values; n in [1, kMaxShBands]. No allocation; noexcept.
void shBasis(int bands, const glm::dvec3& direction, std::span<double> out) noexcept;
void shBasis(int bands, const glm::vec3& direction, std::span<float> out) noexcept;
// Adds the n*n basis functions at a unit direction into sum[0 .. n*n) (the transfer's inner
// loop, unrolled per band count). Bands outside [1, kMaxShBands] add nothing.
void addShBasis(int bands, const glm::vec3& direction, float* sum) noexcept;

// The clamped-cosine kernel max(0, cos theta) in band l, as the factor A_l of the
// convolution: A_l = sqrt(4 pi / (2l + 1)) * (its zonal coefficient). Exact for any l >= 0:
// pi, 2pi/3, pi/4, 0, -pi/24, 0, pi/64, ...; zero for every odd l > 1.
[[nodiscard]] double cosineLobeBand(int l) noexcept;

// Gauss-Legendre nodes and weights on [-1, 1] (Newton on P_n; exact for polynomials of
// degree <= 2n - 1). Used by the projection (per row of a map) and by the tests.
struct GaussLegendre {
  std::vector<double> nodes, weights;
};
[[nodiscard]] GaussLegendre gaussLegendre(int points);

// Windows against ringing: band l is multiplied by w_l. Every window blurs: the costs are
// measured in docs/accuracy.md ("SH windowing").
//   Hann:    w_l = (1 + cos(pi l / n)) / 2         (zero at the first band left out)
//   Lanczos: w_l = sinc(l / n)                     (sinc(x) = sin(pi x) / (pi x))
//   Sinc4:   w_l = sinc(l / h)^4 with the cutoff h chosen per map: the largest h (least blur)
//            for which the windowed irradiance is >= 0 in every channel over a dense set of
//            directions; h = infinity (no window) when the plain irradiance has no negative lobe.
enum class ShWindow { None, Hann, Lanczos, Sinc4 };
[[nodiscard]] const char* windowName(ShWindow window) noexcept;
// Per-band weights of a window with a given cutoff (Sinc4: h; the others ignore it).
[[nodiscard]] std::array<double, kMaxShBands> windowWeights(ShWindow window, int bands, double cutoff = 0.0) noexcept;

}  // namespace marionette::prt
