// Mirror-ball light probes: the reflection convention, the ball <-> lat-long conversion on
// analytic and real data, loadLightProbe's aspect detection, clamping and errors.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "marionette/prt/environment_map.hpp"
#include "marionette/prt/mirror_ball.hpp"
#include "prt_test_util.hpp"
#include "image_test_util.hpp"
#include "test_data.hpp"

using namespace marionette::prt;
namespace mt = marionette::test;
namespace fs = std::filesystem;

using marionette::prt::test::mentions;
using marionette::prt::test::tempDir;
using marionette::prt::test::writeFloatImage;

namespace {
constexpr double kPi = std::numbers::pi;
const double kHalfSqrt2 = std::sqrt(0.5);


bool near(const glm::dvec3& a, const glm::dvec3& b, double tolerance = 1e-12) {
  return glm::length(a - b) < tolerance;
}

// A smooth, strictly positive radiance: 1.5 + the direction's components, one per channel.
glm::dvec3 smoothRadiance(const glm::dvec3& d) { return glm::dvec3(1.5) + glm::dvec3(d.x, d.y, d.z); }

EnvironmentMap smoothMap(int width) {
  const int height = width / 2;
  std::vector<float> px(static_cast<std::size_t>(width) * height * 3);
  EnvironmentMap probe(width, height, {});
  for (int r = 0; r < height; ++r)
    for (int c = 0; c < width; ++c) {
      const glm::dvec3 v = smoothRadiance(probe.texelDirection(c, r));
      for (int k = 0; k < 3; ++k) px[(static_cast<std::size_t>(r) * width + c) * 3 + k] = static_cast<float>(v[k]);
    }
  return EnvironmentMap(width, height, std::move(px));
}

// Angle (radians) between a unit direction and -Z.
double angleFromMinusZ(const glm::dvec3& d) { return std::acos(std::clamp(-d.z, -1.0, 1.0)); }

double sum3(const glm::dvec3& v) { return v.x + v.y + v.z; }
}  // namespace

TEST(MirrorBall, KnownBallPointsReflectTheDocumentedDirections) {
  EXPECT_TRUE(near(mirrorBallDirection({0, 0}), {0, 0, 1}));    // centre: back toward the camera
  EXPECT_TRUE(near(mirrorBallDirection({1, 0}), {0, 0, -1}));   // rim: straight behind the ball
  EXPECT_TRUE(near(mirrorBallDirection({0, -1}), {0, 0, -1}));
  EXPECT_TRUE(near(mirrorBallDirection({-0.6, 0.8}), {0, 0, -1}));
  // Radius 1/sqrt(2): the normal is at 45 degrees to the view, the reflection at 90.
  EXPECT_TRUE(near(mirrorBallDirection({kHalfSqrt2, 0}), {1, 0, 0}));
  EXPECT_TRUE(near(mirrorBallDirection({-kHalfSqrt2, 0}), {-1, 0, 0}));
  EXPECT_TRUE(near(mirrorBallDirection({0, kHalfSqrt2}), {0, 1, 0}));
  EXPECT_TRUE(near(mirrorBallDirection({0, -kHalfSqrt2}), {0, -1, 0}));
  EXPECT_TRUE(near(mirrorBallDirection({3, 4}), {0, 0, -1}));  // outside the disc: the rim

  // Against the reflection law written out independently (glm::reflect) at scattered points.
  for (double a : {-0.9, -0.31, 0.0, 0.2, 0.55})
    for (double b : {-0.4, 0.0, 0.33, 0.7}) {
      if (a * a + b * b >= 1.0) continue;
      const glm::dvec3 n(a, b, std::sqrt(1.0 - a * a - b * b));
      EXPECT_TRUE(near(mirrorBallDirection({a, b}), glm::reflect(glm::dvec3(0, 0, -1), n), 1e-12)) << a << " " << b;
    }

  auto nearPoint = [](glm::dvec2 p, glm::dvec2 q) { return glm::length(p - q) < 1e-12; };
  EXPECT_TRUE(nearPoint(mirrorBallPoint({1, 0, 0}), {kHalfSqrt2, 0}));
  EXPECT_TRUE(nearPoint(mirrorBallPoint({0, 5, 0}), {0, kHalfSqrt2}));  // need not be normalized
  EXPECT_TRUE(nearPoint(mirrorBallPoint({0, 0, 2}), {0, 0}));
  EXPECT_TRUE(nearPoint(mirrorBallPoint({0, 0, 0}), {0, 0}));
  // -Z: any rim point; documented as (1, 0). Next to it: on the rim, in the direction of (x, y).
  const glm::dvec2 rim = mirrorBallPoint({0, 0, -1});
  EXPECT_TRUE(std::isfinite(rim.x) && std::isfinite(rim.y));
  EXPECT_TRUE(nearPoint(rim, {1, 0}));
  const glm::dvec2 almost = mirrorBallPoint({0, -1e-9, -1});
  EXPECT_NEAR(almost.x, 0.0, 1e-12);
  EXPECT_NEAR(almost.y, -1.0, 1e-12);
}

TEST(MirrorBall, DirectionToBallPointAndBackRoundTrips) {
  const double cap = 1.0 * kPi / 180.0;  // the ball has no resolution at -Z itself
  int checked = 0;
  double worst = 0.0;
  for (const glm::dvec3& w : test::fibonacciSphere(20000)) {
    if (angleFromMinusZ(w) < cap) continue;
    const glm::dvec2 p = mirrorBallPoint(w);
    ASSERT_LE(glm::length(p), 1.0 + 1e-15);
    worst = std::max(worst, glm::length(mirrorBallDirection(p) - w));
    ++checked;
  }
  EXPECT_GT(checked, 19990);
  EXPECT_LT(worst, 1e-9);
  std::printf("direction -> ball point -> direction: worst error %.3g over %d directions\n", worst, checked);
}

TEST(MirrorBall, RenderedBallIsOrientedAsDocumented) {
  // R, G, B = the positive parts of x, y, z: red to the right, green at the top, blue in the middle.
  EnvironmentMap map(256, 128, {});
  for (int r = 0; r < 128; ++r)
    for (int c = 0; c < 256; ++c) {
      const glm::dvec3 d = map.texelDirection(c, r);
      float* p = &map.pixels()[(static_cast<std::size_t>(r) * 256 + c) * 3];
      p[0] = static_cast<float>(std::max(d.x, 0.0)), p[1] = static_cast<float>(std::max(d.y, 0.0));
      p[2] = static_cast<float>(std::max(d.z, 0.0));
    }
  const int size = 100;
  const std::vector<float> ball = renderMirrorBall(map, size);
  ASSERT_EQ(ball.size(), static_cast<std::size_t>(size * size * 3));
  auto at = [&](int column, int row) {
    const float* p = &ball[(static_cast<std::size_t>(row) * size + column) * 3];
    return glm::dvec3(p[0], p[1], p[2]);
  };
  const int off = static_cast<int>(std::lround(50 * kHalfSqrt2));  // radius 1/sqrt(2) in pixels
  EXPECT_TRUE(near(at(50 + off, 50), {1, 0, 0}, 0.08)) << at(50 + off, 50).x;  // right: +X
  EXPECT_TRUE(near(at(50, 50 - off), {0, 1, 0}, 0.08)) << at(50, 50 - off).y;  // up (earlier rows): +Y
  EXPECT_TRUE(near(at(50 - off, 50), {0, 0, 0}, 0.08));                       // left: -X, nothing positive
  EXPECT_TRUE(near(at(50, 50), {0, 0, 1}, 0.05));                             // centre: +Z
  EXPECT_EQ(at(0, 0), glm::dvec3(0.0));                                        // outside the ball: black
  EXPECT_EQ(at(99, 99), glm::dvec3(0.0));
}

TEST(MirrorBall, AnalyticBallConvertsToTheRadianceItReflects) {
  // A ball written independently of the library (glm::reflect at each pixel centre) in a cropped,
  // non-square photo; everything outside the circle is NaN, which must never be read.
  const int width = 170, height = 150;
  const MirrorBallCircle circle{80.0, 72.5, 64.0};
  std::vector<float> px(static_cast<std::size_t>(width) * height * 3, std::numeric_limits<float>::quiet_NaN());
  for (int r = 0; r < height; ++r)
    for (int c = 0; c < width; ++c) {
      const double a = (c + 0.5 - circle.centerX) / circle.radius, b = (circle.centerY - r - 0.5) / circle.radius;
      if (a * a + b * b > 1.0) continue;
      const glm::dvec3 n(a, b, std::sqrt(std::max(0.0, 1.0 - a * a - b * b)));
      const glm::dvec3 v = smoothRadiance(glm::reflect(glm::dvec3(0, 0, -1), n));
      for (int k = 0; k < 3; ++k) px[(static_cast<std::size_t>(r) * width + c) * 3 + k] = static_cast<float>(v[k]);
    }
  marionette::Diagnostics diag;
  const auto map = mirrorBallToLatLong(px.data(), width, height, {circle, 0}, diag, "analytic");
  ASSERT_TRUE(map) << diag.format();
  EXPECT_TRUE(diag.items.empty()) << diag.format();
  EXPECT_EQ(map->width(), 256);  // default: twice the diameter
  EXPECT_EQ(map->height(), 128);
  double meanError = 0.0, maxError = 0.0, weight = 0.0;
  for (int r = 0; r < map->height(); ++r)
    for (int c = 0; c < map->width(); ++c) {
      const glm::dvec3 got(map->texel(c, r));
      ASSERT_TRUE(std::isfinite(got.x) && std::isfinite(got.y) && std::isfinite(got.z)) << c << " " << r;
      const glm::dvec3 d = map->texelDirection(c, r);
      if (angleFromMinusZ(d) < 20.0 * kPi / 180.0) continue;
      const glm::dvec3 want = smoothRadiance(d);
      const double e = sum3(glm::abs(got - want)) / sum3(want);
      meanError += e * map->texelSolidAngle(r), weight += map->texelSolidAngle(r);
      maxError = std::max(maxError, e);
    }
  meanError /= weight;
  std::printf("analytic 128-px ball -> lat-long: mean relative error %.3g, max %.3g (outside 20 deg of -Z)\n",
              meanError, maxError);
  // Measured 2.3e-4 mean, 4.3e-3 max (the max near the 20-degree edge, where the ball is most
  // squeezed): bounds about 2x. Moving the circle by a quarter pixel gives 3.5e-3 mean (1 pixel:
  // 1.4e-2), a mirrored axis errors of order 1: this is the test of the mapping's registration.
  EXPECT_LT(meanError, 5e-4);
  EXPECT_LT(maxError, 1e-2);
}

TEST(MirrorBall, QuarryRoundTripThroughA512PixelBall) {
  const std::string path = mt::sharedAsset("envmaps/quarry_01_1k.hdr");
  MARIONETTE_REQUIRE_FILE(path);
  const auto load = loadEnvironmentMap(path);
  ASSERT_TRUE(load.map) << load.diagnostics.format();
  const EnvironmentMap& original = *load.map;
  const int size = 512;
  const std::vector<float> ball = renderMirrorBall(original, size);
  marionette::Diagnostics diag;
  MirrorBallOptions options;
  options.outputWidth = original.width();  // compare pixel for pixel
  const auto back = mirrorBallToLatLong(ball.data(), size, size, options, diag, "quarry ball");
  ASSERT_TRUE(back) << diag.format();
  ASSERT_EQ(back->width(), original.width());
  ASSERT_EQ(back->height(), original.height());

  const double capCos = std::cos(20.0 * kPi / 180.0);
  double meanError = 0.0, weight = 0.0, powerOriginal = 0.0, powerBack = 0.0;
  double powerOriginalOutside = 0.0, powerBackOutside = 0.0;
  int zeroReference = 0;
  for (int r = 0; r < original.height(); ++r)
    for (int c = 0; c < original.width(); ++c) {
      const double omega = original.texelSolidAngle(r);
      const glm::dvec3 want(original.texel(c, r)), got(back->texel(c, r));
      powerOriginal += sum3(want) * omega, powerBack += sum3(got) * omega;
      if (-original.texelDirection(c, r).z > capCos) continue;  // within 20 degrees of -Z
      powerOriginalOutside += sum3(want) * omega, powerBackOutside += sum3(got) * omega;
      if (!(sum3(want) > 0.0)) {
        ++zeroReference;
        continue;
      }
      meanError += sum3(glm::abs(got - want)) / sum3(want) * omega;
      weight += omega;
    }
  meanError /= weight;
  const double powerError = std::abs(powerBack - powerOriginal) / powerOriginal;
  const double powerErrorOutside = std::abs(powerBackOutside - powerOriginalOutside) / powerOriginalOutside;
  std::printf("quarry_01_1k -> 512-px ball -> 1024x512: mean |relative error| %.4f (solid-angle weighted, "
              "outside 20 deg of -Z), power error %.4f (whole sphere), %.4f (outside the cap)\n",
              meanError, powerError, powerErrorOutside);
  EXPECT_EQ(zeroReference, 0);
  // Rationale: the 512-px ball has pi 256^2 = 206k samples of the sphere against the original's
  // 524k, so the round trip is a low-pass filter: the error is the map's detail finer than the
  // ball's pixels (quarry's gravel, rock edges, the sun's disc), not a mapping error (the
  // analytic test above measures those at 2e-4). Goal: 0.10. Mirroring the ball image
  // left-right gives 1.15, top-bottom 2.57; shifting it by one whole pixel 0.080 (the analytic
  // test is the one made to catch that; the regression bound below does too).
  EXPECT_LT(meanError, 0.10);
  // regression: docs/prt.md publishes 0.0505; 1.5x.
  EXPECT_LT(meanError, 0.075);
  // Power: the ball spends the same solid angle on every pixel (4 / R^2 sr), so the filtering
  // keeps the integral. Goal 0.005 (a few times tighter than "a few percent").
  EXPECT_LT(powerError, 0.005);
  EXPECT_LT(powerErrorOutside, 0.005);
  // regression: docs/prt.md publishes 0.17 % over the whole sphere and 0.21 % outside the cap; 1.5x.
  EXPECT_LT(powerError, 0.0026);
  EXPECT_LT(powerErrorOutside, 0.0032);
}

TEST(MirrorBall, LoadLightProbeDetectsTheProjectionFromTheAspect) {
  const fs::path dir = tempDir("ball_auto");
  const EnvironmentMap smooth = smoothMap(128);
  const std::string ballPath = (dir / "ball.exr").string();
  const std::vector<float> ball = renderMirrorBall(smooth, 64);
  writeFloatImage(ballPath, 64, 64, 3, ball);
  const std::string latLongPath = (dir / "latlong.exr").string();
  writeFloatImage(latLongPath, 128, 64, 3, smooth.pixels());
  const std::string widePath = (dir / "wide.exr").string();
  writeFloatImage(widePath, 48, 16, 3, std::vector<float>(48 * 16 * 3, 1.0f));

  // Square: a mirror ball, converted to 2 x diameter = 128 x 64, holding the smooth radiance.
  const auto a = loadLightProbe(ballPath);
  ASSERT_TRUE(a.map) << a.diagnostics.format();
  EXPECT_TRUE(a.diagnostics.items.empty()) << a.diagnostics.format();
  EXPECT_EQ(a.map->width(), 128);
  EXPECT_EQ(a.map->height(), 64);
  const int c = 96, r = 32;  // about +X
  const glm::dvec3 want = smoothRadiance(a.map->texelDirection(c, r));
  EXPECT_LT(sum3(glm::abs(glm::dvec3(a.map->texel(c, r)) - want)) / sum3(want), 0.01);
  // The same file forced to lat-long: read as is, with the aspect warning.
  const auto forced = loadLightProbe(ballPath, LightProbeKind::LatLong);
  ASSERT_TRUE(forced.map);
  EXPECT_EQ(forced.map->width(), 64);
  EXPECT_TRUE(mentions(forced.diagnostics, "not 2:1")) << forced.diagnostics.format();

  // 2:1: lat-long, exactly what loadEnvironmentMap gives.
  const auto b = loadLightProbe(latLongPath);
  ASSERT_TRUE(b.map) << b.diagnostics.format();
  EXPECT_TRUE(b.diagnostics.items.empty()) << b.diagnostics.format();
  EXPECT_EQ(b.map->pixels(), loadEnvironmentMap(latLongPath).map->pixels());

  // 3:1: neither; lat-long with the aspect warning naming the file.
  const auto w = loadLightProbe(widePath);
  ASSERT_TRUE(w.map);
  EXPECT_EQ(w.map->width(), 48);
  EXPECT_TRUE(mentions(w.diagnostics, "not 2:1")) << w.diagnostics.format();
  EXPECT_TRUE(mentions(w.diagnostics, widePath));

  // A ball cropped into a 2:1 image only loads as a ball when asked, with its circle.
  const std::string croppedPath = (dir / "cropped.exr").string();
  std::vector<float> cropped(128 * 64 * 3, 0.0f);
  for (int row = 0; row < 64; ++row)
    for (int col = 0; col < 64; ++col)
      for (int k = 0; k < 3; ++k)
        cropped[(static_cast<std::size_t>(row) * 128 + 40 + col) * 3 + k] = ball[(static_cast<std::size_t>(row) * 64 + col) * 3 + k];
  writeFloatImage(croppedPath, 128, 64, 3, cropped);
  const auto d = loadLightProbe(croppedPath, LightProbeKind::MirrorBall, {MirrorBallCircle{72.0, 32.0, 32.0}, 0});
  ASSERT_TRUE(d.map) << d.diagnostics.format();
  ASSERT_EQ(d.map->pixels().size(), a.map->pixels().size());
  for (std::size_t i = 0; i < a.map->pixels().size(); ++i)
    ASSERT_NEAR(d.map->pixels()[i], a.map->pixels()[i], 1e-5) << i;
}

TEST(MirrorBall, BadInputIsAnErrorNamingTheFile) {
  const fs::path dir = tempDir("ball_errors");
  const std::string missing = (dir / "no_such_probe.exr").string();
  const auto a = loadLightProbe(missing);
  EXPECT_FALSE(a.map);
  EXPECT_TRUE(mentions(a.diagnostics, missing)) << a.diagnostics.format();
  EXPECT_TRUE(mentions(a.diagnostics, "not found"));

  const std::string empty = (dir / "empty.hdr").string();
  { std::ofstream touch(empty); }
  ASSERT_EQ(fs::file_size(empty), 0u);
  for (LightProbeKind kind : {LightProbeKind::Auto, LightProbeKind::MirrorBall, LightProbeKind::LatLong}) {
    const auto b = loadLightProbe(empty, kind);
    EXPECT_FALSE(b.map);
    EXPECT_FALSE(b.diagnostics.ok());
    EXPECT_TRUE(mentions(b.diagnostics, empty)) << b.diagnostics.format();
  }

  const std::string ballPath = (dir / "ball.exr").string();
  writeFloatImage(ballPath, 32, 32, 3, std::vector<float>(32 * 32 * 3, 1.0f));
  for (const MirrorBallCircle& bad : {MirrorBallCircle{16, 16, 20}, MirrorBallCircle{100, 16, 8},
                                      MirrorBallCircle{-10, -10, 4}, MirrorBallCircle{16, 16, 0},
                                      MirrorBallCircle{16, std::numeric_limits<double>::quiet_NaN(), 8}}) {
    const auto c = loadLightProbe(ballPath, LightProbeKind::MirrorBall, {bad, 0});
    EXPECT_FALSE(c.map);
    EXPECT_FALSE(c.diagnostics.ok());
    EXPECT_TRUE(mentions(c.diagnostics, ballPath)) << c.diagnostics.format();
    EXPECT_TRUE(mentions(c.diagnostics, "mirror-ball circle")) << c.diagnostics.format();
  }
  const auto odd = loadLightProbe(ballPath, LightProbeKind::Auto, {std::nullopt, 101});
  EXPECT_FALSE(odd.map);
  EXPECT_TRUE(mentions(odd.diagnostics, ballPath)) << odd.diagnostics.format();

  // In memory: no pixels or no data.
  marionette::Diagnostics d;
  EXPECT_FALSE(mirrorBallToLatLong(nullptr, 16, 16, {}, d, "memory"));
  const float one[3] = {1, 1, 1};
  EXPECT_FALSE(mirrorBallToLatLong(one, 0, 1, {}, d, "memory"));
  EXPECT_EQ(d.items.size(), 2u);
  EXPECT_TRUE(mentions(d, "memory"));
  EXPECT_TRUE(renderMirrorBall(smoothMap(16), 0).empty());
}

TEST(MirrorBall, NanAndNegativeValuesInABallAreClampedWithAWarningNamingTheFile) {
  const fs::path dir = tempDir("ball_clamp");
  const std::string path = (dir / "dirty_ball.exr").string();
  std::vector<float> px = renderMirrorBall(smoothMap(64), 32);
  const std::size_t centre = (16u * 32 + 16) * 3;
  px[centre] = std::numeric_limits<float>::quiet_NaN();
  px[centre + 4] = -2.0f;
  writeFloatImage(path, 32, 32, 3, px);
  const auto load = loadLightProbe(path);
  ASSERT_TRUE(load.map) << load.diagnostics.format();
  ASSERT_EQ(load.diagnostics.items.size(), 1u) << load.diagnostics.format();
  EXPECT_EQ(load.diagnostics.items[0].severity, marionette::Severity::Warning);
  EXPECT_EQ(load.diagnostics.items[0].file, path);
  EXPECT_TRUE(mentions(load.diagnostics, "2 pixel values clamped to 0 (1 negative, 1 NaN, 0 infinite)"))
      << load.diagnostics.format();
  for (float v : load.map->pixels()) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f) << path;
}
