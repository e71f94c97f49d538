// n-band spherical harmonics: the Legendre recurrence far past the bands used (l + m to 80),
// the basis at the poles, orthonormality, projection, windows and rotations; the stiff and
// extreme cases of docs/accuracy.md ("SH: stiff and extreme cases").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "marionette/prt/environment_map.hpp"
#include "marionette/prt/sh_lighting.hpp"
#include "marionette/prt/sh_rotation.hpp"
#include "marionette/prt/sphere_sampling.hpp"
#include "test_data.hpp"

using namespace marionette::prt;
namespace mt = marionette::test;

namespace {
constexpr double kPi = std::numbers::pi;

ShBasis basis(int bands, const glm::dvec3& d) {
  ShBasis y{};
  shBasis(bands, d, y);
  return y;
}

// A map whose pixels are a band-limited function sampled at their centres.
EnvironmentMap mapOf(int w, int h, const ShCoefficients& f) {
  EnvironmentMap shape(w, h, {});
  std::vector<float> px(static_cast<std::size_t>(w) * h * 3);
  for (int row = 0; row < h; ++row)
    for (int col = 0; col < w; ++col) {
      const glm::dvec3 v = f.evaluate(shape.texelDirection(col, row));
      float* p = &px[(static_cast<std::size_t>(row) * w + col) * 3];
      p[0] = static_cast<float>(v.x), p[1] = static_cast<float>(v.y), p[2] = static_cast<float>(v.z);
    }
  return EnvironmentMap(w, h, std::move(px));
}

ShCoefficients randomCoefficients(int bands, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  ShCoefficients f;
  f.bands = bands;
  for (int i = 0; i < shCount(bands); ++i) f.c[i] = {u(rng), u(rng), u(rng)};
  f.c[0] += glm::dvec3(12.0);  // keep the function positive, like radiance
  return f;
}

double maxAbsDifference(const ShCoefficients& a, const ShCoefficients& b) {
  double e = 0.0;
  for (int i = 0; i < kMaxShCoefficients; ++i)
    for (int k = 0; k < 3; ++k) e = std::max(e, std::abs(a.c[i][k] - b.c[i][k]));
  return e;
}
}  // namespace

TEST(SphericalHarmonics, LegendreRecurrenceMatchesTheStandardLibraryPastLPlusM80) {
  // std::sph_legendre(l, m, theta) = Y_l^m(theta, 0) with the Condon-Shortley phase (-1)^m.
  double worst = 0.0;
  for (int l = 0; l <= 40; ++l)
    for (int m = 0; m <= l; ++m)
      for (double theta : {0.0, 1e-9, 0.01, 0.3, 1.0, kPi / 2, 2.0, kPi - 1e-6, kPi}) {
        const double reference = (m % 2 ? -1.0 : 1.0) * std::sph_legendre(l, m, theta);
        const double ours = normalizedLegendre(l, m, std::cos(theta));
        ASSERT_TRUE(std::isfinite(ours)) << l << "," << m << " at " << theta;
        worst = std::max(worst, std::abs(ours - reference));
        ASSERT_NEAR(ours, reference, 1e-12 * std::max(1.0, std::abs(reference))) << l << "," << m << " at " << theta;
      }
  std::printf("  |Pbar - std::sph_legendre| <= %.2e for l <= 40\n", worst);
}

TEST(SphericalHarmonics, LegendreIsOrthonormalToL40UnderExactQuadrature) {
  // 2 pi int Pbar_l^m Pbar_l'^m dt: the integrand is a polynomial of degree l + l' <= 80, which
  // 64-point Gauss-Legendre integrates exactly.
  const GaussLegendre gl = gaussLegendre(64);
  for (int m : {0, 1, 2, 7, 20, 33, 40})
    for (int l = m; l <= 40; ++l)
      for (int l2 = l; l2 <= 40; ++l2) {
        double sum = 0.0;
        for (std::size_t k = 0; k < gl.nodes.size(); ++k)
          sum += gl.weights[k] * normalizedLegendre(l, m, gl.nodes[k]) * normalizedLegendre(l2, m, gl.nodes[k]);
        EXPECT_NEAR(2.0 * kPi * sum, l == l2 ? 1.0 : 0.0, 1e-12) << "m " << m << " l " << l << " l' " << l2;
      }
}

TEST(SphericalHarmonics, BasisAtThePolesIsZonalAndExact) {
  for (int bands = 1; bands <= kMaxShBands; ++bands) {
    const ShBasis up = basis(bands, {0, 1, 0}), down = basis(bands, {0, -1, 0});
    for (int l = 0; l < bands; ++l)
      for (int m = -l; m <= l; ++m) {
        const double zonal = m == 0 ? std::sqrt((2.0 * l + 1.0) / (4.0 * kPi)) : 0.0;
        EXPECT_NEAR(up[shIndex(l, m)], zonal, 1e-14) << l << "," << m;
        EXPECT_NEAR(down[shIndex(l, m)], (l % 2 ? -1.0 : 1.0) * zonal, 1e-14) << l << "," << m;
        if (m != 0) {
          EXPECT_EQ(up[shIndex(l, m)], 0.0);  // exactly, not by cancellation
        }
      }
  }
}

TEST(SphericalHarmonics, BasisIsOrthonormalForEightBands) {
  // Gauss-Legendre in t (exact for the polynomial part) times a uniform rule in psi (exact
  // for trigonometric polynomials of degree < 32).
  const GaussLegendre gl = gaussLegendre(16);
  const int steps = 32;
  std::vector<double> gram(kMaxShCoefficients * kMaxShCoefficients, 0.0);
  for (std::size_t k = 0; k < gl.nodes.size(); ++k)
    for (int j = 0; j < steps; ++j) {
      const double t = gl.nodes[k], s = std::sqrt(1.0 - t * t), psi = 2.0 * kPi * j / steps;
      const ShBasis y = basis(kMaxShBands, {s * std::sin(psi), t, s * std::cos(psi)});
      const double w = gl.weights[k] * 2.0 * kPi / steps;
      for (int a = 0; a < kMaxShCoefficients; ++a)
        for (int b = 0; b < kMaxShCoefficients; ++b) gram[a * kMaxShCoefficients + b] += w * y[a] * y[b];
    }
  for (int a = 0; a < kMaxShCoefficients; ++a)
    for (int b = 0; b < kMaxShCoefficients; ++b)
      EXPECT_NEAR(gram[a * kMaxShCoefficients + b], a == b ? 1.0 : 0.0, 1e-13) << a << "," << b;
}

TEST(SphericalHarmonics, FloatBasisMatchesDouble) {
  for (const auto& d : fibonacciSphere(500)) {
    const ShBasis yd = basis(kMaxShBands, d);
    std::array<float, kMaxShCoefficients> yf{};
    shBasis(kMaxShBands, glm::vec3(d), yf);
    for (int i = 0; i < kMaxShCoefficients; ++i) EXPECT_NEAR(yf[i], yd[i], 2e-6) << i;
  }
}

TEST(SphericalHarmonics, CosineLobeOddBandsAboveOneAreExactlyZero) {
  for (int l = 3; l < 80; l += 2) EXPECT_EQ(cosineLobeBand(l), 0.0) << l;
  // Even bands: 2 pi int_0^1 t P_l(t) dt by exact Gauss-Legendre on [0, 1], up to l = 40.
  const GaussLegendre gl = gaussLegendre(40);
  for (int l = 0; l <= 40; l += 2) {
    double integral = 0.0;
    for (std::size_t k = 0; k < gl.nodes.size(); ++k) {
      const double t = 0.5 * (gl.nodes[k] + 1.0);
      integral += 0.5 * gl.weights[k] * t * normalizedLegendre(l, 0, t) * std::sqrt(4.0 * kPi / (2.0 * l + 1.0));
    }
    EXPECT_NEAR(cosineLobeBand(l), 2.0 * kPi * integral, 1e-14) << l;
  }
}

TEST(SphericalHarmonics, EightBandProjectionRecoversABandLimitedMap) {
  const ShCoefficients f = randomCoefficients(kMaxShBands, 7);
  const ShCoefficients back = projectRadiance(mapOf(1024, 512, f), kMaxShBands);
  // The map holds the function at pixel centres (piecewise constant): the error is that
  // sampling's, O(pixel^2) of the function's scale.
  const double e = maxAbsDifference(back, f);
  std::printf("  8-band map round trip: max coefficient error %.2e\n", e);
  EXPECT_LT(e, 2e-4);
}

TEST(SphericalHarmonics, ConstantMapGivesOnlyTheDcTermInEveryBand) {
  std::vector<float> px(512 * 256 * 3, 2.5f);
  const EnvironmentMap map(512, 256, px);
  for (int bands = 1; bands <= kMaxShBands; ++bands) {
    const ShCoefficients sh = projectRadiance(map, bands);
    EXPECT_NEAR(sh.c[0].x, 2.5 * 2.0 * std::sqrt(kPi), 1e-9);
    for (int i = 1; i < kMaxShCoefficients; ++i) EXPECT_NEAR(std::abs(sh.c[i].x), 0.0, 1e-11) << bands << ": " << i;
  }
}

TEST(SphericalHarmonics, BlackMapAndOnePixelSunStayFiniteInEveryBand) {
  EnvironmentMap map(1024, 512, std::vector<float>(1024 * 512 * 3, 0.0f));
  for (int bands = 1; bands <= kMaxShBands; ++bands) {
    const ShCoefficients sh = projectRadiance(map, bands);
    for (const auto& c : sh.c) EXPECT_EQ(c, glm::dvec3(0.0));
    const IrradianceError e = lightingError(map, bands, ShWindow::None, 50);
    EXPECT_EQ(e.mean, 0.0);
    EXPECT_EQ(e.max, 0.0);
  }
  const int col = 300, row = 120;
  float* p = &map.pixels()[(static_cast<std::size_t>(row) * 1024 + col) * 3];
  p[0] = p[1] = p[2] = 3e4f;
  const glm::dvec3 sun = map.texelDirection(col, row);
  const double exact = 3e4 * map.texelSolidAngle(row);
  for (int bands = 1; bands <= kMaxShBands; ++bands) {
    const ShCoefficients sh = projectRadiance(map, bands);
    // A delta light's n-band irradiance toward it: sum_l A_l (2l + 1) / (4 pi).
    double expected = 0.0;
    for (int l = 0; l < bands; ++l) expected += cosineLobeBand(l) * (2.0 * l + 1.0) / (4.0 * kPi);
    const glm::dvec3 toward = irradiance(sh, sun);
    EXPECT_TRUE(std::isfinite(toward.x));
    EXPECT_NEAR(toward.x / exact, expected, 2e-3) << bands;
    const IrradianceError e = lightingError(map, bands, ShWindow::None, 200);
    EXPECT_TRUE(std::isfinite(e.mean) && std::isfinite(e.max)) << bands;
  }
}

TEST(SphericalHarmonics, RotationAboutYInEveryBandEqualsReprojection) {
  const ShCoefficients f = randomCoefficients(kMaxShBands, 11);
  const ShRotation general(kMaxShBands);
  for (double angle : {0.1, 1.0, -2.5, kPi}) {
    const ShCoefficients closed = rotateAboutY(f, angle);
    // The geometric meaning: f'(R w) = f(w), R turning +Z toward +X.
    const glm::dmat3 r(glm::rotate(glm::dmat4(1.0), angle, glm::dvec3(0, 1, 0)));
    for (const auto& w : fibonacciSphere(50)) {
      const glm::dvec3 a = closed.evaluate(r * w), b = f.evaluate(w);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], 1e-11);
    }
    EXPECT_LT(maxAbsDifference(general.rotate(r, f), closed), 1e-12) << angle;
  }
}

TEST(SphericalHarmonics, GeneralRotationEqualsRotatingTheMap) {
  const ShRotation rotation(kMaxShBands);
  const ShCoefficients f = randomCoefficients(kMaxShBands, 3);
  std::mt19937 rng(5);
  std::normal_distribution<double> g;
  for (int trial = 0; trial < 20; ++trial) {
    const glm::dvec3 axis = glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
    const glm::dmat3 r(glm::rotate(glm::dmat4(1.0), 3.0 * g(rng), axis));
    const ShCoefficients turned = rotation.rotate(r, f);
    for (const auto& w : fibonacciSphere(40)) {  // f'(R w) = f(w)
      const glm::dvec3 a = turned.evaluate(r * w), b = f.evaluate(w);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], 1e-11);
    }
    // Energy per band is kept; composing rotations composes.
    for (int l = 0; l < kMaxShBands; ++l) {
      double e0 = 0.0, e1 = 0.0;
      for (int m = -l; m <= l; ++m) e0 += f.c[shIndex(l, m)].x * f.c[shIndex(l, m)].x,
                                    e1 += turned.c[shIndex(l, m)].x * turned.c[shIndex(l, m)].x;
      EXPECT_NEAR(e1, e0, 1e-11 * std::max(1.0, e0));
    }
    EXPECT_LT(maxAbsDifference(rotation.rotate(r, rotation.rotate(r, f)), rotation.rotate(r * r, f)), 1e-11);
  }
  // On a real map: rotating the 8-band coefficients equals projecting the map rotated
  // pixel by pixel (sampled bilinearly), up to that resampling's blur, well under the
  // truncation error of docs/accuracy.md.
  auto load = loadEnvironmentMap(mt::sharedAsset("envmaps/blender_studiolight_forest.exr"));
  ASSERT_TRUE(load.map) << load.diagnostics.format();
  const EnvironmentMap& map = *load.map;
  const glm::dmat3 r(glm::rotate(glm::dmat4(1.0), 0.7, glm::normalize(glm::dvec3(1, 2, 0.5))));
  std::vector<float> px(map.pixels().size());
  for (int row = 0; row < map.height(); ++row)
    for (int col = 0; col < map.width(); ++col) {
      const glm::vec3 v = map.sample(glm::transpose(r) * map.texelDirection(col, row));
      float* q = &px[(static_cast<std::size_t>(row) * map.width() + col) * 3];
      q[0] = v.r, q[1] = v.g, q[2] = v.b;
    }
  const ShCoefficients a = rotation.rotate(r, projectRadiance(map, kMaxShBands));
  const ShCoefficients b = projectRadiance(EnvironmentMap(map.width(), map.height(), px), kMaxShBands);
  const double e = maxAbsDifference(a, b) / std::abs(a.c[0].y);
  std::printf("  rotated coefficients vs rotated forest map, 8 bands: max |diff| / DC %.2e\n", e);
  EXPECT_LT(e, 5e-3);
}

TEST(SphericalHarmonics, WindowsDampHighBandsAndSinc4RemovesTheSunsNegativeLobe) {
  for (ShWindow w : {ShWindow::Hann, ShWindow::Lanczos}) {
    const auto weights = windowWeights(w, 6);
    EXPECT_EQ(weights[0], 1.0) << windowName(w);
    for (int l = 1; l < 6; ++l) EXPECT_LT(weights[l], weights[l - 1]) << windowName(w) << " " << l;
  }
  // A one-pixel sun rings: the plain 8-band irradiance goes negative somewhere.
  EnvironmentMap map(512, 256, std::vector<float>(512 * 256 * 3, 0.01f));
  float* p = &map.pixels()[(static_cast<std::size_t>(60) * 512 + 200) * 3];
  p[0] = p[1] = p[2] = 3e4f;
  const ShCoefficients sh = projectRadiance(map, kMaxShBands);
  double plainMin = 1e30, windowedMin = 1e30;
  double cutoff = 0.0;
  const ShCoefficients windowed = windowRadiance(sh, ShWindow::Sinc4, &cutoff);
  for (const auto& d : fibonacciSphere(4000)) {
    plainMin = std::min(plainMin, irradiance(sh, d).x);
    windowedMin = std::min(windowedMin, irradiance(windowed, d).x);
  }
  std::printf("  one-pixel sun, 8 bands: min E plain %.3g, sinc^4 (cutoff %.2f) %.3g\n", plainMin, cutoff, windowedMin);
  EXPECT_LT(plainMin, 0.0);
  EXPECT_TRUE(std::isfinite(cutoff));
  EXPECT_GT(windowedMin, -1e-3 * irradiance(sh, map.texelDirection(200, 60)).x);  // (checked on 2562 directions)
  // A constant map needs no window.
  const ShCoefficients flat = projectRadiance(EnvironmentMap(64, 32, std::vector<float>(64 * 32 * 3, 1.0f)), 4);
  (void)windowRadiance(flat, ShWindow::Sinc4, &cutoff);
  EXPECT_TRUE(std::isinf(cutoff));
}
