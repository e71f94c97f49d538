// CameraLightEstimator: bad input first, then a constant world, the pose's convention, clipped
// highlights, the temporal behaviour (a lamp switched off, noise), determinism and the camera
// match. The probe sweeps against truth are CameraLightAccuracy (camera_light_accuracy_test.cpp).
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>
#include <vector>

#include "camera_sweep.hpp"
#include "marionette/prt/sh_lighting.hpp"
#include "marionette_ar/camera_light_estimate.hpp"

using namespace marionette;
using marionette::ar::CameraLightEstimator;
using marionette::ar::CameraLightFrame;
using marionette::ar::LightFrameResult;

namespace {

constexpr int kW = 64, kH = 48;

double linear(int code) {
  const double c = code / 255.0;
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

std::vector<std::uint8_t> solid(int r, int g, int b, int w = kW, int h = kH) {
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(w) * h * 3);
  for (std::size_t i = 0; i < rgb.size(); i += 3) rgb[i] = static_cast<std::uint8_t>(r), rgb[i + 1] = static_cast<std::uint8_t>(g), rgb[i + 2] = static_cast<std::uint8_t>(b);
  return rgb;
}

CameraLightFrame frameOf(const std::vector<std::uint8_t>& rgb, const glm::dmat3& rotation, double t, double exposure = 1.0) {
  CameraLightFrame f;
  f.image = {rgb.data(), kW, kH, 0};
  f.cameraToWorld = glm::dmat4(rotation);
  f.intrinsics = ar::PinholeIntrinsics::fromFovY(kW, kH, 45.0);
  f.timeSeconds = t;
  f.exposure = exposure;
  return f;
}

bool sameBits(const ar::CameraLightEstimate& a, const ar::CameraLightEstimate& b) {
  return std::memcmp(a.radiance.c.data(), b.radiance.c.data(), sizeof(glm::dvec3) * 9) == 0 &&
         a.seenFraction == b.seenFraction && a.clippedFraction == b.clippedFraction &&
         a.framesAccepted == b.framesAccepted && a.valid == b.valid;
}

glm::dmat3 yaw(double degrees) { return test::rotationAbout({0, 1, 0}, degrees); }
glm::dmat3 pitch(double degrees) { return test::rotationAbout({1, 0, 0}, degrees); }

}  // namespace

TEST(CameraLightEstimate, BadInputIsRejectedWithItsReasonAndChangesNothing) {
  CameraLightEstimator estimator;
  const auto rgb = solid(120, 120, 120);
  ASSERT_EQ(estimator.addFrame(frameOf(rgb, glm::dmat3(1.0), 0.0)), LightFrameResult::Accepted);
  const ar::CameraLightEstimate before = estimator.estimate();
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const auto bright = solid(250, 250, 250);
  struct Case {
    const char* what;
    LightFrameResult expect;
    void (*spoil)(CameraLightFrame&, double, double);
  };
  const Case cases[] = {
      {"no pose", LightFrameResult::NoPose, [](CameraLightFrame& f, double, double) { f.cameraToWorld.reset(); }},
      {"null pixels", LightFrameResult::EmptyImage, [](CameraLightFrame& f, double, double) { f.image.rgb = nullptr; }},
      {"zero width", LightFrameResult::EmptyImage, [](CameraLightFrame& f, double, double) { f.image.width = 0; }},
      {"negative height", LightFrameResult::EmptyImage, [](CameraLightFrame& f, double, double) { f.image.height = -3; }},
      {"short stride", LightFrameResult::EmptyImage, [](CameraLightFrame& f, double, double) { f.image.strideBytes = kW * 3 - 1; }},
      {"fx zero", LightFrameResult::BadIntrinsics, [](CameraLightFrame& f, double, double) { f.intrinsics.fx = 0; }},
      {"fy negative", LightFrameResult::BadIntrinsics, [](CameraLightFrame& f, double, double) { f.intrinsics.fy = -10; }},
      {"fx NaN", LightFrameResult::BadIntrinsics, [](CameraLightFrame& f, double n, double) { f.intrinsics.fx = n; }},
      {"fy infinite", LightFrameResult::BadIntrinsics, [](CameraLightFrame& f, double, double i) { f.intrinsics.fy = i; }},
      {"cx outside", LightFrameResult::BadIntrinsics, [](CameraLightFrame& f, double, double) { f.intrinsics.cx = kW + 5; }},
      {"cy NaN", LightFrameResult::BadIntrinsics, [](CameraLightFrame& f, double n, double) { f.intrinsics.cy = n; }},
      {"pose NaN", LightFrameResult::BadPose, [](CameraLightFrame& f, double n, double) { (*f.cameraToWorld)[3][0] = n; }},
      {"pose scaled", LightFrameResult::BadPose, [](CameraLightFrame& f, double, double) { (*f.cameraToWorld)[0] *= 2.0; }},
      {"pose mirrored", LightFrameResult::BadPose, [](CameraLightFrame& f, double, double) { (*f.cameraToWorld)[2] *= -1.0; }},
      {"pose zero", LightFrameResult::BadPose, [](CameraLightFrame& f, double, double) { f.cameraToWorld = glm::dmat4(0.0); }},
      {"time NaN", LightFrameResult::BadTime, [](CameraLightFrame& f, double n, double) { f.timeSeconds = n; }},
      {"time infinite", LightFrameResult::BadTime, [](CameraLightFrame& f, double, double i) { f.timeSeconds = i; }},
      {"exposure zero", LightFrameResult::BadExposure, [](CameraLightFrame& f, double, double) { f.exposure = 0; }},
      {"exposure negative", LightFrameResult::BadExposure, [](CameraLightFrame& f, double, double) { f.exposure = -1; }},
      {"exposure infinite", LightFrameResult::BadExposure, [](CameraLightFrame& f, double, double i) { f.exposure = i; }},
  };
  for (const Case& c : cases) {
    CameraLightFrame f = frameOf(bright, pitch(60.0), 1.0);
    c.spoil(f, nan, inf);
    EXPECT_EQ(estimator.addFrame(f), c.expect) << c.what;
    EXPECT_TRUE(sameBits(estimator.estimate(), before)) << c.what << ": the estimate changed";
    EXPECT_GT(std::strlen(ar::lightFrameResultName(c.expect)), 5u);
  }
  for (int i = 0; i < 9; ++i)
    for (int ch = 0; ch < 3; ++ch) EXPECT_TRUE(std::isfinite(estimator.estimate().radiance.c[static_cast<std::size_t>(i)][ch]));
  // Intrinsics from a bad field of view are zero, and so rejected.
  const ar::PinholeIntrinsics bad = ar::PinholeIntrinsics::fromFovY(kW, kH, 180.0);
  EXPECT_EQ(bad.fx, 0.0);
}

TEST(CameraLightEstimate, NothingSeenIsAZeroInvalidEstimate) {
  const CameraLightEstimator estimator;
  EXPECT_FALSE(estimator.estimate().valid);
  EXPECT_EQ(estimator.estimate().seenFraction, 0.0);
  EXPECT_EQ(estimator.estimate().radiance.bands, 3);
  for (int i = 0; i < 9; ++i) EXPECT_EQ(estimator.estimate().radiance.c[static_cast<std::size_t>(i)], glm::dvec3(0.0));
}

TEST(CameraLightEstimate, AConstantWorldGivesTheDcTermAlone) {
  // One colour everywhere the camera looks, at an exposure of 0.5: the radiance is the decoded
  // value / 0.5, the prior fills the rest with it, and E = pi L for every normal.
  CameraLightEstimator estimator;
  const auto rgb = solid(180, 120, 60);
  for (int k = 0; k < 12; ++k)
    ASSERT_EQ(estimator.addFrame(frameOf(rgb, yaw(30.0 * k) * pitch(20.0 * std::sin(k)), k / 30.0, 0.5)),
              LightFrameResult::Accepted);
  const ar::CameraLightEstimate& e = estimator.estimate();
  EXPECT_TRUE(e.valid);
  EXPECT_GT(e.seenFraction, 0.2);
  EXPECT_LT(e.seenFraction, 0.9);
  EXPECT_EQ(e.clippedFraction, 0.0);
  const glm::dvec3 radiance(linear(180) / 0.5, linear(120) / 0.5, linear(60) / 0.5);
  for (int i = 1; i < 9; ++i)
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(e.radiance.c[static_cast<std::size_t>(i)][ch], 0.0, 1e-6 * radiance[ch]) << i;  // float cells
  for (const glm::dvec3& n : {glm::dvec3(0, 1, 0), glm::dvec3(0, -1, 0), glm::normalize(glm::dvec3(1, 2, -3))}) {
    const glm::dvec3 irradiance = prt::irradiance(e.radiance, n);
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(irradiance[ch] / (std::numbers::pi * radiance[ch]), 1.0, 0.005);
  }
}

TEST(CameraLightEstimate, AFrameWithoutAPoseChangesNothing) {
  CameraLightEstimator estimator;
  const auto grey = solid(100, 100, 100), white = solid(240, 240, 240);
  ASSERT_EQ(estimator.addFrame(frameOf(grey, glm::dmat3(1.0), 0.0)), LightFrameResult::Accepted);
  const ar::CameraLightEstimate before = estimator.estimate();
  CameraLightFrame lost = frameOf(white, glm::dmat3(1.0), 0.5);
  lost.cameraToWorld.reset();
  EXPECT_EQ(estimator.addFrame(lost), LightFrameResult::NoPose);
  EXPECT_TRUE(sameBits(estimator.estimate(), before));
  EXPECT_EQ(estimator.estimate().framesAccepted, 1);
}

TEST(CameraLightEstimate, ImageAndPoseFollowTheWorldConvention) {
  // Identity pose: the camera looks along -Z with +Y up. The image's left half (toward -X) and
  // its top rows (toward +Y) are bright, the rest dark.
  std::vector<std::uint8_t> rgb = solid(20, 20, 20);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      if (x < kW / 2)
        for (int ch = 0; ch < 3; ++ch) rgb[static_cast<std::size_t>(3 * (y * kW + x) + ch)] = 230;
  CameraLightEstimator estimator;
  ASSERT_EQ(estimator.addFrame(frameOf(rgb, glm::dmat3(1.0), 0.0)), LightFrameResult::Accepted);
  const auto cellToward = [&](const glm::dvec3& d) {
    const glm::dvec2 uv = prt::EnvironmentMap::uv(d);
    return estimator.cell(static_cast<int>(uv.x * CameraLightEstimator::kColumns),
                          static_cast<int>(uv.y * CameraLightEstimator::kRows));
  };
  EXPECT_NEAR(cellToward({-0.3, 0.0, -1.0}).radiance.r, linear(230), 0.02);
  EXPECT_NEAR(cellToward({0.3, 0.0, -1.0}).radiance.r, linear(20), 0.01);
  EXPECT_EQ(cellToward({0.0, 0.0, 1.0}).coverage, 0.0f);  // behind the camera: not seen
  const glm::dvec3 main = ar::mainLightDirection(estimator.estimate().radiance);
  EXPECT_LT(main.x, -0.5);

  // Pitched up 90 degrees (the camera's -Z to world +Y): the view is the zenith cap, row 0.
  CameraLightEstimator up;
  ASSERT_EQ(up.addFrame(frameOf(solid(200, 200, 200), pitch(90.0), 0.0)), LightFrameResult::Accepted);
  float top = 0.0f, bottom = 0.0f;
  for (int c = 0; c < CameraLightEstimator::kColumns; ++c)
    top += up.cell(c, 0).coverage, bottom += up.cell(c, CameraLightEstimator::kRows - 1).coverage;
  EXPECT_GT(top / CameraLightEstimator::kColumns, 0.7f);
  EXPECT_EQ(bottom, 0.0f);
}

TEST(CameraLightEstimate, ClippedHighlightsAreExtrapolatedKeptAndReported) {
  CameraLightEstimator estimator;  // clippedFactor 2
  ASSERT_EQ(estimator.addFrame(frameOf(solid(255, 255, 255), glm::dmat3(1.0), 0.0)), LightFrameResult::Accepted);
  EXPECT_NEAR(estimator.cell(16, 8).radiance.g, 2.0, 1e-5);  // 2 x linear(255), straight ahead (-Z)
  EXPECT_GT(estimator.estimate().clippedFraction, 0.99);

  // Measured unclipped at a quarter of the exposure (radiance linear(200) / 0.25 = 2.3), then
  // clipped at exposure 1 (at least 1.0): the measurement stays.
  CameraLightEstimator bracketed;
  ASSERT_EQ(bracketed.addFrame(frameOf(solid(200, 200, 200), glm::dmat3(1.0), 0.0, 0.25)), LightFrameResult::Accepted);
  const float measured = bracketed.cell(16, 8).radiance.g;
  EXPECT_NEAR(measured, linear(200) / 0.25, 1e-4);
  ASSERT_EQ(bracketed.addFrame(frameOf(solid(255, 255, 255), glm::dmat3(1.0), 1.0, 1.0)), LightFrameResult::Accepted);
  EXPECT_EQ(bracketed.cell(16, 8).radiance.g, measured);
  // But a clipped view brighter than the stored value (the light came on) replaces it.
  ASSERT_EQ(bracketed.addFrame(frameOf(solid(255, 255, 255), glm::dmat3(1.0), 2.0, 4.0)), LightFrameResult::Accepted);
  ASSERT_EQ(bracketed.addFrame(frameOf(solid(255, 255, 255), glm::dmat3(1.0), 3.0, 0.1)), LightFrameResult::Accepted);
  EXPECT_NEAR(bracketed.cell(16, 8).radiance.g, 2.0 / 0.1, 1e-3);
}

TEST(CameraLightEstimate, ALampSwitchedOffIsFollowedInOneFrame) {
  // 30 fps, the camera still; the room at sRGB 200 for a second, then at 40: the next frame's
  // estimate is the dark room (N = 1), not a blend.
  CameraLightEstimator estimator;
  const auto lit = solid(200, 200, 200), dark = solid(40, 40, 40);
  int k = 0;
  for (; k < 30; ++k) ASSERT_EQ(estimator.addFrame(frameOf(lit, yaw(10.0), k / 30.0)), LightFrameResult::Accepted);
  EXPECT_NEAR(estimator.estimate().radiance.c[0].g / (linear(200) * 2.0 * std::sqrt(std::numbers::pi)), 1.0, 1e-4);
  ASSERT_EQ(estimator.addFrame(frameOf(dark, yaw(10.0), k / 30.0)), LightFrameResult::Accepted);
  EXPECT_NEAR(estimator.estimate().radiance.c[0].g / (linear(40) * 2.0 * std::sqrt(std::numbers::pi)), 1.0, 1e-3);
}

TEST(CameraLightEstimate, SmallFlickerIsSmoothedOverAFewFrames) {
  // Codes 120 and 124 alternating (3.5 % in linear, under the 25 % change threshold): the
  // estimate moves by at most about a third of that per frame (alpha = 1 - exp(-1/3) = 0.28).
  CameraLightEstimator estimator;
  const auto a = solid(120, 120, 120), b = solid(124, 124, 124);
  double last = 0.0, largestStep = 0.0;
  for (int k = 0; k < 60; ++k) {
    ASSERT_EQ(estimator.addFrame(frameOf(k % 2 ? b : a, glm::dmat3(1.0), k / 30.0)), LightFrameResult::Accepted);
    const double dc = estimator.estimate().radiance.c[0].g;
    if (k > 10) largestStep = std::max(largestStep, std::abs(dc - last) / dc);
    last = dc;
  }
  const double input = (linear(124) - linear(120)) / linear(120);
  EXPECT_LT(largestStep, 0.35 * input);
  EXPECT_GT(largestStep, 0.0);
}

TEST(CameraLightEstimate, TheSameFramesGiveTheSameBits) {
  const auto run = [] {
    CameraLightEstimator estimator;
    std::vector<std::uint8_t> rgb(static_cast<std::size_t>(kW) * kH * 3);
    for (int k = 0; k < 40; ++k) {
      for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<std::uint8_t>((i * 7 + static_cast<std::size_t>(k) * 13) % 256);
      (void)estimator.addFrame(frameOf(rgb, yaw(9.0 * k) * pitch(25.0 * std::sin(0.3 * k)), k / 30.0, 1.0 + 0.01 * k));
    }
    return estimator.estimate();
  };
  const ar::CameraLightEstimate a = run(), b = run();
  EXPECT_TRUE(sameBits(a, b));
  EXPECT_GT(a.seenFraction, 0.3);
}

TEST(CameraLightEstimate, ResetForgetsEverything) {
  CameraLightEstimator estimator;
  ASSERT_EQ(estimator.addFrame(frameOf(solid(90, 90, 90), glm::dmat3(1.0), 0.0)), LightFrameResult::Accepted);
  estimator.reset();
  EXPECT_TRUE(sameBits(estimator.estimate(), CameraLightEstimator().estimate()));
}

TEST(CameraLightEstimate, CameraMatchGivesWhatTheCameraShowsAWhiteCard) {
  // A constant world seen at exposure 0.5 with code 150: a white matte card in it has the
  // world's radiance, so the camera records linear(150) for it. Lit by the matched estimate at
  // that exposure, a white Lambertian surface shades to E / pi = linear(150).
  CameraLightEstimator estimator;
  ASSERT_EQ(estimator.addFrame(frameOf(solid(150, 150, 150), glm::dmat3(1.0), 0.0, 0.5)), LightFrameResult::Accepted);
  const prt::ShCoefficients matched = ar::cameraMatchedRadiance(estimator.estimate().radiance, 0.5);
  for (const glm::dvec3& n : {glm::dvec3(0, 1, 0), glm::dvec3(1, 0, 0), glm::dvec3(0, 0, -1)})
    EXPECT_NEAR(prt::irradiance(matched, n).g / std::numbers::pi, linear(150), 1e-3 * linear(150));
  // Bad exposures count as 1.
  const prt::ShCoefficients same = ar::cameraMatchedRadiance(estimator.estimate().radiance, std::nan(""));
  EXPECT_EQ(same.c[0], estimator.estimate().radiance.c[0]);

  // Gray world: a tinted world's mean becomes neutral at the same luminance.
  CameraLightEstimator tinted;
  ASSERT_EQ(tinted.addFrame(frameOf(solid(200, 150, 90), glm::dmat3(1.0), 0.0)), LightFrameResult::Accepted);
  const prt::ShCoefficients& raw = tinted.estimate().radiance;
  const prt::ShCoefficients neutral = ar::cameraMatchedRadiance(raw, 1.0, ar::WhiteBalance::GrayWorld);
  const glm::dvec3 luma(0.2126, 0.7152, 0.0722);
  EXPECT_NEAR(neutral.c[0].r / neutral.c[0].g, 1.0, 1e-9);
  EXPECT_NEAR(neutral.c[0].b / neutral.c[0].g, 1.0, 1e-9);
  EXPECT_NEAR(glm::dot(neutral.c[0], luma), glm::dot(raw.c[0], luma), 1e-9);
}
