// A hand-held camera looking around inside a light probe, for the camera light estimate's tests
// and its accuracy table (tests/accuracy/camera_light_estimate_error.cpp, docs/accuracy.md
// "Light estimated from the camera").
//
// The camera: a pinhole of 640 x 480 pixels with a 60-degree horizontal field of view (OpenCV's
// pixel convention), each pixel the probe's bilinear radiance along the ray through its centre,
// times the exposure, plus a small deterministic sensor noise (uniform, sigma 0.002 linear),
// clipped at 1 and quantised to sRGB 8 bits: what a webcam gives. Its exposure meters like an
// auto-exposing camera: the median (or the mean) luminance over a 40 x 30 grid of the view is
// put at mid grey (0.18), and the exposure follows that target in log space with a time
// constant of 0.25 s (the first frame starts metered); or it is locked at 1.
//
// compressIntoCameraRange: a probe squeezed into what an 8-bit camera holds (L / (1 + L) per
// channel, seen at a locked exposure of 1): the estimator's own error, without clipped highlights.
//
// The paths: the yaw eases from yawFrom to yawTo (a smooth start and stop), the pitch swings
// between -30 and +40 degrees (5 + 35 sin(2 pi t / 3.2 s)), with a hand's tremor (about 1 degree
// of yaw and pitch, 3 degrees of roll, slow sines). Yaw 0 looks along -Z; positive turns toward -X.
#pragma once
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "marionette/prt/environment_map.hpp"
#include "marionette/prt/sh_lighting.hpp"
#include "marionette_ar/camera_light_estimate.hpp"

namespace marionette::test {

struct SweepPath {
  const char* name;
  double yawFromDegrees, yawToDegrees;
  double seconds;
};
inline constexpr SweepPath kSweepPaths[] = {
    {"narrow pan", -30.0, 30.0, 4.0}, {"half turn", -90.0, 90.0, 8.0}, {"full turn", 0.0, 360.0, 12.0}};

inline glm::dmat3 rotationAbout(const glm::dvec3& axis, double degrees) {
  const double a = degrees * std::numbers::pi / 180.0, c = std::cos(a), s = std::sin(a);
  const glm::dvec3 u = glm::normalize(axis);
  glm::dmat3 r(c);
  r += (1.0 - c) * glm::dmat3(u.x * u, u.y * u, u.z * u);  // outer product, column by column
  r += s * glm::dmat3(glm::dvec3(0, u.z, -u.y), glm::dvec3(-u.z, 0, u.x), glm::dvec3(u.y, -u.x, 0));
  return r;
}

// Camera-to-world rotation at time t (seconds) of a path.
inline glm::dmat3 sweepOrientation(const SweepPath& path, double t) {
  const double tau = 2.0 * std::numbers::pi;
  const double ease = 0.5 * (1.0 - std::cos(std::numbers::pi * std::clamp(t / path.seconds, 0.0, 1.0)));
  const double yaw = path.yawFromDegrees + (path.yawToDegrees - path.yawFromDegrees) * ease +
                     1.0 * std::sin(tau * 0.7 * t + 0.3);
  const double pitch = 5.0 + 35.0 * std::sin(tau * t / 3.2) + 0.8 * std::sin(tau * 1.1 * t + 1.0);
  const double roll = 3.0 * std::sin(tau * 0.4 * t + 2.0);
  return rotationAbout({0, 1, 0}, yaw) * rotationAbout({1, 0, 0}, pitch) * rotationAbout({0, 0, 1}, roll);
}

enum class Metering { Median, Mean, Locked };
[[nodiscard]] inline const char* meteringName(Metering m) {
  return m == Metering::Median ? "median" : m == Metering::Mean ? "mean" : "locked";
}

inline prt::EnvironmentMap compressIntoCameraRange(prt::EnvironmentMap map) {
  for (float& v : map.pixels()) v = v / (1.0f + v);
  return map;
}

class ProbeCamera {
 public:
  static constexpr double kMidGrey = 0.18, kExposureSeconds = 0.25, kNoise = 0.002;

  explicit ProbeCamera(const prt::EnvironmentMap& probe, Metering metering = Metering::Median, int width = 640,
                       int height = 480, double hfovDegrees = 60.0)
      : probe_(probe), metering_(metering), width_(width), height_(height) {
    intrinsics_.fx = intrinsics_.fy = 0.5 * width / std::tan(hfovDegrees * std::numbers::pi / 360.0);
    intrinsics_.cx = 0.5 * (width - 1);
    intrinsics_.cy = 0.5 * (height - 1);
    rays_.reserve(static_cast<std::size_t>(width) * height);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        rays_.push_back(glm::vec3(glm::normalize(
            glm::dvec3((x - intrinsics_.cx) / intrinsics_.fx, -(y - intrinsics_.cy) / intrinsics_.fy, -1.0))));
    encode_.resize(kEncodeSteps + 1);
    for (int i = 0; i <= kEncodeSteps; ++i) {
      const double v = static_cast<double>(i) / kEncodeSteps;
      const double s = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
      encode_[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(std::lround(255.0 * s));
    }
  }

  [[nodiscard]] const ar::PinholeIntrinsics& intrinsics() const noexcept { return intrinsics_; }
  [[nodiscard]] int width() const noexcept { return width_; }
  [[nodiscard]] int height() const noexcept { return height_; }

  // The exposure that puts the view's median (mean) luminance (40 x 30 grid) at mid grey; 1 when locked.
  [[nodiscard]] double meteredExposure(const glm::dmat3& cameraToWorld) const {
    if (metering_ == Metering::Locked) return 1.0;
    std::vector<double> luminance;
    luminance.reserve(40 * 30);
    for (int j = 0; j < 30; ++j)
      for (int i = 0; i < 40; ++i) {
        const int x = (2 * i + 1) * width_ / 80, y = (2 * j + 1) * height_ / 60;
        const glm::vec3 l = probe_.sample(cameraToWorld * glm::dvec3(rays_[static_cast<std::size_t>(y * width_ + x)]));
        luminance.push_back(0.2126 * l.r + 0.7152 * l.g + 0.0722 * l.b);
      }
    double level = 0.0;
    if (metering_ == Metering::Mean) {
      for (double l : luminance) level += l / static_cast<double>(luminance.size());
    } else {
      std::nth_element(luminance.begin(), luminance.begin() + luminance.size() / 2, luminance.end());
      level = luminance[luminance.size() / 2];
    }
    return kMidGrey / std::max(level, 1e-6);
  }

  // One RGB8 frame (rows from the top, no padding) of the view at this exposure. `frame` seeds
  // the noise.
  void render(const glm::dmat3& cameraToWorld, double exposure, std::uint64_t frame, std::vector<std::uint8_t>& rgb) const {
    rgb.resize(static_cast<std::size_t>(width_) * height_ * 3);
    std::uint64_t state = 0x9E3779B97F4A7C15ull * (frame + 1);
    const glm::mat3 rotation(cameraToWorld);
    const float gain = static_cast<float>(exposure), noise = static_cast<float>(kNoise * 1.7320508);
    for (std::size_t p = 0; p < rays_.size(); ++p) {
      const glm::vec3 l = bilinear(rotation * rays_[p]);
      for (int c = 0; c < 3; ++c) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;  // LCG: a uniform in [-1, 1)
        const float u = static_cast<float>(state >> 40) * (2.0f / 16777216.0f) - 1.0f;
        const float v = std::clamp(gain * l[c] + noise * u, 0.0f, 1.0f);  // sigma kNoise
        rgb[3 * p + static_cast<std::size_t>(c)] = encode_[static_cast<std::size_t>(v * kEncodeSteps + 0.5f)];
      }
    }
  }

 private:
  static constexpr int kEncodeSteps = 1 << 16;

  // prt::EnvironmentMap::sample in float (the same lookup: bilinear between pixel centres,
  // repeating in u, clamped in v), three times faster for the 307200 rays of a frame.
  [[nodiscard]] glm::vec3 bilinear(const glm::vec3& d) const noexcept {
    constexpr float kInvTwoPi = 0.15915494f, kInvPi = 0.31830989f;
    const int w = probe_.width(), h = probe_.height();
    const float u = 0.5f + std::atan2(d.x, -d.z) * kInvTwoPi;
    const float v = std::acos(std::clamp(d.y / std::sqrt(glm::dot(d, d)), -1.0f, 1.0f)) * kInvPi;
    const float x = u * static_cast<float>(w) - 0.5f;
    const float y = std::clamp(v * static_cast<float>(h) - 0.5f, 0.0f, static_cast<float>(h - 1));
    const float fx = std::floor(x), fy = std::floor(y), ax = x - fx, ay = y - fy;
    const int c0 = ((static_cast<int>(fx) % w) + w) % w, c1 = (c0 + 1) % w;
    const int r0 = static_cast<int>(fy), r1 = std::min(r0 + 1, h - 1);
    const glm::vec3 top = probe_.texel(c0, r0) * (1.0f - ax) + probe_.texel(c1, r0) * ax;
    const glm::vec3 bottom = probe_.texel(c0, r1) * (1.0f - ax) + probe_.texel(c1, r1) * ax;
    return top * (1.0f - ay) + bottom * ay;
  }

  const prt::EnvironmentMap& probe_;
  Metering metering_;
  int width_, height_;
  ar::PinholeIntrinsics intrinsics_;
  std::vector<glm::vec3> rays_;
  std::vector<std::uint8_t> encode_;
};

// One path through the estimator at `fps`, the auto-exposure passed on as relative exposures
// (E_k / E_0): the estimate comes out in the first frame's camera units, so
// estimate / referenceExposure is in the probe's units.
struct SweepRun {
  prt::ShCoefficients probeUnits;  // the estimate divided by the first frame's exposure
  ar::CameraLightEstimate estimate;
  double referenceExposure = 1.0;
  std::vector<double> frameMilliseconds;  // addFrame's cost, per frame
  int frames = 0;
};
// `bracketStops` > 0: the camera brackets, as HDR video does: of every three frames the second is
// exposed that many stops darker than metered, the third twice that (what a camera API lets an app
// ask for); the exposure is reported with each frame.
inline SweepRun runSweep(const ProbeCamera& camera, const SweepPath& path, double fps, ar::CameraLightEstimator& estimator,
                         int bracketStops = 0) {
  SweepRun run;
  std::vector<std::uint8_t> rgb;
  const int frames = static_cast<int>(std::lround(path.seconds * fps)) + 1;
  double logExposure = 0.0;
  for (int k = 0; k < frames; ++k) {
    const double t = k / fps;
    const glm::dmat3 rotation = sweepOrientation(path, t);
    const double target = std::log(camera.meteredExposure(rotation));
    logExposure = k == 0 ? target
                         : logExposure + (1.0 - std::exp(-1.0 / (fps * ProbeCamera::kExposureSeconds))) * (target - logExposure);
    const double exposure = std::exp(logExposure) / std::exp2(static_cast<double>(bracketStops * (k % 3)));
    if (k == 0) run.referenceExposure = exposure;
    camera.render(rotation, exposure, static_cast<std::uint64_t>(k), rgb);
    ar::CameraLightFrame frame;
    frame.image = {rgb.data(), camera.width(), camera.height(), 0};
    frame.cameraToWorld = glm::dmat4(rotation);
    frame.intrinsics = camera.intrinsics();
    frame.timeSeconds = t;
    frame.exposure = exposure / run.referenceExposure;
    const auto t0 = std::chrono::steady_clock::now();
    const ar::LightFrameResult result = estimator.addFrame(frame);
    run.frameMilliseconds.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    if (result == ar::LightFrameResult::Accepted) ++run.frames;
  }
  run.estimate = estimator.estimate();
  run.probeUnits = ar::cameraMatchedRadiance(run.estimate.radiance, 1.0 / run.referenceExposure);
  return run;
}

// Estimated irradiance against the probe's own 9-coefficient irradiance over unit normals.
struct LightError {
  double meanOfMeanE = 0, maxOfMeanE = 0;      // per normal: max over R, G, B of |dE| / (the probe's mean E)
  double meanPointwise = 0, maxPointwise = 0;  // per normal: max over R, G, B of |dE| / E (prt::irradianceError)
  double meanShape = 0;         // meanOfMeanE after scaling the estimate to the probe's mean luminance
  double directionDegrees = 0;  // between the main light directions (band 1 of the luminance)
};
inline LightError compareIrradiance(const prt::ShCoefficients& estimate, const prt::ShCoefficients& truth,
                                    const std::vector<glm::dvec3>& normals) {
  std::vector<glm::dvec3> approx, reference;
  glm::dvec3 mean(0.0);
  for (const glm::dvec3& n : normals) {
    approx.push_back(prt::irradiance(estimate, n));
    reference.push_back(prt::irradiance(truth, n));
    mean += reference.back() / static_cast<double>(normals.size());
  }
  const glm::dvec3 luma(0.2126, 0.7152, 0.0722);
  const double estimatedDc = glm::dot(estimate.c[0], luma);
  const double scale = estimatedDc > 0.0 ? glm::dot(truth.c[0], luma) / estimatedDc : 1.0;
  LightError e;
  for (std::size_t i = 0; i < normals.size(); ++i) {
    double worst = 0.0, worstShape = 0.0;
    for (int c = 0; c < 3; ++c) {
      worst = std::max(worst, std::abs(approx[i][c] - reference[i][c]) / mean[c]);
      worstShape = std::max(worstShape, std::abs(scale * approx[i][c] - reference[i][c]) / mean[c]);
    }
    e.meanOfMeanE += worst / static_cast<double>(normals.size());
    e.maxOfMeanE = std::max(e.maxOfMeanE, worst);
    e.meanShape += worstShape / static_cast<double>(normals.size());
  }
  const prt::IrradianceError pointwise = prt::irradianceError(approx, reference);
  e.meanPointwise = pointwise.mean;
  e.maxPointwise = pointwise.max;
  const glm::dvec3 a = ar::mainLightDirection(estimate), b = ar::mainLightDirection(truth);
  e.directionDegrees = std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)) * 180.0 / std::numbers::pi;
  return e;
}

}  // namespace marionette::test
