// The environment light from the camera's frames (camera_light_estimate.hpp says what and why).
#include "marionette_ar/camera_light_estimate.hpp"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "marionette/prt/environment_map.hpp"
#include "marionette/prt/spherical_harmonics.hpp"

namespace marionette::ar {
namespace {

constexpr int kBands = 3;
constexpr int kMaxSamples = 64, kMaxPixelsPerSample = 8;
const glm::dvec3 kLuma(0.2126, 0.7152, 0.0722);  // Rec. 709

double luma(const glm::dvec3& c) noexcept { return glm::dot(c, kLuma); }

float srgbToLinear(int code) noexcept {
  const double c = code / 255.0;
  return static_cast<float>(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
}

// A setting outside its range takes the nearest allowed value (non-finite: the default).
double within(double value, double lowest, double highest, double fallback) noexcept {
  return std::isfinite(value) ? std::clamp(value, lowest, highest) : fallback;
}
CameraLightSettings sanitized(CameraLightSettings s) noexcept {
  const CameraLightSettings d;
  s.samplesX = std::clamp(s.samplesX, 1, kMaxSamples);
  s.samplesY = std::clamp(s.samplesY, 1, kMaxSamples);
  s.pixelsPerSample = std::clamp(s.pixelsPerSample, 1, kMaxPixelsPerSample);
  s.noiseTimeConstant = within(s.noiseTimeConstant, 1e-6, 1e6, d.noiseTimeConstant);
  s.changeThreshold = within(s.changeThreshold, 0.0, 1e6, d.changeThreshold);
  s.darkNoiseFloor = within(s.darkNoiseFloor, 1e-6, 1.0, d.darkNoiseFloor);
  s.saturationLevel = std::clamp(s.saturationLevel, 1, 255);
  s.clippedFactor = within(s.clippedFactor, 1.0, 1e6, d.clippedFactor);
  s.minRowCoverage = within(s.minRowCoverage, 0.0, 1.0, d.minRowCoverage);
  return s;
}

bool isRotation(const glm::dmat4& m) noexcept {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  const glm::dmat3 rot(m);
  const glm::dmat3 gram = glm::transpose(rot) * rot;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r)
      if (std::abs(gram[c][r] - (c == r ? 1.0 : 0.0)) > 1e-3) return false;
  return glm::determinant(rot) > 0.0;
}

// Pixel k of the sample grid's n * s positions along an axis of `size` pixels: sample i's
// sub-pixel a sits at the centre of the a-th of s equal parts of the sample's block.
void subPixels(int size, int samples, int perSample, std::array<int, 64 * 8>& out) noexcept {
  const double block = static_cast<double>(size) / samples;
  for (int i = 0; i < samples; ++i)
    for (int a = 0; a < perSample; ++a) {
      const double x = (i + (a + 0.5) / perSample) * block - 0.5;
      out[static_cast<std::size_t>(i * perSample + a)] = std::clamp(static_cast<int>(std::lround(x)), 0, size - 1);
    }
}

}  // namespace

PinholeIntrinsics PinholeIntrinsics::fromFovY(int width, int height, double fovYDegrees) noexcept {
  PinholeIntrinsics k;
  if (width <= 0 || height <= 0 || !(fovYDegrees > 0.0 && fovYDegrees < 180.0)) return k;  // zero: rejected
  k.fy = 0.5 * height / std::tan(fovYDegrees * std::numbers::pi / 360.0);
  k.fx = k.fy;
  k.cx = 0.5 * (width - 1);
  k.cy = 0.5 * (height - 1);
  return k;
}

const char* lightFrameResultName(LightFrameResult result) noexcept {
  switch (result) {
    case LightFrameResult::Accepted: return "accepted";
    case LightFrameResult::NoPose: return "no pose (tracking lost)";
    case LightFrameResult::EmptyImage: return "empty image (no pixels, a size <= 0 or a stride shorter than a row)";
    case LightFrameResult::BadIntrinsics: return "bad intrinsics (a focal length <= 0 or not finite, or the principal point outside the image)";
    case LightFrameResult::BadPose: return "bad pose (not finite, or its rotation part is not a rotation)";
    case LightFrameResult::BadTime: return "bad time (not finite)";
    case LightFrameResult::BadExposure: return "bad exposure (<= 0 or not finite)";
  }
  return "unknown";
}

CameraLightEstimator::CameraLightEstimator(const CameraLightSettings& settings) : settings_(sanitized(settings)) {
  for (int i = 0; i < 256; ++i) linear_[static_cast<std::size_t>(i)] = srgbToLinear(i);
  // The grid is a 32 x 16 lat-long map: its cells' solid angles and exact basis integrals are
  // the projection's (prt::pixelBasisIntegrals), computed once.
  const prt::EnvironmentMap grid(kColumns, kRows, std::vector<float>(static_cast<std::size_t>(kCells) * 3, 0.0f));
  for (int r = 0; r < kRows; ++r) {
    cellSolidAngle_[static_cast<std::size_t>(r)] = grid.texelSolidAngle(r);
    for (int c = 0; c < kColumns; ++c)
      cellIntegrals_[static_cast<std::size_t>(r * kColumns + c)] = prt::pixelBasisIntegrals(grid, c, r, kBands);
  }
  reset();
}

void CameraLightEstimator::reset() noexcept {
  cells_.fill(Cell{});
  completed_.fill(glm::dvec3(0.0));
  estimate_ = CameraLightEstimate{};
  estimate_.radiance.bands = kBands;
}

LightFrameResult CameraLightEstimator::addFrame(const CameraLightFrame& frame) noexcept {
  if (!frame.cameraToWorld) return LightFrameResult::NoPose;
  const CameraImageView& image = frame.image;
  if (image.rgb == nullptr || image.width <= 0 || image.height <= 0) return LightFrameResult::EmptyImage;
  const std::size_t rowBytes = static_cast<std::size_t>(image.width) * 3;
  const std::size_t stride = image.strideBytes == 0 ? rowBytes : image.strideBytes;
  if (stride < rowBytes) return LightFrameResult::EmptyImage;
  const PinholeIntrinsics& k = frame.intrinsics;
  if (!(std::isfinite(k.fx) && std::isfinite(k.fy) && k.fx > 0.0 && k.fy > 0.0) ||
      !(k.cx >= -0.5 && k.cx <= image.width - 0.5 && k.cy >= -0.5 && k.cy <= image.height - 0.5))
    return LightFrameResult::BadIntrinsics;
  if (!isRotation(*frame.cameraToWorld)) return LightFrameResult::BadPose;
  if (!std::isfinite(frame.timeSeconds)) return LightFrameResult::BadTime;
  if (!(std::isfinite(frame.exposure) && frame.exposure > 0.0)) return LightFrameResult::BadExposure;

  const int sx = settings_.samplesX, sy = settings_.samplesY, per = settings_.pixelsPerSample;
  subPixels(image.width, sx, per, columnPixels_);
  subPixels(image.height, sy, per, rowPixels_);
  frame_.fill(FrameCell{});
  const glm::dmat3 rotation(*frame.cameraToWorld);
  // A sample stands for its block of the image: (W / sx) x (H / sy) pixels, each 1 / (fx fy) of
  // the image plane at unit depth, so its solid angle is that area times cos^3 of its off-axis
  // angle (1 / |ray|^3 for the ray (x, y, 1)).
  const double blockW = static_cast<double>(image.width) / sx, blockH = static_cast<double>(image.height) / sy;
  const double blockArea = blockW * blockH / (k.fx * k.fy);
  const int saturation = settings_.saturationLevel;
  const float factor = static_cast<float>(settings_.clippedFactor);
  const float perPixel = 1.0f / static_cast<float>(per * per);
  for (int j = 0; j < sy; ++j) {
    const double y = ((j + 0.5) * blockH - 0.5 - k.cy) / k.fy;
    for (int i = 0; i < sx; ++i) {
      const double x = ((i + 0.5) * blockW - 0.5 - k.cx) / k.fx;
      const glm::dvec3 ray(x, -y, -1.0);  // OpenCV's pixel to the OpenGL camera: y up, looking along -Z
      const double length = glm::length(ray);
      const glm::dvec3 direction = rotation * (ray / length);
      const glm::dvec2 uv = prt::EnvironmentMap::uv(direction);
      const int column = std::clamp(static_cast<int>(uv.x * kColumns), 0, kColumns - 1);
      const int row = std::clamp(static_cast<int>(uv.y * kRows), 0, kRows - 1);
      glm::vec3 sum(0.0f), lower(0.0f);
      int clipped = 0;
      for (int b = 0; b < per; ++b) {
        const std::uint8_t* line = image.rgb + static_cast<std::size_t>(rowPixels_[static_cast<std::size_t>(j * per + b)]) * stride;
        for (int a = 0; a < per; ++a) {
          const std::uint8_t* p = line + 3 * static_cast<std::size_t>(columnPixels_[static_cast<std::size_t>(i * per + a)]);
          const glm::vec3 value(linear_[p[0]], linear_[p[1]], linear_[p[2]]);
          lower += value;
          if (p[0] >= saturation || p[1] >= saturation || p[2] >= saturation) {
            ++clipped;
            for (int ch = 0; ch < 3; ++ch) sum[ch] += p[ch] >= saturation ? factor * value[ch] : value[ch];
          } else {
            sum += value;
          }
        }
      }
      const float solidAngle = static_cast<float>(blockArea / (length * length * length));
      FrameCell& cell = frame_[static_cast<std::size_t>(row * kColumns + column)];
      cell.sum += sum * (solidAngle * perPixel);
      cell.lower += lower * (solidAngle * perPixel);
      cell.weight += solidAngle;
      cell.clippedWeight += solidAngle * static_cast<float>(clipped) * perPixel;
    }
  }
  updateCells(frame.timeSeconds, frame.exposure);
  complete();
  project();
  ++estimate_.framesAccepted;
  estimate_.valid = true;
  return LightFrameResult::Accepted;
}

void CameraLightEstimator::updateCells(double time, double exposure) noexcept {
  const double floor = settings_.darkNoiseFloor / exposure;
  const float clipLevel = static_cast<float>(linear_[static_cast<std::size_t>(settings_.saturationLevel)] / exposure);
  for (int index = 0; index < kCells; ++index) {
    const FrameCell& seen = frame_[static_cast<std::size_t>(index)];
    if (seen.weight <= 0.0f) continue;
    Cell& cell = cells_[static_cast<std::size_t>(index)];
    const double cellAngle = cellSolidAngle_[static_cast<std::size_t>(index / kColumns)];
    const float coverage = static_cast<float>(std::min(1.0, seen.weight / cellAngle));
    const glm::dvec3 observed = glm::dvec3(seen.sum) / (static_cast<double>(seen.weight) * exposure);
    const glm::dvec3 bound = glm::dvec3(seen.lower) / (static_cast<double>(seen.weight) * exposure);
    const float clippedShare = seen.clippedWeight / seen.weight;
    if (cell.coverage <= 0.0f) {  // first seen
      cell.radiance = glm::vec3(observed);
      cell.coverage = coverage;
      cell.clipped = clippedShare;
      cell.clipLevel = clipLevel;
      cell.lastSeen = time;
      continue;
    }
    const double dt = std::max(0.0, time - cell.lastSeen);
    cell.lastSeen = time;
    cell.coverage = std::max(cell.coverage, coverage);
    // How much of what the cell holds this view sees again: 1 when it sees as much as ever (a
    // still camera replaces its partly seen cells as fully as the others).
    const double share = coverage / cell.coverage;
    // A clipped view says "at least `bound`": a value measured at a darker exposure (a higher
    // clip level) that is consistent with it stays.
    const glm::dvec3 stored(cell.radiance);
    if (clippedShare > 0.0f && cell.clipLevel > clipLevel &&
        luma(stored) >= luma(bound) * (1.0 - settings_.changeThreshold))
      continue;
    // Below the noise floor an observation says "at most the floor" (a frame exposed darker, as a
    // bracketing camera takes, records a dim region as a few codes): what the cell holds stays
    // when it is within that bound; a cell brighter than it (a lamp switched off) takes it.
    if (luma(observed) < floor && luma(stored) <= floor) continue;
    double change = 0.0;
    for (int ch = 0; ch < 3; ++ch)
      change = std::max(change, std::abs(observed[ch] - stored[ch]) / std::max({observed[ch], stored[ch], floor}));
    const double alpha = change > settings_.changeThreshold
                             ? share
                             : share * (1.0 - std::exp(-dt / settings_.noiseTimeConstant));
    cell.radiance = glm::vec3(stored + alpha * (observed - stored));
    cell.clipped += static_cast<float>(alpha) * (clippedShare - cell.clipped);
    if (alpha >= 0.5) cell.clipLevel = clipLevel;  // the new view now dominates the cell
  }
}

void CameraLightEstimator::complete() noexcept {
  std::array<glm::dvec3, kRows> rowSum{};
  std::array<double, kRows> rowWeight{}, rowCoverage{};
  glm::dvec3 totalSum(0.0);
  double totalWeight = 0.0, clippedWeight = 0.0;
  for (int r = 0; r < kRows; ++r) {
    const double angle = cellSolidAngle_[static_cast<std::size_t>(r)];
    for (int c = 0; c < kColumns; ++c) {
      const Cell& cell = cells_[static_cast<std::size_t>(r * kColumns + c)];
      const double w = angle * cell.coverage;
      rowSum[static_cast<std::size_t>(r)] += w * glm::dvec3(cell.radiance);
      rowWeight[static_cast<std::size_t>(r)] += w;
      clippedWeight += w * cell.clipped;
    }
    totalSum += rowSum[static_cast<std::size_t>(r)];
    totalWeight += rowWeight[static_cast<std::size_t>(r)];
    rowCoverage[static_cast<std::size_t>(r)] = rowWeight[static_cast<std::size_t>(r)] / (angle * kColumns);
  }
  estimate_.seenFraction = std::min(1.0, totalWeight / (4.0 * std::numbers::pi));
  estimate_.clippedFraction = totalWeight > 0.0 ? clippedWeight / totalWeight : 0.0;
  if (totalWeight <= 0.0) {
    completed_.fill(glm::dvec3(0.0));
    return;
  }
  const auto qualifies = [&](int r) {
    return r >= 0 && r < kRows && rowWeight[static_cast<std::size_t>(r)] > 0.0 &&
           rowCoverage[static_cast<std::size_t>(r)] >= settings_.minRowCoverage;
  };
  const auto mean = [&](int r) { return rowSum[static_cast<std::size_t>(r)] / rowWeight[static_cast<std::size_t>(r)]; };
  for (int r = 0; r < kRows; ++r) {
    // The row's prior: its own mean, else the nearest row's that is seen enough (the two
    // nearest, averaged, on a tie), else the mean of everything seen.
    glm::dvec3 prior = totalSum / totalWeight;
    for (int d = 0; d < kRows; ++d) {
      const bool below = qualifies(r + d), above = d > 0 && qualifies(r - d);
      if (below && above) prior = 0.5 * (mean(r + d) + mean(r - d));
      else if (below) prior = mean(r + d);
      else if (above) prior = mean(r - d);
      if (below || above) break;
    }
    for (int c = 0; c < kColumns; ++c) {
      const std::size_t index = static_cast<std::size_t>(r * kColumns + c);
      const Cell& cell = cells_[index];
      const double coverage = cell.coverage;
      completed_[index] = coverage * glm::dvec3(cell.radiance) + (1.0 - coverage) * prior;
    }
  }
}

void CameraLightEstimator::project() noexcept {
  prt::ShCoefficients& sh = estimate_.radiance;
  sh.bands = kBands;
  sh.c.fill(glm::dvec3(0.0));
  const int count = prt::shCount(kBands);
  for (int index = 0; index < kCells; ++index) {
    const glm::dvec3& radiance = completed_[static_cast<std::size_t>(index)];
    const prt::ShBasis& integral = cellIntegrals_[static_cast<std::size_t>(index)];
    for (int i = 0; i < count; ++i) sh.c[static_cast<std::size_t>(i)] += radiance * integral[static_cast<std::size_t>(i)];
  }
}

glm::dvec3 mainLightDirection(const prt::ShCoefficients& coefficients) noexcept {
  // Band 1 in index order is (x, y, z): Y_1 = 0.488603 x, Y_2 = 0.488603 y, Y_3 = 0.488603 z.
  const glm::dvec3 v(luma(coefficients.c[1]), luma(coefficients.c[2]), luma(coefficients.c[3]));
  const double length = glm::length(v);
  return length > 0.0 && std::isfinite(length) ? v / length : glm::dvec3(0.0);
}

prt::ShCoefficients cameraMatchedRadiance(const prt::ShCoefficients& estimate, double exposure,
                                          WhiteBalance whiteBalance) noexcept {
  if (!(std::isfinite(exposure) && exposure > 0.0)) exposure = 1.0;
  glm::dvec3 gain(exposure);
  if (whiteBalance == WhiteBalance::GrayWorld) {
    const glm::dvec3& dc = estimate.c[0];
    const double y = luma(dc);
    if (y > 0.0 && std::isfinite(y))
      for (int ch = 0; ch < 3; ++ch) gain[ch] *= dc[ch] > 0.0 ? std::clamp(y / dc[ch], 0.25, 4.0) : 4.0;
  }
  prt::ShCoefficients out = estimate;
  for (auto& c : out.c) c *= gain;
  return out;
}

}  // namespace marionette::ar
