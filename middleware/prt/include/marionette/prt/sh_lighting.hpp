// Diffuse environment lighting in n spherical-harmonic bands (basis and conventions:
// spherical_harmonics.hpp). n = 3 (9 coefficients) is Ramamoorthi and Hanrahan 2001, "An
// Efficient Representation for Irradiance Environment Maps"; more bands follow the map's
// small bright sources better (the error against n is in docs/accuracy.md).
//
// Irradiance. E(n) = sum_l A_l sum_m L_lm Y_lm(n) with the clamped-cosine kernel's bands A_l
// (cosineLobeBand). irradianceCoefficients() folds A_l in, so that a shader evaluates
// E(n) = sum_i c_i Y_i(n). No exposure here: scaling by an exposure is the renderer's job.
#pragma once
#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <vector>

#include "marionette/prt/environment_map.hpp"
#include "marionette/prt/spherical_harmonics.hpp"

namespace marionette::prt {

inline constexpr int kDefaultLightingBands = 3;  // see docs/accuracy.md "Environment lighting"

// RGB coefficients of a function on the sphere (radiance or irradiance), bands 1..8, in a
// fixed-size array so that copies and rotations allocate nothing. Coefficients past
// bands * bands are zero.
struct ShCoefficients {
  int bands = kDefaultLightingBands;
  std::array<glm::dvec3, kMaxShCoefficients> c{};

  [[nodiscard]] int count() const noexcept { return shCount(bands); }
  // sum_i c_i Y_i(direction): for irradiance coefficients, the irradiance.
  [[nodiscard]] glm::dvec3 evaluate(const glm::dvec3& direction) const noexcept;
};

// Projection L_lm = sum over pixels L_pixel * (integral of Y_lm over the pixel), in double:
// the projection of the map taken as constant over each pixel. The azimuthal part of the
// integral is exact (closed form per column); the polar part uses 8-point Gauss-Legendre in
// theta per row, exact to rounding for these smooth functions. Deterministic (no random
// sampling), O(pixels * (2n - 1)). A constant map projects to the DC term alone.
[[nodiscard]] ShCoefficients projectRadiance(const EnvironmentMap& map, int bands = kDefaultLightingBands);
// The integrals of the n*n basis functions over one pixel (the projection's weights).
[[nodiscard]] ShBasis pixelBasisIntegrals(const EnvironmentMap& map, int column, int row,
                                          int bands = kDefaultLightingBands);

// The "irradiance coefficients" c_i = A_l(i) L_i, ready for a shader: E(n) = sum c_i Y_i(n).
[[nodiscard]] ShCoefficients irradianceCoefficients(const ShCoefficients& radiance) noexcept;
// Irradiance at unit normal n from radiance coefficients: sum A_l L_lm Y_lm(n).
[[nodiscard]] glm::dvec3 irradiance(const ShCoefficients& radiance, const glm::dvec3& normal) noexcept;

// Band l multiplied by weights[l].
[[nodiscard]] ShCoefficients applyWindow(const ShCoefficients& coefficients,
                                         const std::array<double, kMaxShBands>& weights) noexcept;
// The window applied to radiance coefficients; for Sinc4 the cutoff is found from the map's
// own irradiance (spherical_harmonics.hpp) and returned in `cutoff` (infinity: no window needed).
[[nodiscard]] ShCoefficients windowRadiance(const ShCoefficients& radiance, ShWindow window, double* cutoff = nullptr);

// The coefficients of the environment turned by `radians` about +Y (right-handed: a positive
// angle turns +Z toward +X), L'(w) = L(R^-1 w), in closed form: every m = 0 stays; each
// (m, -m) pair turns by |m| * radians. Works on radiance or irradiance coefficients alike
// (the convolution commutes with rotation). For any other rotation: ShRotation.
[[nodiscard]] ShCoefficients rotateAboutY(const ShCoefficients& coefficients, double radians) noexcept;

// Reference irradiance by brute force: E(n) = sum over pixels L(w) max(0, n.w) dw, for each
// normal (unit). Threads: 0 = std::thread::hardware_concurrency(). O(normals * pixels).
[[nodiscard]] std::vector<glm::dvec3> bruteForceIrradiance(const EnvironmentMap& map,
                                                           const std::vector<glm::dvec3>& normals,
                                                           unsigned threads = 0);

// Relative irradiance error over a set of normals: per normal, the largest over R, G, B of
// |approx - reference| / reference; where a reference channel is below 1e-9 of the map's mean
// irradiance (a black map, a normal facing away from the only light) the error is taken
// against that floor instead, so it stays finite.
struct IrradianceError {
  double mean = 0.0, max = 0.0;
};
[[nodiscard]] IrradianceError irradianceError(const std::vector<glm::dvec3>& approx,
                                              const std::vector<glm::dvec3>& reference);
// `marionette prt lighting-error`: the n-band irradiance of `map` (with a window) against
// brute force over `normalCount` Fibonacci normals.
[[nodiscard]] IrradianceError lightingError(const EnvironmentMap& map, int bands, ShWindow window = ShWindow::None,
                                            int normalCount = 1000);

}  // namespace marionette::prt
