// 9-coefficient (n = 3) SH lighting against brute-force irradiance on real HDR maps, and its
// exact cases (constant, black, sun, rotation, the cosine kernel's bands).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "prt_test_util.hpp"
#include "marionette/prt/environment_map.hpp"
#include "marionette/prt/sh_lighting.hpp"
#include "test_data.hpp"

using namespace marionette::prt;
using marionette::prt::test::errorStats;
using marionette::prt::test::fibonacciSphere;
namespace mt = marionette::test;

namespace {
constexpr double kPi = std::numbers::pi;
constexpr int kShCount = 9;  // bands 0..2

ShBasis basis9(const glm::dvec3& d) {
  ShBasis y{};
  shBasis(3, d, y);
  return y;
}

EnvironmentMap constantMap(int w, int h, glm::vec3 value) {
  std::vector<float> px(static_cast<std::size_t>(w) * h * 3);
  for (std::size_t i = 0; i < px.size(); i += 3) px[i] = value.r, px[i + 1] = value.g, px[i + 2] = value.b;
  return EnvironmentMap(w, h, std::move(px));
}

std::vector<glm::dvec3> shIrradiance(const ShCoefficients& radiance, const std::vector<glm::dvec3>& normals) {
  std::vector<glm::dvec3> out;
  for (const auto& n : normals) out.push_back(irradiance(radiance, n));
  return out;
}

// Checks one real map: SH9 against brute force over 1000 normals.
void checkRealMap(const std::string& path, double meanBound, double maxBound) {
  MARIONETTE_REQUIRE_FILE(path);
  auto load = loadEnvironmentMap(path);
  ASSERT_TRUE(load.map) << load.diagnostics.format();
  const auto normals = fibonacciSphere(1000);
  const ShCoefficients sh = projectRadiance(*load.map);
  const auto reference = bruteForceIrradiance(*load.map, normals);
  const auto stats = errorStats(shIrradiance(sh, normals), reference);
  std::printf("  %-70s mean %.4f  max %.4f\n", path.c_str(), stats.mean, stats.max);
  EXPECT_LT(stats.mean, meanBound) << path;
  EXPECT_LT(stats.max, maxBound) << path;
  for (const auto& e : reference) ASSERT_GT(std::min({e.r, e.g, e.b}), 0.0) << path;
}
}  // namespace

TEST(ShLighting, CosineLobeBandsAreRamamoorthiHanrahansAndOddBandsVanish) {
  EXPECT_DOUBLE_EQ(cosineLobeBand(0), kPi);
  EXPECT_DOUBLE_EQ(cosineLobeBand(1), 2.0 * kPi / 3.0);
  EXPECT_DOUBLE_EQ(cosineLobeBand(2), kPi / 4.0);
  EXPECT_EQ(cosineLobeBand(3), 0.0);
  EXPECT_EQ(cosineLobeBand(5), 0.0);
  EXPECT_NEAR(cosineLobeBand(4), -kPi / 24.0, 1e-15);
  // Independently: A_l = 2 pi sqrt(4 pi / (2l+1)) * int_0^1 max(0, t) Y_l0(t) dt, with the
  // zonal harmonic Y_l0(t) = sqrt((2l+1) / 4 pi) P_l(t): so A_l = 2 pi int_0^1 t P_l(t) dt.
  for (int l = 0; l <= 6; ++l) {
    const int steps = 200000;
    double integral = 0.0;
    for (int s = 0; s < steps; ++s) {
      const double t = (s + 0.5) / steps;
      double p0 = 1.0, p1 = t;  // Legendre recurrence
      double pl = l == 0 ? p0 : p1;
      for (int k = 2; k <= l; ++k) {
        pl = ((2.0 * k - 1.0) * t * p1 - (k - 1.0) * p0) / k;
        p0 = p1, p1 = pl;
      }
      integral += t * pl / steps;
    }
    EXPECT_NEAR(cosineLobeBand(l), 2.0 * kPi * integral, 1e-8) << "band " << l;
  }
}

TEST(ShLighting, IrradianceCoefficientsFoldTheKernelIn) {
  ShCoefficients radiance;
  for (int i = 0; i < kShCount; ++i) radiance.c[i] = glm::dvec3(1.0 + i, 2.0 * i, -0.5 * i);
  const ShCoefficients c = irradianceCoefficients(radiance);
  EXPECT_EQ(c.c[0], radiance.c[0] * kPi);
  for (int i = 1; i < 4; ++i) EXPECT_EQ(c.c[i], radiance.c[i] * (2.0 * kPi / 3.0));
  for (int i = 4; i < 9; ++i) EXPECT_EQ(c.c[i], radiance.c[i] * (kPi / 4.0));
  const glm::dvec3 n = glm::normalize(glm::dvec3(0.3, -0.5, 0.8));
  const glm::dvec3 a = c.evaluate(n), b = irradiance(radiance, n);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], 1e-12);
}

TEST(ShLighting, BasisIsOrthonormalUnderTheSolidAngleQuadrature) {
  const EnvironmentMap map = constantMap(512, 256, glm::vec3(0.0f));
  for (int i = 0; i < kShCount; ++i)
    for (int j = i; j < kShCount; ++j) {
      double sum = 0.0;
      for (int row = 0; row < map.height(); ++row)
        for (int col = 0; col < map.width(); ++col) {
          const ShBasis y = basis9(map.texelDirection(col, row));
          sum += y[i] * y[j] * map.texelSolidAngle(row);
        }
      EXPECT_NEAR(sum, i == j ? 1.0 : 0.0, 2e-4) << i << "," << j;
    }
}

TEST(ShLighting, PixelIntegralsOfTheBasisMatchFineQuadratureAndCloseOverTheSphere) {
  const EnvironmentMap map(64, 32, std::vector<float>(64 * 32 * 3));
  ShBasis total{};
  for (int row = 0; row < map.height(); ++row)
    for (int col = 0; col < map.width(); ++col) {
      const ShBasis exact = pixelBasisIntegrals(map, col, row);
      for (int i = 0; i < kShCount; ++i) total[i] += exact[i];
      if ((row * 7 + col) % 5 != 0 && row != 0 && row != 31) continue;  // a sample, and both polar rows
      // Midpoint rule over 40 x 40 sub-cells, each weighted by its exact solid angle.
      ShBasis fine{};
      const int n = 40;
      for (int a = 0; a < n; ++a) {
        const double v0 = (row + static_cast<double>(a) / n) / map.height(), v1 = (row + (a + 1.0) / n) / map.height();
        const double dw = 2.0 * kPi / map.width() / n * (std::cos(kPi * v0) - std::cos(kPi * v1));
        for (int b = 0; b < n; ++b) {
          const ShBasis y = basis9(EnvironmentMap::direction((col + (b + 0.5) / n) / map.width(), 0.5 * (v0 + v1)));
          for (int i = 0; i < kShCount; ++i) fine[i] += y[i] * dw;
        }
      }
      const double dw = map.texelSolidAngle(row);
      EXPECT_NEAR(exact[0], basis9({0, 1, 0})[0] * dw, 1e-15);
      for (int i = 0; i < kShCount; ++i) EXPECT_NEAR(exact[i], fine[i], 2e-4 * dw) << i << " at " << col << "," << row;
    }
  EXPECT_NEAR(total[0], 4.0 * kPi * 0.5 / std::sqrt(kPi), 1e-12);
  for (int i = 1; i < kShCount; ++i) EXPECT_NEAR(total[i], 0.0, 1e-12) << i;
}

TEST(ShLighting, BandLimitedMapIsReproducedByNineCoefficients) {
  // L = a polynomial of degree 2 in the direction: exactly bands 0..2, so SH9 irradiance is
  // exact and must match brute force up to the brute force's own quadrature error. This pins
  // every basis function's sign and constant, and the direction convention, to the reference.
  const int w = 1024, h = 512;
  std::vector<float> px(static_cast<std::size_t>(w) * h * 3);
  EnvironmentMap shape(w, h, {});
  for (int row = 0; row < h; ++row)
    for (int col = 0; col < w; ++col) {
      const glm::dvec3 d = shape.texelDirection(col, row);
      const double base = 3.0 + 0.9 * d.x - 0.7 * d.y + 0.5 * d.z + 0.8 * d.x * d.z - 0.6 * d.x * d.y +
                          0.4 * (3 * d.y * d.y - 1) + 0.3 * d.y * d.z - 0.5 * (d.z * d.z - d.x * d.x);
      float* p = &px[(static_cast<std::size_t>(row) * w + col) * 3];
      p[0] = static_cast<float>(base), p[1] = static_cast<float>(base + 0.5 * d.y), p[2] = static_cast<float>(base - 0.8 * d.x * d.z);
    }
  const EnvironmentMap map(w, h, px);
  const auto normals = fibonacciSphere(100);
  const ShCoefficients sh = projectRadiance(map);
  const auto stats = errorStats(shIrradiance(sh, normals), bruteForceIrradiance(map, normals));
  std::printf("  band-limited map: mean %.2e  max %.2e\n", stats.mean, stats.max);
  EXPECT_LT(stats.max, 1e-4);  // goal: the brute force's quadrature error, not the method's
  // regression: docs/accuracy.md ("Environment lighting") publishes 3.4e-6; 1.5x.
  EXPECT_LT(stats.max, 5e-6);
}

TEST(ShLighting, ConstantMapHasOnlyTheDcTermAndIrradiancePiL) {
  const glm::vec3 value(0.25f, 1.0f, 3.5f);
  const EnvironmentMap map = constantMap(1024, 512, value);
  const ShCoefficients sh = projectRadiance(map);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(sh.c[0][k], value[k] * 2.0 * std::sqrt(kPi), 1e-6);
  for (int i = 1; i < kShCount; ++i)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(sh.c[i][k], 0.0, 1e-6) << "coefficient " << i;
  for (const auto& n : fibonacciSphere(200)) {
    const glm::dvec3 e = irradiance(sh, n);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(e[k], kPi * value[k], 1e-6);
  }
  // The brute force agrees (its only error: the cosine's kink inside pixels).
  const auto brute = bruteForceIrradiance(map, fibonacciSphere(20));
  for (const auto& e : brute)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(e[k] / (kPi * value[k]), 1.0, 1e-4);
}

TEST(ShLighting, BlackMapGivesZero) {
  const EnvironmentMap map = constantMap(256, 128, glm::vec3(0.0f));
  const ShCoefficients sh = projectRadiance(map);
  for (const auto& c : sh.c) EXPECT_EQ(c, glm::dvec3(0.0));
  for (const auto& n : fibonacciSphere(50)) EXPECT_EQ(irradiance(sh, n), glm::dvec3(0.0));
  for (const auto& e : bruteForceIrradiance(map, fibonacciSphere(10))) EXPECT_EQ(e, glm::dvec3(0.0));
}

TEST(ShLighting, OnePixelSunGivesFinitePositiveIrradianceTowardIt) {
  EnvironmentMap map = constantMap(1024, 512, glm::vec3(0.0f));
  const int col = 700, row = 150;
  float* p = &map.pixels()[(static_cast<std::size_t>(row) * 1024 + col) * 3];
  p[0] = p[1] = p[2] = 3e4f;
  const ShCoefficients sh = projectRadiance(map);
  const glm::dvec3 sun = map.texelDirection(col, row);
  const glm::dvec3 toward = irradiance(sh, sun);
  const double exact = 3e4 * map.texelSolidAngle(row);  // a point light: E = L dw (n . w = 1)
  for (int k = 0; k < 3; ++k) {
    EXPECT_TRUE(std::isfinite(toward[k]));
    EXPECT_GT(toward[k], 0.0);
    // SH9 of a delta light: sum_l A_l (2l+1)/(4 pi) P_l(1) = (pi + 2 pi + 5 pi / 4) / (4 pi) = 17/16.
    // (1e-3: the projection integrates the basis over the sun's pixel, 0.35 degrees wide.)
    EXPECT_NEAR(toward[k] / exact, 17.0 / 16.0, 1e-3);
  }
  const auto brute = bruteForceIrradiance(map, {sun, -sun});
  EXPECT_NEAR(brute[0].r / exact, 1.0, 1e-9);
  EXPECT_EQ(brute[1].r, 0.0);
  // Away from the sun SH9 rings (negative lobe): the known cost of 9 coefficients.
  EXPECT_LT(irradiance(sh, -sun).r, toward.r);
}

TEST(ShLighting, RotationAboutYEqualsReprojectingTheRotatedMap) {
  auto load = loadEnvironmentMap(mt::sharedAsset("envmaps/quarry_01_1k.hdr"));
  ASSERT_TRUE(load.map) << load.diagnostics.format();
  const EnvironmentMap& map = *load.map;
  const ShCoefficients sh = projectRadiance(map);
  for (int shift : {1, 37, 256, 700}) {
    const double angle = 2.0 * kPi * shift / map.width();
    // The rotated map, pixel by pixel: L'(w) = L(R^-1 w); R^-1 w of a pixel centre is the
    // centre of another pixel of the same row, found from the geometry (not assumed).
    std::vector<float> rotated(map.pixels().size());
    for (int row = 0; row < map.height(); ++row)
      for (int c = 0; c < map.width(); ++c) {
        const glm::dvec3 w = map.texelDirection(c, row);
        const glm::dvec3 back(w.x * std::cos(angle) - w.z * std::sin(angle), w.y,
                              w.x * std::sin(angle) + w.z * std::cos(angle));  // R_y(-angle) w
        const int source = static_cast<int>(std::lround(EnvironmentMap::uv(back).x * map.width() - 0.5)) %
                           map.width();
        const glm::vec3 l = map.texel(source, row);
        float* q = &rotated[(static_cast<std::size_t>(row) * map.width() + c) * 3];
        q[0] = l.r, q[1] = l.g, q[2] = l.b;
      }
    const ShCoefficients reprojected = projectRadiance(EnvironmentMap(map.width(), map.height(), rotated));
    const ShCoefficients turned = rotateAboutY(sh, angle);
    for (int i = 0; i < kShCount; ++i)
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(turned.c[i][k], reprojected.c[i][k], 1e-9 + 1e-9 * std::abs(sh.c[0][k]))
            << "shift " << shift << " coefficient " << i;
    // And the geometric meaning: +Z turns toward +X.
    const glm::dvec3 n = glm::normalize(glm::dvec3(0.2, 0.4, 0.9));
    const glm::dvec3 rn(n.x * std::cos(angle) + n.z * std::sin(angle), n.y,
                        -n.x * std::sin(angle) + n.z * std::cos(angle));
    const glm::dvec3 a = irradiance(turned, rn), b = irradiance(sh, n);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], 1e-9 * std::abs(b[k]) + 1e-12);
  }
  // Not a trivial identity: a quarter turn changes the coefficients.
  const ShCoefficients quarter = rotateAboutY(sh, kPi / 2);
  EXPECT_GT(std::abs(quarter.c[3].g - sh.c[3].g), 1e-3 * std::abs(sh.c[0].g));
}

// Bounds: the figures measured in docs/accuracy.md ("Environment lighting") plus 25 %. The
// errors are SH9's truncation (the cosine kernel's band 4 and up, -pi/24 ...), largest in
// relative terms on normals facing away from a sun (little irradiance, the sun's ringing).
// The band-limited test above shows the implementation itself is exact to 5e-6.
TEST(ShLighting, Sh9MatchesBruteForceOnTheSharedMaps) {
  std::printf("SH9 vs brute force, relative irradiance error over 1000 normals:\n");
  checkRealMap(mt::sharedAsset("envmaps/blender_studiolight_forest.exr"), 0.080, 0.55);
  checkRealMap(mt::sharedAsset("envmaps/quarry_01_1k.hdr"), 0.27, 1.40);
  checkRealMap(mt::sharedAsset("envmaps/royal_esplanade_1k.hdr"), 0.14, 0.60);
}

TEST(ShLighting, Sh9MatchesBruteForceOnEveryBlenderStudiolight) {
  std::printf("SH9 vs brute force, Blender studio lights (%s):\n", marionette::test::studiolightsDir().c_str());
  const struct {
    const char* name;
    double mean, max;
  } maps[] = {{"city.exr", 0.097, 0.45},     {"courtyard.exr", 0.113, 0.63}, {"forest.exr", 0.080, 0.55},
              {"interior.exr", 0.083, 0.56}, {"night.exr", 0.103, 4.4},      {"studio.exr", 0.118, 0.88},
              {"sunrise.exr", 0.47, 6.7},    {"sunset.exr", 0.045, 0.26}};
  for (const auto& m : maps) checkRealMap(mt::blenderStudiolight(m.name), m.mean, m.max);
}
