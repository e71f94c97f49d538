// The occlusion mask's state and the pieces its steps share (a private header of
// examples/ar/tracking/src; the method: target_occlusion.hpp). target_occlusion.cpp holds the
// public API, the grid, the geometry, the frame and reference reading and a frame's steps in
// order; occlusion_alignment.cpp the pose's residual shift and the blur matching (steps 2 and 3);
// occlusion_verdict.cpp the per-pixel verdict and the cleaning (steps 4 and 5).
#pragma once
#include "marionette_ar/tracking/target_occlusion.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include <opencv2/core.hpp>

namespace marionette::ar::occlusion_detail {

inline constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
inline constexpr int kParts = 3;          // the shift field's parts across and down the target's image
inline constexpr float kInside = 0.99f;   // coverage that counts a mask pixel as wholly on the target
inline constexpr int kMaxShifts = 7 * 7;  // (2 searchRadius + 1)^2 at searchRadius 3
// Past this box (mask pixels), the shift search and the photometric fit take every other pixel
// both ways.
inline constexpr long kDenseBoxPixels = 4000;
inline constexpr float kGreyBias = 128.0f;  // values centred before the window sums (float precision)

// A frame block this bright or dark is clipped (over- or under-exposed): it says nothing about
// what is there, and is left out of the comparison.
inline constexpr float kBright = 250.0f, kDark = 3.0f;
inline bool clipped(float frame) noexcept { return frame >= kBright || frame <= kDark; }

inline float clamp01(float v) noexcept { return v < 0.0f ? 0.0f : v > 1.0f ? 1.0f : v; }

struct Box {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // [x0, x1) x [y0, y1)
  [[nodiscard]] bool empty() const noexcept { return x0 >= x1 || y0 >= y1; }
  [[nodiscard]] Box grown(int m, int w, int h) const noexcept {
    return {std::max(0, x0 - m), std::max(0, y0 - m), std::min(w, x1 + m), std::min(h, y1 + m)};
  }
};

// Correlation sums of one part at one shift.
struct Sums {
  double n = 0, f = 0, r = 0, ff = 0, rr = 0, fr = 0;
  void add(double fv, double rv) noexcept {
    n += 1, f += fv, r += rv, ff += fv * fv, rr += rv * rv, fr += fv * rv;
  }
  Sums& operator+=(const Sums& o) noexcept {
    n += o.n, f += o.f, r += o.r, ff += o.ff, rr += o.rr, fr += o.fr;
    return *this;
  }
  [[nodiscard]] double varR() const noexcept { return n > 0 ? std::max(0.0, rr / n - (r / n) * (r / n)) : 0.0; }
  [[nodiscard]] double ncc() const noexcept {
    if (n < 2) return -1;
    const double vf = ff / n - (f / n) * (f / n), vr = rr / n - (r / n) * (r / n), c = fr / n - (f / n) * (r / n);
    return vf > 1e-6 && vr > 1e-6 ? c / std::sqrt(vf * vr) : 0.0;
  }
};

inline constexpr double kMaxBlurLength = 12;  // mask pixels (48 frame pixels at scale 4)

// A line blur as a small sparse kernel: offsets and weights (summing to 1).
struct LineKernel {
  static constexpr int kRadius = 8;  // kMaxBlurLength / 2 + 1, and a margin
  int n = 0;
  int reach = 0;  // the largest |dx| or |dy|
  std::array<int, (2 * kRadius + 1) * (2 * kRadius + 1)> dx{}, dy{};
  std::array<std::ptrdiff_t, (2 * kRadius + 1) * (2 * kRadius + 1)> offset{};  // dy * row + dx
  std::array<float, (2 * kRadius + 1) * (2 * kRadius + 1)> w{};
};

}  // namespace marionette::ar::occlusion_detail

namespace marionette::ar {

// Only target_occlusion.cpp and the occlusion_*.cpp files include this header: the names above
// are theirs.
using namespace occlusion_detail;  // NOLINT(google-build-using-namespace)

struct TargetOcclusion::Impl {
  CameraModel camera;
  OcclusionSettings s;
  int mw = 0, mh = 0;
  std::vector<float> rayX, rayY;  // each mask pixel's centre ray, undistorted, normalized (NaN: none)
  std::vector<cv::Mat> levels;    // the reference, CV_32F, and its pyrDown levels
  std::vector<float> levelScale;  // 2^-l
  double A[9] = {};               // plane (X, Z, 1) -> reference pixel
  int refW = 0, refH = 0;

  // Per mask pixel (mw * mh each).
  std::vector<float> u, v;     // the reference pixel (level 0) its centre ray meets; NaN: none
  std::vector<float> lod;      // pyramid level matched to its footprint
  std::vector<float> cover;    // its share on the target
  std::vector<float> F, R0, R, Rb, gx, gy;  // frame, reference unshifted, aligned, blurred; R's gradient
  std::vector<float> shiftX, shiftY;
  std::array<std::vector<float>, 6> sums;  // window sums: weight, f, r, ff, rr, fr
  std::array<std::vector<float>, 6> inner;  // the same over 3 x 3
  std::vector<float> tmp, h, h2;
  std::vector<std::uint32_t> rowAcc;  // a mask row's block sums of the frame's grey (14-bit weights)
  std::vector<double> fitR, fitF, fitSigmaF, fitSigmaR, fitResidual;
  std::vector<std::uint8_t> out;
  std::vector<std::uint8_t> cells;  // geometry: the cells near the target
  Box written;  // the output's non-zero box
  std::array<Sums, kParts * kParts * kMaxShifts> partSums{};
  std::array<int, 2 * kParts + 2> partEdges{};
  LineKernel kernel;
  OcclusionMask mask;

  [[nodiscard]] std::size_t at(int x, int y) const noexcept {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(mw) + static_cast<std::size_t>(x);
  }

  float sampleLevel(int l, float x, float y) const noexcept {
    const cv::Mat& m = levels[static_cast<std::size_t>(l)];
    x = std::clamp(x, 0.0f, static_cast<float>(m.cols - 1));
    y = std::clamp(y, 0.0f, static_cast<float>(m.rows - 1));
    const int x0 = std::min(static_cast<int>(x), m.cols - 2 < 0 ? 0 : m.cols - 2);
    const int y0 = std::min(static_cast<int>(y), m.rows - 2 < 0 ? 0 : m.rows - 2);
    const int x1 = std::min(x0 + 1, m.cols - 1), y1 = std::min(y0 + 1, m.rows - 1);
    const float ax = x - static_cast<float>(x0), ay = y - static_cast<float>(y0);
    const float* r0 = m.ptr<float>(y0);
    const float* r1 = m.ptr<float>(y1);
    return (r0[x0] * (1 - ax) + r0[x1] * ax) * (1 - ay) + (r1[x0] * (1 - ax) + r1[x1] * ax) * ay;
  }
  // Trilinear: level l holds level 0's pixel x at x 2^-l (pyrDown decimates the even pixels).
  float sampleReference(float x, float y, float level) const noexcept {
    const int last = static_cast<int>(levels.size()) - 1;
    const int l0 = std::min(static_cast<int>(level), last);
    const int l1 = std::min(l0 + 1, last);
    const float a = std::clamp(level - static_cast<float>(l0), 0.0f, 1.0f);
    const float s0 = levelScale[static_cast<std::size_t>(l0)], s1 = levelScale[static_cast<std::size_t>(l1)];
    float value = sampleLevel(l0, x * s0, y * s0);
    if (a > 0 && l1 != l0) value = value * (1 - a) + sampleLevel(l1, x * s1, y * s1) * a;
    return value;
  }

  void clearOutput() noexcept {
    for (int y = written.y0; y < written.y1; ++y)
      std::memset(out.data() + at(written.x0, y), 0, static_cast<std::size_t>(written.x1 - written.x0));
    written = {};
    mask.targetInView = false;
    mask.targetPixels = mask.hiddenShare = mask.clippedShare = 0;
    mask.gain = 1, mask.bias = 0, mask.blurLength = 0, mask.blurAngleRad = 0, mask.shiftX = 0, mask.shiftY = 0;
  }

  // The neighbours across and down whose rays meet the plane (the previous ones at the last column
  // or row, or where the next miss it); false when there are none.
  bool neighbours(int x, int y, std::size_t& nx, std::size_t& ny) const noexcept {
    const std::size_t i = at(x, y);
    nx = x + 1 < mw && !std::isnan(u[i + 1]) ? i + 1 : x > 0 && !std::isnan(u[i - 1]) ? i - 1 : i;
    const std::size_t row = static_cast<std::size_t>(mw);
    ny = y + 1 < mh && !std::isnan(u[i + row]) ? i + row : y > 0 && !std::isnan(u[i - row]) ? i - row : i;
    return nx != i && ny != i;
  }
  // The lengths in reference pixels of the steps to those neighbours.
  void steps(std::size_t i, std::size_t nx, std::size_t ny, float& lx, float& ly) const noexcept {
    const float ux = u[nx] - u[i], vx = v[nx] - v[i], uy = u[ny] - u[i], vy = v[ny] - v[i];
    lx = std::sqrt(ux * ux + vx * vx);
    ly = std::sqrt(uy * uy + vy * vy);
  }
  bool geometry(const glm::dmat4& cameraToWorld, Box& target) noexcept;
  void levelsOver(const Box& b) noexcept;
  void readFrame(const ImageView& frame, const Box& b) noexcept;
  void sampleReferenceOver(const Box& b, std::vector<float>& dst) noexcept;
  void shiftReference(const Box& w) noexcept;
  void searchShift(const Box& t, const Box& w) noexcept;
  // Correlation sums of the frame against `ref` over each part's pixels wholly on the target.
  void partSumsOf(const std::vector<float>& ref, std::array<Sums, kParts * kParts>& parts) const noexcept;
  [[nodiscard]] static double betterHalfNcc(const std::array<Sums, kParts * kParts>& parts) noexcept;
  void matchBlur(const Box& w) noexcept;
  [[nodiscard]] float applyKernel(const LineKernel& k, const std::vector<float>& g, const Box& w, int x, int y) const noexcept;
  void lineBlur(const Box& w, const LineKernel& k, std::vector<float>& dst) const noexcept;
  void windowSums(const Box& w) noexcept;
  void photometricModel(const Box& t, double& gain, double& bias) noexcept;
  void decide(const Box& t, double gain, double bias) noexcept;
  void clean(const Box& t, const Box& e) noexcept;
  bool update(const ImageView& frame, const glm::dmat4& cameraToWorld) noexcept;
  // The buffers for a grid of `scale` (create; allocates).
  void configureGrid(int scale);
  // The target's area in this grid's pixels (its coverage summed), 0 out of view.
  [[nodiscard]] double targetArea(const glm::dmat4& cameraToWorld) noexcept;
  // This grid's mask from `coarse`'s (twice the scale), bilinear between its pixel centres.
  void upsampleFrom(const Impl& coarse) noexcept;
  [[nodiscard]] Box workBox(const Box& t) const noexcept { return t.grown(s.window / 2 + s.searchRadius + 2, mw, mh); }
};

}  // namespace marionette::ar
