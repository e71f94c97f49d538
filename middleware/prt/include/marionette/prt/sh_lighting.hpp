// Diffuse environment lighting with 9 real spherical-harmonic coefficients (bands 0..2)
// per colour channel (Ramamoorthi and Hanrahan 2001, "An Efficient Representation for
// Irradiance Environment Maps").
//
// Basis. The usual real SH basis written with +Y as the polar axis (the renderer's up), so
// that a rotation of the environment about +Y only mixes the two coefficients of each
// (band, |m|) pair. Index i = l (l + 1) + m; for a unit direction (x, y, z):
//   i=0 (l0,m 0)  0.282095                     i=4 (l2,m-2)  1.092548 x z
//   i=1 (l1,m-1)  0.488603 x                   i=5 (l2,m-1)  1.092548 x y
//   i=2 (l1,m 0)  0.488603 y                   i=6 (l2,m 0)  0.315392 (3 y^2 - 1)
//   i=3 (l1,m 1)  0.488603 z                   i=7 (l2,m 1)  1.092548 y z
//                                              i=8 (l2,m 2)  0.546274 (z^2 - x^2)
// (the textbook z-up basis with (x, y, z) renamed (z, x, y), a cyclic, handedness-keeping
// permutation). With phi = atan2(x, z), the m > 0 functions go as cos(m phi) and the m < 0
// ones as sin(|m| phi).
//
// Irradiance. E(n) = sum_l A_l sum_m L_lm Y_lm(n), A_0 = pi, A_1 = 2 pi / 3, A_2 = pi / 4
// (the clamped-cosine kernel's bands; its odd bands above 1 vanish, band 4 is -pi/24, which
// is what 9 coefficients leave out). irradianceCoefficients() folds A_l in, so a shader
// evaluates E(n) = sum_i c_i Y_i(n) with the 9 polynomials above (irradiance() in
// examples/ar/shaders/lighting.glsl, the one GLSL copy).
// No exposure here: scaling by an exposure is the renderer's job.
#pragma once
#include <glm/vec3.hpp>

#include <array>
#include <vector>

#include "marionette/prt/environment_map.hpp"

namespace marionette::prt {

inline constexpr int kShBands = 3;                       // l = 0, 1, 2
inline constexpr int kShCount = kShBands * kShBands;     // 9

using ShBasis = std::array<double, kShCount>;

// The 9 basis functions at a unit direction.
[[nodiscard]] ShBasis shBasis(const glm::dvec3& direction) noexcept;

// The clamped-cosine kernel max(0, cos theta) in band l, as the factor A_l of the
// convolution: A_l = sqrt(4 pi / (2l + 1)) * (its zonal coefficient). Exact for any l >= 0:
// pi, 2pi/3, pi/4, 0, -pi/24, 0, pi/64, ...; zero for every odd l > 1.
[[nodiscard]] double cosineLobeBand(int l) noexcept;

// Nine RGB coefficients (double: they are sums over the whole map).
struct ShCoefficients {
  std::array<glm::dvec3, kShCount> c{};

  // Radiance coefficients L_lm -> E(n) with the cosine kernel applied: evaluate directly.
  [[nodiscard]] glm::dvec3 evaluate(const glm::dvec3& direction) const noexcept;
};

// Projection L_lm = sum over pixels L_pixel * (integral of Y_lm over the pixel), accumulated
// in double: the exact projection of the map taken as constant over each pixel (for Y_00 the
// integral is Y_00 times the pixel's exact solid angle, EnvironmentMap::texelSolidAngle; for
// the others it is the closed form of a polynomial over a lat-long cell). Deterministic (no
// random sampling), O(pixels). A constant map projects to the DC term alone, to rounding.
[[nodiscard]] ShBasis pixelBasisIntegrals(const EnvironmentMap& map, int column, int row) noexcept;
[[nodiscard]] ShCoefficients projectRadiance(const EnvironmentMap& map);

// The "irradiance coefficients" c_i = A_l(i) L_i, ready for a shader: E(n) = sum c_i Y_i(n).
[[nodiscard]] ShCoefficients irradianceCoefficients(const ShCoefficients& radiance) noexcept;

// Irradiance at unit normal n from radiance coefficients: sum A_l L_lm Y_lm(n).
[[nodiscard]] glm::dvec3 irradiance(const ShCoefficients& radiance, const glm::dvec3& normal) noexcept;

// The coefficients of the environment turned by `radians` about +Y (right-handed: a positive
// angle turns +Z toward +X), L'(w) = L(R^-1 w), in closed form: band 0 and every m = 0 stay;
// each (m, -m) pair turns by |m| * radians. Works on radiance or irradiance coefficients
// alike (the convolution commutes with rotation). Equals re-projecting the rotated map.
[[nodiscard]] ShCoefficients rotateAboutY(const ShCoefficients& coefficients, double radians) noexcept;

// Reference irradiance by brute force: E(n) = sum over pixels L(w) max(0, n.w) dw, for each
// normal (unit). Threads: 0 = std::thread::hardware_concurrency(). O(normals * pixels).
[[nodiscard]] std::vector<glm::dvec3> bruteForceIrradiance(const EnvironmentMap& map,
                                                           const std::vector<glm::dvec3>& normals,
                                                           unsigned threads = 0);

}  // namespace marionette::prt
