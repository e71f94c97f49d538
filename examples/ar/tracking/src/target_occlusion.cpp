#include "marionette_ar/tracking/target_occlusion.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include <glm/mat3x3.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "marionette_ar/tracking/planar_map.hpp"

namespace marionette::ar {

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr int kParts = 3;          // the shift field's parts across and down the target's image
constexpr float kInside = 0.99f;   // coverage that counts a mask pixel as wholly on the target
constexpr double kMaxBlurLength = 12;  // mask pixels (48 frame pixels at scale 4)
constexpr int kMaxShifts = 7 * 7;      // (2 searchRadius + 1)^2 at searchRadius 3
// The shift search: a part's best correlation must reach this to set its own shift (the whole's
// to set any), over at least this many pixels with at least kPartSigma grey levels of texture.
constexpr double kPartNcc = 0.4, kWholeNcc = 0.3, kPartSigma = 4.0;
constexpr int kPartMinPixels = 30;
// Past this box (mask pixels), the shift search and the photometric fit take every other pixel
// both ways.
constexpr long kDenseBoxPixels = 4000;
constexpr int kCell = 4;  // geometry's first pass: cells of kCell x kCell mask pixels
// The blur's direction counts where the normalised tensors differ by this much along it, and
// the blur is kept where it raises the agreeing parts' correlation by this much.
constexpr double kMinAnisotropy = 0.04, kMinBlurGain = 0.01;
// The photometric fit: windows whose correlation reaches this, with texture, not saturated.
constexpr double kFitNcc = 0.8;
constexpr float kGreyBias = 128.0f;  // values centred before the window sums (float precision)
// A textured window's verdict of hidden is weakened for a pixel whose own value agrees with the
// reference's (within kOwnLow of the intensity tolerance; not from kOwnHigh), unless the window
// correlates kOwnNcc below hiddenNcc: a window that straddles the edge of a hand correlates
// poorly on both sides of it.
constexpr float kOwnLow = 0.25f, kOwnHigh = 0.5f, kOwnNcc = 0.2f;
// A pixel's own disagreement is hidden from kPixelTol of the intensity tolerance plus kEdgeTol
// times the reference's gradient (grey levels per mask pixel: a mask pixel's misalignment), in full
// from kPixelRamp times that.
constexpr float kPixelTol = 0.7f, kEdgeTol = 1.0f, kPixelRamp = 1.5f;

// A frame block this bright or dark is clipped (over- or under-exposed): it says nothing about
// what is there, and is left out of the comparison.
constexpr float kBright = 250.0f, kDark = 3.0f;
inline bool clipped(float frame) noexcept { return frame >= kBright || frame <= kDark; }
constexpr double kMaxClippedShare = 0.25;

inline float clamp01(float v) noexcept { return v < 0.0f ? 0.0f : v > 1.0f ? 1.0f : v; }
inline float ramp(float v, float lo, float hi) noexcept { return clamp01((v - lo) / (hi - lo)); }

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

// Sub-pixel offset of a parabola's peak through (-1, a), (0, b), (1, c), within +-0.5.
double parabolaPeak(double a, double b, double c) noexcept {
  const double d = a - 2 * b + c;
  if (!(d < -1e-12)) return 0.0;
  return std::clamp(0.5 * (a - c) / d, -0.5, 0.5);
}

// The median of nine values (a sorting network's exchanges, branch-free).
inline float median9(float* p) noexcept {
  auto s = [p](int a, int b) {
    const float lo = std::min(p[a], p[b]), hi = std::max(p[a], p[b]);
    p[a] = lo, p[b] = hi;
  };
  s(1, 2), s(4, 5), s(7, 8), s(0, 1), s(3, 4), s(6, 7), s(1, 2), s(4, 5), s(7, 8), s(0, 3), s(5, 8), s(4, 7), s(3, 6),
      s(1, 4), s(2, 5), s(4, 7), s(4, 2), s(6, 4), s(4, 2);
  return p[4];
}

// A line blur as a small sparse kernel: offsets and weights (summing to 1).
struct LineKernel {
  static constexpr int kRadius = 8;  // kMaxBlurLength / 2 + 1, and a margin
  int n = 0;
  int reach = 0;  // the largest |dx| or |dy|
  std::array<int, (2 * kRadius + 1) * (2 * kRadius + 1)> dx{}, dy{};
  std::array<std::ptrdiff_t, (2 * kRadius + 1) * (2 * kRadius + 1)> offset{};  // dy * row + dx
  std::array<float, (2 * kRadius + 1) * (2 * kRadius + 1)> w{};
};
// `row`: the grid's width (the taps' offsets in it).
void makeLineKernel(double length, double angle, int row, LineKernel& k) noexcept;

}  // namespace

std::string OcclusionSettings::problem() const {
  const OcclusionSettings& s = *this;
  if (s.scale < 2 || s.scale > 16) return "scale must be 2..16";
  if (s.window < 3 || s.window > 9 || s.window % 2 == 0) return "window must be odd, 3..9";
  if (s.searchRadius < 0 || s.searchRadius > 3) return "searchRadius must be 0..3";
  if (s.featherPasses < 0 || s.featherPasses > 8) return "featherPasses must be 0..8";
  if (!(s.fineWeight >= 0 && s.fineWeight <= 1)) return "fineWeight must be 0..1";
  if (s.maxTargetPixels < 0) return "maxTargetPixels must be >= 0";
  for (const double v : {s.hiddenNcc, s.visibleNcc, s.flatSigma, s.texturedSigma, s.meanTolerance,
                         s.meanToleranceShare, s.textureTolerance})
    if (!std::isfinite(v)) return "the thresholds must be finite";
  if (!(s.hiddenNcc < s.visibleNcc) || s.hiddenNcc < -1 || s.visibleNcc > 1)
    return "need -1 <= hiddenNcc < visibleNcc <= 1";
  if (!(s.flatSigma >= 0) || !(s.flatSigma < s.texturedSigma)) return "need 0 <= flatSigma < texturedSigma";
  if (!(s.meanTolerance > 0) || !(s.meanToleranceShare >= 0) || !(s.textureTolerance > 0))
    return "meanTolerance and textureTolerance must be positive, meanToleranceShare >= 0";
  return {};
}

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
  // Bilinear in a per-mask-pixel float grid, clamped to `b`.
  float gridAt(const std::vector<float>& g, const Box& b, float x, float y) const noexcept {
    x = std::clamp(x, static_cast<float>(b.x0), static_cast<float>(b.x1 - 1));
    y = std::clamp(y, static_cast<float>(b.y0), static_cast<float>(b.y1 - 1));
    const int x0 = std::min(static_cast<int>(x), std::max(b.x0, b.x1 - 2));
    const int y0 = std::min(static_cast<int>(y), std::max(b.y0, b.y1 - 2));
    const int x1 = std::min(x0 + 1, b.x1 - 1), y1 = std::min(y0 + 1, b.y1 - 1);
    const float ax = x - static_cast<float>(x0), ay = y - static_cast<float>(y0);
    return (g[at(x0, y0)] * (1 - ax) + g[at(x1, y0)] * ax) * (1 - ay) + (g[at(x0, y1)] * (1 - ax) + g[at(x1, y1)] * ax) * ay;
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

bool TargetOcclusion::Impl::geometry(const glm::dmat4& c2w, Box& target) noexcept {
  // World -> OpenCV camera (Y and Z of the renderer's camera negated), then the plane's
  // homography to normalized coordinates, [r1 r3 t], and its inverse.
  const glm::dmat3 cvToWorld{glm::dvec3(c2w[0]), -glm::dvec3(c2w[1]), -glm::dvec3(c2w[2])};
  const glm::dmat3 rot = glm::transpose(cvToWorld);
  const glm::dvec3 t = -(rot * glm::dvec3(c2w[3]));
  const glm::dmat3 hn(rot[0], rot[2], t);
  const double det = glm::determinant(hn);
  if (!(std::abs(det) > 1e-15) || !std::isfinite(det)) return false;
  const glm::dmat3 hi = glm::inverse(hn);
  // The reference pixel mask pixel i's ray meets; false where none (behind the camera, off the
  // lens model, far outside the reference: there the numbers only need to say so).
  const double limit = 16.0 * (refW + refH);
  auto project = [&](std::size_t i, double& uu, double& vv) {
    const double rx = rayX[i], ry = rayY[i];
    if (std::isnan(rx)) return false;
    const glm::dvec3 q = hi * glm::dvec3(rx, ry, 1.0);
    if (!(q.z > 0)) return false;  // the ray meets the plane behind the camera
    const double X = q.x / q.z, Z = q.y / q.z;
    const double w = A[6] * X + A[7] * Z + A[8];
    if (!(w > 0)) return false;
    uu = (A[0] * X + A[1] * Z + A[2]) / w, vv = (A[3] * X + A[4] * Z + A[5]) / w;
    return std::abs(uu) < limit && std::abs(vv) < limit;
  };
  // First the corners of kCell x kCell cells: a cell whose corners' reference box, grown by its
  // own size, misses the reference (and any cell with a corner without a ray) is far from the
  // target; the rest, grown by two cells (more than the work's margins), are worked out pixel by
  // pixel.
  const int cw = (mw + kCell - 1) / kCell, ch = (mh + kCell - 1) / kCell;
  std::fill(cells.begin(), cells.end(), std::uint8_t{0});
  for (int cy = 0; cy < ch; ++cy)
    for (int cx = 0; cx < cw; ++cx) {
      double lo[2] = {1e300, 1e300}, hi2[2] = {-1e300, -1e300};
      bool near = false;
      for (int k = 0; k < 4 && !near; ++k) {
        const int x = std::min(mw - 1, kCell * (cx + (k & 1))), y = std::min(mh - 1, kCell * (cy + (k >> 1)));
        double uu, vv;
        if (!project(at(x, y), uu, vv)) {
          near = true;
          break;
        }
        lo[0] = std::min(lo[0], uu), lo[1] = std::min(lo[1], vv), hi2[0] = std::max(hi2[0], uu), hi2[1] = std::max(hi2[1], vv);
      }
      const double grow = std::max(hi2[0] - lo[0], hi2[1] - lo[1]) + 1;
      near = near || (lo[0] - grow < refW && hi2[0] + grow > -1 && lo[1] - grow < refH && hi2[1] + grow > -1);
      if (!near) continue;
      for (int y = std::max(0, cy - 2); y <= std::min(ch - 1, cy + 2); ++y)
        for (int x = std::max(0, cx - 2); x <= std::min(cw - 1, cx + 2); ++x) cells[static_cast<std::size_t>(y * cw + x)] = 1;
    }
  for (int y = 0; y < mh; ++y)
    for (int x = 0; x < mw; ++x) {
      const std::size_t i = at(x, y);
      u[i] = v[i] = kNaN;
      double uu, vv;
      if (!cells[static_cast<std::size_t>((y / kCell) * cw + x / kCell)] || !project(i, uu, vv)) continue;
      u[i] = static_cast<float>(uu);
      v[i] = static_cast<float>(vv);
    }
  // Coverage from the steps to the neighbours: the edge's distance in reference pixels over the
  // pixel's side is its share on the target. Pixels whose centre is farther off the reference
  // than their steps (an upper bound of the side) are off it.
  target = {mw, mh, 0, 0};
  const float fw = static_cast<float>(refW), fh = static_cast<float>(refH);
  for (int y = 0; y < mh; ++y)
    for (int x = 0; x < mw; ++x) {
      const std::size_t i = at(x, y);
      cover[i] = 0;
      if (std::isnan(u[i])) continue;  // (and every pixel of a cell far from the target)
      std::size_t nx, ny;
      if (!neighbours(x, y, nx, ny)) continue;
      const float ax = std::abs(u[nx] - u[i]) + std::abs(v[nx] - v[i]), ay = std::abs(u[ny] - u[i]) + std::abs(v[ny] - v[i]);
      const float bound = std::max(ax, ay);  // at least the side below
      const float d = std::min(std::min(u[i] + 0.5f, fw - 0.5f - u[i]), std::min(v[i] + 0.5f, fh - 0.5f - v[i]));
      if (!(d > -0.5f * bound)) continue;
      if (d >= 0.5f * bound) {
        cover[i] = 1;  // wholly inside: 0.5 + d / side >= 1
      } else {
        float lx, ly;
        steps(i, nx, ny, lx, ly);
        const float side = std::sqrt(lx * ly);
        if (!(side > 0) || !std::isfinite(side)) continue;
        cover[i] = clamp01(0.5f + d / side);
      }
      if (cover[i] > 0) {
        target.x0 = std::min(target.x0, x), target.y0 = std::min(target.y0, y);
        target.x1 = std::max(target.x1, x + 1), target.y1 = std::max(target.y1, y + 1);
      }
    }
  return !target.empty();
}

void TargetOcclusion::Impl::levelsOver(const Box& b) noexcept {
  // The frame's block is a box of `footprint` reference pixels; a pyrDown level l is a Gaussian
  // of about 0.6 2^l: the level one below log2 of the footprint matches it.
  const float last = static_cast<float>(levels.size() - 1);
  for (int y = b.y0; y < b.y1; ++y)
    for (int x = b.x0; x < b.x1; ++x) {
      const std::size_t i = at(x, y);
      std::size_t nx, ny;
      if (std::isnan(u[i]) || !neighbours(x, y, nx, ny)) {
        lod[i] = 0;
        continue;
      }
      float lx, ly;
      steps(i, nx, ny, lx, ly);
      const float footprint = std::max(std::min(lx, ly), 0.5f * std::max(lx, ly));
      lod[i] = std::isfinite(footprint) ? std::clamp(std::log2(std::max(footprint, 1e-6f)) - 1.0f, 0.0f, last) : last;
    }
}

void TargetOcclusion::Impl::readFrame(const ImageView& frame, const Box& b) noexcept {
  const int sc = s.scale, W = frame.width, H = frame.height, ch = frame.channels;
  const std::ptrdiff_t stride = frame.rowBytes();
  for (int y = b.y0; y < b.y1; ++y) {
    std::fill(rowAcc.begin() + b.x0, rowAcc.begin() + b.x1, 0u);
    const int fy0 = y * sc, fy1 = std::min(H, fy0 + sc);
    for (int fy = fy0; fy < fy1; ++fy) {
      const std::uint8_t* row = frame.pixels + fy * stride;
      for (int x = b.x0; x < b.x1; ++x) {
        const int fx0 = x * sc, fx1 = std::min(W, fx0 + sc);
        std::uint32_t acc = 0;
        if (ch == 1) {
          for (int fx = fx0; fx < fx1; ++fx) acc += static_cast<std::uint32_t>(row[fx]) << 14;
        } else {
          // OpenCV's RGB2GRAY weights in 14 bits (RGBA: the alpha ignored).
          for (int fx = fx0; fx < fx1; ++fx) {
            const std::uint8_t* p = row + fx * ch;
            acc += 4899u * p[0] + 9617u * p[1] + 1868u * p[2];
          }
        }
        rowAcc[static_cast<std::size_t>(x)] += acc;
      }
    }
    for (int x = b.x0; x < b.x1; ++x) {
      const int count = (std::min(W, x * sc + sc) - x * sc) * (fy1 - fy0);
      F[at(x, y)] = static_cast<float>(static_cast<double>(rowAcc[static_cast<std::size_t>(x)]) / (16384.0 * count));
    }
  }
}

void TargetOcclusion::Impl::sampleReferenceOver(const Box& b, std::vector<float>& dst) noexcept {
  for (int y = b.y0; y < b.y1; ++y)
    for (int x = b.x0; x < b.x1; ++x) {
      const std::size_t i = at(x, y);
      dst[i] = std::isnan(u[i]) ? kNaN : sampleReference(u[i], v[i], lod[i]);
    }
}

void TargetOcclusion::Impl::shiftReference(const Box& w) noexcept {
  // R(p) = R0(p + shift(p)), bilinear in R0's grid (its own pixel where a tap has no value).
  for (int y = w.y0; y < w.y1; ++y)
    for (int x = w.x0; x < w.x1; ++x) {
      const std::size_t i = at(x, y);
      R[i] = R0[i];
      if (std::isnan(R0[i]) || (shiftX[i] == 0 && shiftY[i] == 0)) continue;
      const float sx = static_cast<float>(x) + shiftX[i], sy = static_cast<float>(y) + shiftY[i];
      const int x0 = static_cast<int>(std::floor(sx)), y0 = static_cast<int>(std::floor(sy));
      if (x0 < w.x0 || y0 < w.y0 || x0 + 1 >= w.x1 || y0 + 1 >= w.y1) continue;
      const std::size_t j = at(x0, y0), row = static_cast<std::size_t>(mw);
      const float ax = sx - static_cast<float>(x0), ay = sy - static_cast<float>(y0);
      const float value = (R0[j] * (1 - ax) + R0[j + 1] * ax) * (1 - ay) + (R0[j + row] * (1 - ax) + R0[j + row + 1] * ax) * ay;
      if (!std::isnan(value)) R[i] = value;
    }
}

void TargetOcclusion::Impl::partSumsOf(const std::vector<float>& ref, std::array<Sums, kParts * kParts>& parts) const noexcept {
  parts.fill({});
  for (int py = 0; py < kParts; ++py)
    for (int px = 0; px < kParts; ++px) {
      Sums& sum = parts[static_cast<std::size_t>(py * kParts + px)];
      for (int y = partEdges[static_cast<std::size_t>(kParts + 1 + py)];
           y < partEdges[static_cast<std::size_t>(kParts + 2 + py)]; ++y)
        for (int x = partEdges[static_cast<std::size_t>(px)]; x < partEdges[static_cast<std::size_t>(px + 1)]; ++x) {
          const std::size_t i = at(x, y);
          if (cover[i] >= kInside && !std::isnan(ref[i]) && !clipped(F[i])) sum.add(F[i] - kGreyBias, ref[i] - kGreyBias);
        }
    }
}

double TargetOcclusion::Impl::betterHalfNcc(const std::array<Sums, kParts * kParts>& parts) noexcept {
  std::array<double, kParts * kParts> ncc{};
  int k = 0;
  for (const Sums& p : parts)
    if (p.n >= kPartMinPixels && std::sqrt(p.varR()) >= kPartSigma) ncc[static_cast<std::size_t>(k++)] = p.ncc();
  if (k == 0) return -1;
  std::sort(ncc.begin(), ncc.begin() + k, std::greater<>());
  const int half = (k + 1) / 2;
  double sum = 0;
  for (int j = 0; j < half; ++j) sum += ncc[static_cast<std::size_t>(j)];
  return sum / half;
}

void TargetOcclusion::Impl::searchShift(const Box& t, const Box& w) noexcept {
  // Parts: kParts x kParts over the target's box (edges in partEdges: x then y).
  for (int k = 0; k <= kParts; ++k) {
    partEdges[static_cast<std::size_t>(k)] = t.x0 + (t.x1 - t.x0) * k / kParts;
    partEdges[static_cast<std::size_t>(kParts + 1 + k)] = t.y0 + (t.y1 - t.y0) * k / kParts;
  }
  const int r = s.searchRadius, side = 2 * r + 1, shifts = side * side;
  for (int y = w.y0; y < w.y1; ++y)
    for (int x = w.x0; x < w.x1; ++x) shiftX[at(x, y)] = shiftY[at(x, y)] = 0;
  mask.shiftX = mask.shiftY = 0;
  if (r == 0) return;
  partSums.fill({});
  // Every pixel, or every other one both ways on a large target (a part then still has hundreds).
  const int stride = static_cast<long>(t.x1 - t.x0) * (t.y1 - t.y0) > kDenseBoxPixels ? 2 : 1;
  for (int py = 0; py < kParts; ++py)
    for (int px = 0; px < kParts; ++px) {
      const int part = py * kParts + px;
      for (int y = partEdges[static_cast<std::size_t>(kParts + 1 + py)];
           y < partEdges[static_cast<std::size_t>(kParts + 2 + py)]; y += stride)
        for (int x = partEdges[static_cast<std::size_t>(px)]; x < partEdges[static_cast<std::size_t>(px + 1)]; x += stride) {
          const std::size_t i = at(x, y);
          if (cover[i] < kInside || clipped(F[i])) continue;
          const double f = F[i] - kGreyBias;
          for (int dy = -r; dy <= r; ++dy) {
            const int yy = y + dy;
            if (yy < w.y0 || yy >= w.y1) continue;
            for (int dx = -r; dx <= r; ++dx) {
              const int xx = x + dx;
              if (xx < w.x0 || xx >= w.x1) continue;
              const float rv = R0[at(xx, yy)];
              if (std::isnan(rv)) continue;
              partSums[static_cast<std::size_t>(part * kMaxShifts + (dy + r) * side + (dx + r))].add(f, rv - kGreyBias);
            }
          }
        }
    }
  // The best shift of a set of sums (one part's, or the whole's), sub-pixel; false when nothing
  // correlates enough.
  auto best = [&](const Sums* at, double minNcc, double& sx, double& sy) {
    const Sums& centre = at[r * side + r];
    if (centre.n < kPartMinPixels || std::sqrt(centre.varR()) < kPartSigma) return false;
    int bi = r * side + r;
    double bn = centre.ncc();
    for (int k = 0; k < shifts; ++k)
      if (at[k].n >= kPartMinPixels && at[k].ncc() > bn) bn = at[k].ncc(), bi = k;
    if (bn < minNcc) return false;
    const int bx = bi % side - r, by = bi / side - r;
    sx = bx, sy = by;
    if (bx > -r && bx < r) sx += parabolaPeak(at[bi - 1].ncc(), bn, at[bi + 1].ncc());
    if (by > -r && by < r) sy += parabolaPeak(at[bi - side].ncc(), bn, at[bi + side].ncc());
    return true;
  };
  std::array<Sums, kMaxShifts> whole{};
  for (int part = 0; part < kParts * kParts; ++part)
    for (int k = 0; k < shifts; ++k) whole[static_cast<std::size_t>(k)] += partSums[static_cast<std::size_t>(part * kMaxShifts + k)];
  double wx = 0, wy = 0;
  if (!best(whole.data(), kWholeNcc, wx, wy)) return;  // nothing correlates: no shift at all
  std::array<double, kParts * kParts> px{}, py{};
  for (int part = 0; part < kParts * kParts; ++part) {
    double sx = wx, sy = wy;
    if (!best(&partSums[static_cast<std::size_t>(part * kMaxShifts)], kPartNcc, sx, sy)) sx = wx, sy = wy;
    px[static_cast<std::size_t>(part)] = sx, py[static_cast<std::size_t>(part)] = sy;
  }
  mask.shiftX = wx, mask.shiftY = wy;
  // The field: bilinear between the parts' centres, constant beyond them.
  const double cw = (t.x1 - t.x0) / double(kParts), chh = (t.y1 - t.y0) / double(kParts);
  for (int y = w.y0; y < w.y1; ++y) {
    const double fy = std::clamp((y - t.y0 + 0.5) / chh - 0.5, 0.0, kParts - 1.0);
    const int y0 = std::min(static_cast<int>(fy), kParts - 2);
    const double ay = fy - y0;
    for (int x = w.x0; x < w.x1; ++x) {
      const double fx = std::clamp((x - t.x0 + 0.5) / cw - 0.5, 0.0, kParts - 1.0);
      const int x0 = std::min(static_cast<int>(fx), kParts - 2);
      const double ax = fx - x0;
      auto field = [&](const std::array<double, kParts * kParts>& f) {
        const auto k = [](int a, int b) { return static_cast<std::size_t>(b * kParts + a); };
        return (f[k(x0, y0)] * (1 - ax) + f[k(x0 + 1, y0)] * ax) * (1 - ay) +
               (f[k(x0, y0 + 1)] * (1 - ax) + f[k(x0 + 1, y0 + 1)] * ax) * ay;
      };
      shiftX[at(x, y)] = static_cast<float>(field(px));
      shiftY[at(x, y)] = static_cast<float>(field(py));
    }
  }
}

namespace {
void makeLineKernel(double length, double angle, int row, LineKernel& k) noexcept {
  // Taps a pixel apart at most along the line, centred; each tap's bilinear weights land on the
  // same four neighbours for every pixel (their offsets are the same): one small kernel.
  constexpr int side = 2 * LineKernel::kRadius + 1;
  std::array<float, side * side> grid{};
  const int taps = std::max(2, static_cast<int>(std::ceil(length)) + 1);
  const double dx = std::cos(angle) * length / (taps - 1), dy = std::sin(angle) * length / (taps - 1);
  for (int j = 0; j < taps; ++j) {
    const double o = j - 0.5 * (taps - 1);
    const double tx = o * dx, ty = o * dy;
    const int x0 = static_cast<int>(std::floor(tx)), y0 = static_cast<int>(std::floor(ty));
    const float ax = static_cast<float>(tx - x0), ay = static_cast<float>(ty - y0);
    const float weights[4] = {(1 - ax) * (1 - ay), ax * (1 - ay), (1 - ax) * ay, ax * ay};
    for (int c = 0; c < 4; ++c) {
      const int gx = std::clamp(x0 + (c & 1) + LineKernel::kRadius, 0, side - 1);
      const int gy = std::clamp(y0 + (c >> 1) + LineKernel::kRadius, 0, side - 1);
      grid[static_cast<std::size_t>(gy * side + gx)] += weights[c] / static_cast<float>(taps);
    }
  }
  k.n = 0, k.reach = 0;
  for (int gy = 0; gy < side; ++gy)
    for (int gx = 0; gx < side; ++gx) {
      const float wgt = grid[static_cast<std::size_t>(gy * side + gx)];
      if (wgt <= 0) continue;
      const auto e = static_cast<std::size_t>(k.n++);
      k.dx[e] = gx - LineKernel::kRadius, k.dy[e] = gy - LineKernel::kRadius, k.w[e] = wgt;
      k.offset[e] = static_cast<std::ptrdiff_t>(k.dy[e]) * row + k.dx[e];
      k.reach = std::max({k.reach, std::abs(k.dx[e]), std::abs(k.dy[e])});
    }
}
}  // namespace

float TargetOcclusion::Impl::applyKernel(const LineKernel& k, const std::vector<float>& g, const Box& w, int x,
                                         int y) const noexcept {
  float sum = 0;
  if (x - k.reach >= w.x0 && x + k.reach < w.x1 && y - k.reach >= w.y0 && y + k.reach < w.y1) {
    const float* c = g.data() + at(x, y);  // every tap inside w: no clamping
    for (int e = 0; e < k.n; ++e) sum += k.w[static_cast<std::size_t>(e)] * c[k.offset[static_cast<std::size_t>(e)]];
    return sum;
  }
  for (int e = 0; e < k.n; ++e) {
    const auto j = static_cast<std::size_t>(e);
    sum += k.w[j] * g[at(std::clamp(x + k.dx[j], w.x0, w.x1 - 1), std::clamp(y + k.dy[j], w.y0, w.y1 - 1))];
  }
  return sum;
}

void TargetOcclusion::Impl::lineBlur(const Box& w, const LineKernel& k, std::vector<float>& dst) const noexcept {
  for (int y = w.y0; y < w.y1; ++y)
    for (int x = w.x0; x < w.x1; ++x) {
      const std::size_t i = at(x, y);
      dst[i] = std::isnan(R[i]) ? kNaN : applyKernel(k, R, w, x, y);
    }
}

void TargetOcclusion::Impl::matchBlur(const Box& w) noexcept {
  mask.blurLength = 0, mask.blurAngleRad = 0;
  std::copy(R.begin(), R.end(), Rb.begin());  // (the whole grid: cheap beside the rest, and simple)
  if (!s.matchBlur) return;
  // R (NaN-free over w where the ray meets the plane) with NaNs replaced for the blur's taps.
  for (int y = w.y0; y < w.y1; ++y)
    for (int x = w.x0; x < w.x1; ++x)
      if (std::isnan(R[at(x, y)])) R[at(x, y)] = kGreyBias;
  // Which parts show the target (their correlation at the aligned pose): the statistics come
  // from them alone, so that a hand does not count as blur.
  std::array<Sums, kParts * kParts> parts{};
  partSumsOf(R, parts);
  std::array<bool, kParts * kParts> use{};
  int used = 0;
  for (std::size_t k = 0; k < parts.size(); ++k)
    if (parts[k].n >= kPartMinPixels && std::sqrt(parts[k].varR()) >= kPartSigma && parts[k].ncc() >= 0.5)
      use[k] = true, ++used;
  if (used == 0) return;
  // The reference's gradient over w (0 off the target), and the gradient structure tensors of
  // the frame and the reference over the parts used.
  for (int y = w.y0; y < w.y1; ++y)
    for (int x = w.x0; x < w.x1; ++x) {
      const std::size_t i = at(x, y);
      const bool interior = x > w.x0 && y > w.y0 && x + 1 < w.x1 && y + 1 < w.y1 && cover[i] >= kInside;
      gx[i] = interior ? 0.5f * (R[i + 1] - R[i - 1]) : 0.0f;
      gy[i] = interior ? 0.5f * (R[i + static_cast<std::size_t>(mw)] - R[i - static_cast<std::size_t>(mw)]) : 0.0f;
    }
  double tf[3] = {0, 0, 0}, tr[3] = {0, 0, 0};
  for (std::size_t k = 0; k < parts.size(); ++k) {
    if (!use[k]) continue;
    const int px = static_cast<int>(k) % kParts, py = static_cast<int>(k) / kParts;
    for (int y = std::max(partEdges[static_cast<std::size_t>(kParts + 1 + py)], w.y0 + 1);
         y < std::min(partEdges[static_cast<std::size_t>(kParts + 2 + py)], w.y1 - 1); ++y)
      for (int x = std::max(partEdges[static_cast<std::size_t>(px)], w.x0 + 1);
           x < std::min(partEdges[static_cast<std::size_t>(px + 1)], w.x1 - 1); ++x) {
        const std::size_t i = at(x, y);
        if (cover[i] < kInside || clipped(F[i])) continue;
        const double fx = 0.5 * (F[i + 1] - F[i - 1]), fy = 0.5 * (F[i + static_cast<std::size_t>(mw)] - F[i - static_cast<std::size_t>(mw)]);
        const double rx = 0.5 * (R[i + 1] - R[i - 1]), ry = 0.5 * (R[i + static_cast<std::size_t>(mw)] - R[i - static_cast<std::size_t>(mw)]);
        tf[0] += fx * fx, tf[1] += fx * fy, tf[2] += fy * fy;
        tr[0] += rx * rx, tr[1] += rx * ry, tr[2] += ry * ry;
      }
  }
  const double traceF = tf[0] + tf[2], traceR = tr[0] + tr[2];
  if (!(traceF > 1e-9) || !(traceR > 1e-9)) return;
  // The direction that lost the largest share of the gradient energy.
  const double a = tr[0] / traceR - tf[0] / traceF, b = tr[1] / traceR - tf[1] / traceF, c = tr[2] / traceR - tf[2] / traceF;
  const double lambda = 0.5 * (a + c) + std::sqrt(0.25 * (a - c) * (a - c) + b * b);
  if (lambda < kMinAnisotropy) return;
  const double angle = 0.5 * std::atan2(2 * b, a - c);
  const double ca = std::cos(angle), sa = std::sin(angle);
  const double targetShare = (ca * ca * tf[0] + 2 * ca * sa * tf[1] + sa * sa * tf[2]) / traceF;
  // The share along it of the reference's gradient blurred by a line of `length` (the blur of the
  // gradient, bilinear taps a pixel apart at most: every other pixel of the parts used both ways,
  // every fourth on a large target).
  const int stride = static_cast<long>(w.x1 - w.x0) * (w.y1 - w.y0) > 2 * kDenseBoxPixels ? 4 : 2;
  auto shareAt = [&](double length) {
    makeLineKernel(length, angle, mw, kernel);
    double t0 = 0, t1 = 0, t2 = 0;
    for (std::size_t k = 0; k < parts.size(); ++k) {
      if (!use[k]) continue;
      const int px = static_cast<int>(k) % kParts, py = static_cast<int>(k) / kParts;
      for (int y = std::max(partEdges[static_cast<std::size_t>(kParts + 1 + py)], w.y0 + 1);
           y < std::min(partEdges[static_cast<std::size_t>(kParts + 2 + py)], w.y1 - 1); y += stride)
        for (int x = std::max(partEdges[static_cast<std::size_t>(px)], w.x0 + 1);
             x < std::min(partEdges[static_cast<std::size_t>(px + 1)], w.x1 - 1); x += stride) {
          if (cover[at(x, y)] < kInside) continue;
          // (Off the target the gradient is 0.)
          const float sx = applyKernel(kernel, gx, w, x, y), sy = applyKernel(kernel, gy, w, x, y);
          t0 += double(sx) * sx, t1 += double(sx) * sy, t2 += double(sy) * sy;
        }
    }
    const double trace = t0 + t2;
    return trace > 1e-12 ? (ca * ca * t0 + 2 * ca * sa * t1 + sa * sa * t2) / trace : 0.0;
  };
  if (shareAt(0) <= targetShare) return;
  double lo = 0, hi = kMaxBlurLength;
  if (shareAt(hi) > targetShare) {
    lo = hi;
  } else {
    for (int it = 0; it < 6; ++it) {
      const double mid = 0.5 * (lo + hi);
      (shareAt(mid) > targetShare ? lo : hi) = mid;
    }
  }
  const double length = 0.5 * (lo + hi);
  if (length < 1.0) return;
  makeLineKernel(length, angle, mw, kernel);
  lineBlur(w, kernel, Rb);
  // Kept only where it makes the parts that show the target agree better.
  std::array<Sums, kParts * kParts> blurred{};
  partSumsOf(Rb, blurred);
  if (betterHalfNcc(blurred) < betterHalfNcc(parts) + kMinBlurGain) {
    std::copy(R.begin(), R.end(), Rb.begin());
    return;
  }
  mask.blurLength = length, mask.blurAngleRad = angle;
}

void TargetOcclusion::Impl::windowSums(const Box& w) noexcept {
  // Separable box sums over the window of the weight (wholly on the target, not clipped), and the
  // weighted frame, reference and their products; centred on kGreyBias for float's sake. The
  // same over 3 x 3 (inner): the finer of the two verdicts.
  for (int y = w.y0; y < w.y1; ++y)
    for (int x = w.x0; x < w.x1; ++x) {
      const std::size_t i = at(x, y);
      const bool on = cover[i] >= kInside && !std::isnan(Rb[i]) && !clipped(F[i]);
      const float f = on ? F[i] - kGreyBias : 0.0f, rv = on ? Rb[i] - kGreyBias : 0.0f;
      sums[0][i] = on ? 1.0f : 0.0f;
      sums[1][i] = f, sums[2][i] = rv, sums[3][i] = f * f, sums[4][i] = rv * rv, sums[5][i] = f * rv;
    }
  // Rows of shifted copies added (contiguous: the compiler's vectors), then rows added.
  auto box = [&](const std::vector<float>& q, std::vector<float>& dst, int r) {
    for (int y = w.y0; y < w.y1; ++y) {
      const float* in = q.data() + at(0, y);
      float* row = tmp.data() + at(0, y);
      std::fill(row + w.x0, row + w.x1, 0.0f);
      for (int d = -r; d <= r; ++d)
        for (int x = std::max(w.x0, w.x0 - d); x < std::min(w.x1, w.x1 - d); ++x) row[x] += in[x + d];
    }
    for (int y = w.y0; y < w.y1; ++y) {
      float* row = dst.data() + at(0, y);
      std::fill(row + w.x0, row + w.x1, 0.0f);
      for (int d = std::max(w.y0, y - r); d <= std::min(w.y1 - 1, y + r); ++d) {
        const float* in = tmp.data() + at(0, d);
        for (int x = w.x0; x < w.x1; ++x) row[x] += in[x];
      }
    }
  };
  for (std::size_t k = 0; k < sums.size(); ++k) {
    if (s.fineWeight > 0) box(sums[k], inner[k], 1);
    box(sums[k], sums[k], s.window / 2);
  }
}

void TargetOcclusion::Impl::photometricModel(const Box& t, double& gain, double& bias) noexcept {
  // The frame's grey as gain x reference + bias, from the windows that clearly show the target
  // (textured, correlating, not saturated): a least-squares line through their means (means do
  // not suffer from a blur that contrasts do), refitted without the residuals past 3 MADs; with
  // too narrow a range of means, the contrast ratio and the mean offset.
  const float area = static_cast<float>(s.window * s.window);
  fitR.clear(), fitF.clear(), fitSigmaF.clear(), fitSigmaR.clear();
  double allN = 0, allF = 0, allR = 0, allFF = 0, allRR = 0;
  const int stride = static_cast<long>(t.x1 - t.x0) * (t.y1 - t.y0) > kDenseBoxPixels ? 2 : 1;
  for (int y = t.y0; y < t.y1; y += stride)
    for (int x = t.x0; x < t.x1; x += stride) {
      const std::size_t i = at(x, y);
      const float n = sums[0][i];
      if (cover[i] < kInside || n < 0.6f * area) continue;
      const double mf = sums[1][i] / n, mr = sums[2][i] / n;
      const double vf = std::max(0.0, sums[3][i] / n - mf * mf), vr = std::max(0.0, sums[4][i] / n - mr * mr);
      const double c = sums[5][i] / n - mf * mr;
      allN += 1, allF += mf, allR += mr, allFF += vf, allRR += vr;
      if (std::sqrt(vr) < s.texturedSigma || !(vf > 1e-6)) continue;
      if (c / std::sqrt(vf * vr) < kFitNcc) continue;
      const double mF = mf + kGreyBias;
      if (mF < 8 || mF > 247) continue;
      fitR.push_back(mr), fitF.push_back(mf), fitSigmaF.push_back(std::sqrt(vf)), fitSigmaR.push_back(std::sqrt(vr));
    }
  gain = 1, bias = 0;
  if (fitR.size() < 8) {
    // Nothing clearly visible to measure by: the target's means and contrasts as a whole.
    if (allN > 0 && allRR > 0) {
      gain = std::clamp(std::sqrt(allFF / allRR), 0.25, 4.0);
      bias = (allF - gain * allR) / allN + kGreyBias * (1 - gain);
    }
    return;
  }
  auto fit = [&](double maxResidual) {
    double n = 0, sr = 0, sf = 0, srr = 0, srf = 0, ssf = 0, ssr = 0;
    for (std::size_t k = 0; k < fitR.size(); ++k) {
      if (maxResidual > 0 && std::abs(fitF[k] - (gain * (fitR[k] + kGreyBias) + bias - kGreyBias)) > maxResidual) continue;
      n += 1, sr += fitR[k], sf += fitF[k], srr += fitR[k] * fitR[k], srf += fitR[k] * fitF[k];
      ssf += fitSigmaF[k], ssr += fitSigmaR[k];
    }
    if (n < 4) return;
    const double mr = sr / n, mf = sf / n, vr = srr / n - mr * mr;
    double g = vr >= 144.0 ? (srf / n - mr * mf) / vr : ssf / ssr;
    g = std::clamp(g, 0.25, 4.0);
    gain = g;
    bias = (mf - g * mr) + kGreyBias * (1 - g);  // back to uncentred grey levels
  };
  fit(0);
  // The residuals' median absolute deviation.
  fitResidual.clear();
  for (std::size_t k = 0; k < fitR.size(); ++k)
    fitResidual.push_back(std::abs(fitF[k] - (gain * (fitR[k] + kGreyBias) + bias - kGreyBias)));
  const auto mid = fitResidual.begin() + static_cast<std::ptrdiff_t>(fitResidual.size() / 2);
  std::nth_element(fitResidual.begin(), mid, fitResidual.end());
  const double mad = *mid;
  fit(std::max(3.0 * 1.4826 * mad, 2.0));
}

void TargetOcclusion::Impl::decide(const Box& t, double gain, double bias) noexcept {
  const float area = static_cast<float>(s.window * s.window);
  const float minN = std::max(4.0f, 0.2f * area);
  const float g = static_cast<float>(gain), b = static_cast<float>(bias);
  const float hiddenNcc = static_cast<float>(s.hiddenNcc), visibleNcc = static_cast<float>(s.visibleNcc);
  const float flat = static_cast<float>(s.flatSigma), textured = static_cast<float>(s.texturedSigma);
  const float tolBase = static_cast<float>(s.meanTolerance), tolShare = static_cast<float>(s.meanToleranceShare);
  const float texTol = static_cast<float>(s.textureTolerance);
  const float fine = static_cast<float>(s.fineWeight);
  for (int y = t.y0; y < t.y1; ++y)
    for (int x = t.x0; x < t.x1; ++x) {
      const std::size_t i = at(x, y);
      h[i] = -1;  // undecided: filled from the neighbours (clean)
      const float n = sums[0][i];
      if (cover[i] <= 0 || n < minN || clipped(F[i])) continue;
      const float mf = sums[1][i] / n, mr = sums[2][i] / n;
      const float vf = std::max(0.0f, sums[3][i] / n - mf * mf), vr = std::max(0.0f, sums[4][i] / n - mr * mr);
      const float c = sums[5][i] / n - mf * mr;
      const float sigmaF = std::sqrt(vf), sigmaR = std::sqrt(vr) * g;  // the reference's in frame levels
      const float texture = ramp(sigmaR, flat, textured);
      float hidden = 0;
      // Intensity: the pixel's own (its block is wholly on the target) or the window's mean
      // against the reference's.
      const bool whole = cover[i] >= kInside && !std::isnan(Rb[i]);
      const float frameValue = whole ? F[i] : mf + kGreyBias;
      const float refValue = whole ? Rb[i] : mr + kGreyBias;
      const float predicted = std::clamp(g * refValue + b, 0.0f, 255.0f);
      const float residual = std::abs(frameValue - predicted);
      const float tol = tolBase + tolShare * predicted;
      if (texture > 0) {
        // A window that straddles the edge of a hand correlates poorly on both sides of it: the
        // pixel's own agreement with the reference keeps the visible side visible.
        float ncc = vf > 1e-4f && vr > 1e-6f ? c / std::sqrt(vf * vr) : 0.0f;
        if (fine > 0 && inner[0][i] >= 4) {
          // The 3 x 3 window's, where it has texture of its own: finer, noisier.
          const float n3 = inner[0][i], mf3 = inner[1][i] / n3, mr3 = inner[2][i] / n3;
          const float vf3 = std::max(0.0f, inner[3][i] / n3 - mf3 * mf3), vr3 = std::max(0.0f, inner[4][i] / n3 - mr3 * mr3);
          const float c3 = inner[5][i] / n3 - mf3 * mr3;
          if (vr3 > 1.0f) ncc = (1 - fine) * ncc + fine * (vf3 > 1e-4f ? c3 / std::sqrt(vf3 * vr3) : 0.0f);
        }
        const float own = whole ? std::max(ramp(residual, kOwnLow * tol, kOwnHigh * tol),
                                           ramp(hiddenNcc - ncc, 0.0f, kOwnNcc)) : 1.0f;
        hidden += texture * ramp(visibleNcc - ncc, 0.0f, visibleNcc - hiddenNcc) * own;
      }
      // The pixel's own disagreement, past what a small misalignment explains where the reference
      // has an edge: a finger across a window that otherwise correlates.
      float byPixel = 0;
      if (whole && x > 0 && y > 0 && x + 1 < mw && y + 1 < mh) {
        const float ddx = Rb[i + 1] - Rb[i - 1], ddy = Rb[i + static_cast<std::size_t>(mw)] - Rb[i - static_cast<std::size_t>(mw)];
        const float grad = 0.5f * std::sqrt(ddx * ddx + ddy * ddy);
        if (!std::isnan(grad)) {
          const float tolP = kPixelTol * tol + kEdgeTol * g * grad;
          byPixel = ramp(residual, tolP, kPixelRamp * tolP);
        }
      }
      if (texture < 1) {
        // And texture where the reference has none.
        const float byMean = ramp(residual, 0.5f * tol, tol);
        const float byTexture = ramp(sigmaF - sigmaR, 0.5f * texTol, texTol);
        hidden += (1 - texture) * std::max(byMean, byTexture);
      }
      h[i] = std::max(hidden, byPixel);
    }
}

void TargetOcclusion::Impl::clean(const Box& t, const Box& e) noexcept {
  // h over t (undecided, -1, elsewhere in e) -> undecided pixels take the largest of their decided
  // neighbours (three rounds: the filters below then see the target's verdicts continue past its
  // edge instead of zeros that would erode them) -> median 3x3 -> close -> feather -> times
  // coverage. Reads past e's border repeat its edge.
  for (int y = e.y0; y < e.y1; ++y)
    for (int x = e.x0; x < e.x1; ++x)
      if (x < t.x0 || x >= t.x1 || y < t.y0 || y >= t.y1) h[at(x, y)] = -1;
  const std::ptrdiff_t row = mw;
  // Offsets to the neighbours of (x, y) within e: left, right, up, down.
  auto offsets = [&](int x, int y, std::ptrdiff_t& l, std::ptrdiff_t& r, std::ptrdiff_t& u0, std::ptrdiff_t& d0) {
    l = x > e.x0 ? -1 : 0, r = x + 1 < e.x1 ? 1 : 0, u0 = y > e.y0 ? -row : 0, d0 = y + 1 < e.y1 ? row : 0;
  };
  for (int round = 0; round < 3; ++round) {
    for (int y = e.y0; y < e.y1; ++y)
      for (int x = e.x0; x < e.x1; ++x) {
        const std::size_t i = at(x, y);
        float m = h[i];
        if (m < 0) {
          std::ptrdiff_t l, r, up, dn;
          offsets(x, y, l, r, up, dn);
          const float* c = h.data() + i;
          m = std::max({c[up + l], c[up], c[up + r], c[l], c[r], c[dn + l], c[dn], c[dn + r]});
        }
        h2[i] = m;
      }
    std::swap(h, h2);
  }
  for (int y = e.y0; y < e.y1; ++y)
    for (int x = e.x0; x < e.x1; ++x) h[at(x, y)] = std::max(h[at(x, y)], 0.0f);
  for (int y = e.y0; y < e.y1; ++y)
    for (int x = e.x0; x < e.x1; ++x) {
      std::ptrdiff_t l, r, up, dn;
      offsets(x, y, l, r, up, dn);
      const float* c = h.data() + at(x, y);
      float p[9] = {c[up + l], c[up], c[up + r], c[l], c[0], c[r], c[dn + l], c[dn], c[dn + r]};
      h2[at(x, y)] = median9(p);
    }
  // 3 x 3 max (dilate) or min (erode), separable: src -> tmp -> dst.
  auto morph = [&](const std::vector<float>& src, std::vector<float>& dst, bool dilate) {
    for (int y = e.y0; y < e.y1; ++y)
      for (int x = e.x0; x < e.x1; ++x) {
        std::ptrdiff_t l, r, up, dn;
        offsets(x, y, l, r, up, dn);
        const float* c = src.data() + at(x, y);
        tmp[at(x, y)] = dilate ? std::max({c[l], c[0], c[r]}) : std::min({c[l], c[0], c[r]});
      }
    for (int y = e.y0; y < e.y1; ++y)
      for (int x = e.x0; x < e.x1; ++x) {
        std::ptrdiff_t l, r, up, dn;
        offsets(x, y, l, r, up, dn);
        const float* c = tmp.data() + at(x, y);
        dst[at(x, y)] = dilate ? std::max({c[up], c[0], c[dn]}) : std::min({c[up], c[0], c[dn]});
      }
  };
  // A closing fills the holes a hand's own texture leaves (where it happens to look like the
  // target). No opening: it would erase fingers, 3 to 4 mask pixels wide at arm's length.
  morph(h2, h, true);   // dilate ...
  morph(h, h2, false);  // ... then erode
  for (int pass = 0; pass < s.featherPasses; ++pass) {
    for (int y = e.y0; y < e.y1; ++y)
      for (int x = e.x0; x < e.x1; ++x) {
        std::ptrdiff_t l, r, up, dn;
        offsets(x, y, l, r, up, dn);
        const float* c = h2.data() + at(x, y);
        tmp[at(x, y)] = 0.25f * (c[l] + 2 * c[0] + c[r]);
      }
    for (int y = e.y0; y < e.y1; ++y)
      for (int x = e.x0; x < e.x1; ++x) {
        std::ptrdiff_t l, r, up, dn;
        offsets(x, y, l, r, up, dn);
        const float* c = tmp.data() + at(x, y);
        h2[at(x, y)] = 0.25f * (c[up] + 2 * c[0] + c[dn]);
      }
  }
  double hidden = 0, onTarget = 0;
  for (int y = e.y0; y < e.y1; ++y)
    for (int x = e.x0; x < e.x1; ++x) {
      const std::size_t i = at(x, y);
      const float m = clamp01(h2[i]) * cover[i];
      out[i] = static_cast<std::uint8_t>(255.0f * m + 0.5f);
      hidden += out[i] / 255.0;
      onTarget += cover[i];
    }
  written = e;
  mask.targetPixels = onTarget;
  mask.hiddenShare = onTarget > 0 ? hidden / onTarget : 0.0;
}

bool TargetOcclusion::Impl::update(const ImageView& frame, const glm::dmat4& cameraToWorld) noexcept {
  clearOutput();
  if (!frame.valid() || frame.width != camera.width || frame.height != camera.height) return false;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(cameraToWorld[c][r])) return false;
  Box t;
  if (!geometry(cameraToWorld, t)) return true;  // the target is out of view
  const Box w = workBox(t);
  readFrame(frame, w);
  // Over- or under-exposed: with much of the target clipped, the comparison would be of clipped
  // pixels (and a linear model of the rest): nothing is said hidden.
  double inside = 0, clippedPixels = 0, onTarget = 0;
  for (int y = t.y0; y < t.y1; ++y)
    for (int x = t.x0; x < t.x1; ++x) {
      const std::size_t i = at(x, y);
      onTarget += cover[i];
      if (cover[i] < kInside) continue;
      inside += 1;
      clippedPixels += clipped(F[i]);
    }
  mask.clippedShare = inside > 0 ? clippedPixels / inside : 0.0;
  mask.targetInView = true;
  mask.targetPixels = onTarget;
  if (mask.clippedShare > kMaxClippedShare) return true;
  levelsOver(w);
  sampleReferenceOver(w, R0);
  searchShift(t, w);
  shiftReference(w);
  matchBlur(w);
  windowSums(w);
  double gain = 1, bias = 0;
  photometricModel(t, gain, bias);
  mask.gain = gain, mask.bias = bias;
  decide(t, gain, bias);
  clean(t, t.grown(2 + s.featherPasses, mw, mh));
  return true;
}

void TargetOcclusion::Impl::configureGrid(int sc) {
  mw = (camera.width + sc - 1) / sc, mh = (camera.height + sc - 1) / sc;
  const std::size_t n = static_cast<std::size_t>(mw) * static_cast<std::size_t>(mh);
  // Each mask pixel's centre (its block's centre in frame pixels, OpenCV's convention) as a
  // ray of the pinhole: the lens model undone.
  std::vector<cv::Point2f> centres, rays;
  centres.reserve(n);
  for (int y = 0; y < mh; ++y)
    for (int x = 0; x < mw; ++x) {
      const double cxp = 0.5 * (x * sc + std::min(camera.width, x * sc + sc)) - 0.5;
      const double cyp = 0.5 * (y * sc + std::min(camera.height, y * sc + sc)) - 0.5;
      centres.emplace_back(static_cast<float>(cxp), static_cast<float>(cyp));
    }
  rayX.resize(n), rayY.resize(n);
  if (camera.hasDistortion()) {
    const cv::Matx33d k(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
    cv::undistortPoints(centres, rays, k, std::vector<double>(camera.distortion.begin(), camera.distortion.end()),
                        cv::noArray(), cv::noArray(), cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 50, 1e-9));
    for (std::size_t i = 0; i < n; ++i) {
      rayX[i] = std::isfinite(rays[i].x) ? rays[i].x : kNaN;
      rayY[i] = std::isfinite(rays[i].y) ? rays[i].y : kNaN;
    }
  } else {
    for (std::size_t i = 0; i < n; ++i) {
      rayX[i] = static_cast<float>((centres[i].x - camera.cx) / camera.fx);
      rayY[i] = static_cast<float>((centres[i].y - camera.cy) / camera.fy);
    }
  }
  for (auto* buffer : {&u, &v, &lod, &cover, &F, &R0, &R, &Rb, &gx, &gy, &shiftX, &shiftY, &tmp, &h, &h2})
    buffer->assign(n, 0.0f);
  for (std::vector<float>& q : sums) q.assign(n, 0.0f);
  for (std::vector<float>& q : inner) q.assign(n, 0.0f);
  rowAcc.assign(static_cast<std::size_t>(mw), 0u);
  for (auto* buffer : {&fitR, &fitF, &fitSigmaF, &fitSigmaR, &fitResidual}) buffer->reserve(n);
  out.assign(n, 0);
  cells.assign(static_cast<std::size_t>((mw + kCell - 1) / kCell) * static_cast<std::size_t>((mh + kCell - 1) / kCell), 0);
  mask.width = mw, mask.height = mh, mask.scale = mask.computedScale = sc;
  mask.pixels = out.data();
}

double TargetOcclusion::Impl::targetArea(const glm::dmat4& cameraToWorld) noexcept {
  Box t;
  if (!geometry(cameraToWorld, t)) return 0;
  double area = 0;
  for (int y = t.y0; y < t.y1; ++y)
    for (int x = t.x0; x < t.x1; ++x) area += cover[at(x, y)];
  return area;
}

void TargetOcclusion::Impl::upsampleFrom(const Impl& coarse) noexcept {
  clearOutput();
  const OcclusionMask& c = coarse.mask;
  mask.targetInView = c.targetInView;
  mask.targetPixels = 4 * c.targetPixels;
  mask.hiddenShare = c.hiddenShare, mask.clippedShare = c.clippedShare;
  mask.gain = c.gain, mask.bias = c.bias;
  mask.blurLength = 2 * c.blurLength, mask.blurAngleRad = c.blurAngleRad;
  mask.shiftX = 2 * c.shiftX, mask.shiftY = 2 * c.shiftY;
  const Box& cw = coarse.written;
  if (cw.empty()) return;
  // Fine pixel x's centre is coarse pixel (x + 0.5) / 2 - 0.5: the fine pixels within half a coarse
  // pixel of the coarse box (outside it the coarse mask is 0).
  const Box e{std::max(0, 2 * cw.x0 - 1), std::max(0, 2 * cw.y0 - 1), std::min(mw, 2 * cw.x1 + 1),
              std::min(mh, 2 * cw.y1 + 1)};
  const int cmw = coarse.mw, cmh = coarse.mh;
  auto value = [&](int x, int y) -> float {
    return x < cw.x0 || x >= cw.x1 || y < cw.y0 || y >= cw.y1 ? 0.0f : coarse.out[coarse.at(x, y)];
  };
  for (int y = e.y0; y < e.y1; ++y) {
    const float cy = std::clamp((static_cast<float>(y) + 0.5f) * 0.5f - 0.5f, 0.0f, static_cast<float>(cmh - 1));
    const int y0 = static_cast<int>(cy);
    const float ay = cy - static_cast<float>(y0);
    for (int x = e.x0; x < e.x1; ++x) {
      const float cx = std::clamp((static_cast<float>(x) + 0.5f) * 0.5f - 0.5f, 0.0f, static_cast<float>(cmw - 1));
      const int x0 = static_cast<int>(cx);
      const float ax = cx - static_cast<float>(x0);
      const float m = (value(x0, y0) * (1 - ax) + value(x0 + 1, y0) * ax) * (1 - ay) +
                      (value(x0, y0 + 1) * (1 - ax) + value(x0 + 1, y0 + 1) * ax) * ay;
      out[at(x, y)] = static_cast<std::uint8_t>(std::min(255.0f, m + 0.5f));
    }
  }
  written = e;
}

TargetOcclusion::TargetOcclusion(std::unique_ptr<Impl> impl, std::unique_ptr<Impl> coarse) noexcept
    : impl_(std::move(impl)), coarse_(std::move(coarse)) {}
TargetOcclusion::~TargetOcclusion() = default;

std::unique_ptr<TargetOcclusion> TargetOcclusion::create(const CameraModel& camera, const ImageView& reference,
                                                         const std::array<double, 9>& planeToImage,
                                                         const OcclusionSettings& settings, Diagnostics& diagnostics) {
  if (const std::string p = camera.problem(); !p.empty()) {
    diagnostics.error("camera", p);
    return nullptr;
  }
  if (const std::string p = settings.problem(); !p.empty()) {
    diagnostics.error("occlusion settings", p);
    return nullptr;
  }
  if (!reference.valid() || reference.channels != 1 || reference.width < 16 || reference.height < 16) {
    diagnostics.error("target", "the reference image must be grey and at least 16x16 pixels");
    return nullptr;
  }
  const cv::Matx33d a(planeToImage.data());
  const double det = cv::determinant(a);
  bool finite = true;
  for (const double x : planeToImage) finite = finite && std::isfinite(x);
  if (!finite || !(std::abs(det) > 1e-300)) {
    diagnostics.error("target", "the reference's plane-to-image mapping is singular or not finite");
    return nullptr;
  }
  try {
    auto impl = std::make_unique<Impl>();
    impl->camera = camera;
    impl->s = settings;
    std::copy(planeToImage.begin(), planeToImage.end(), impl->A);
    impl->refW = reference.width, impl->refH = reference.height;
    const cv::Mat grey(reference.height, reference.width, CV_8UC1, const_cast<std::uint8_t*>(reference.pixels),
                       static_cast<std::size_t>(reference.rowBytes()));
    cv::Mat level;
    grey.convertTo(level, CV_32F);
    impl->levels.push_back(level);
    while (impl->levels.size() < 10 && std::min(impl->levels.back().cols, impl->levels.back().rows) >= 8) {
      cv::Mat down;
      cv::pyrDown(impl->levels.back(), down);
      impl->levels.push_back(down);
    }
    for (std::size_t l = 0; l < impl->levels.size(); ++l) impl->levelScale.push_back(std::ldexp(1.0f, -static_cast<int>(l)));
    impl->configureGrid(settings.scale);
    // Twice the scale for a target that fills much of the view (maxTargetPixels), sharing the
    // reference's pyramid.
    std::unique_ptr<Impl> coarse;
    if (settings.maxTargetPixels > 0 && 2 * settings.scale <= 16) {
      coarse = std::make_unique<Impl>();
      coarse->camera = camera;
      coarse->s = settings;
      coarse->s.scale = 2 * settings.scale;
      std::copy(std::begin(impl->A), std::end(impl->A), coarse->A);
      coarse->refW = impl->refW, coarse->refH = impl->refH;
      coarse->levels = impl->levels;  // (headers: the pixels are shared)
      coarse->levelScale = impl->levelScale;
      coarse->configureGrid(coarse->s.scale);
    }
    return std::unique_ptr<TargetOcclusion>(new TargetOcclusion(std::move(impl), std::move(coarse)));
  } catch (const cv::Exception& e) {
    diagnostics.error("target", std::string("OpenCV failed: ") + e.what());
    return nullptr;
  }
}

std::unique_ptr<TargetOcclusion> TargetOcclusion::create(const CameraModel& camera, const PlanarMap& map,
                                                         const OcclusionSettings& settings, Diagnostics& diagnostics) {
  if (map.keyframes.empty()) {
    diagnostics.error("map", "the map has no reference keyframe");
    return nullptr;
  }
  const PlanarKeyframe& k = map.keyframes[0];
  if (k.grey.size() != static_cast<std::size_t>(k.width) * static_cast<std::size_t>(k.height)) {
    diagnostics.error("map", "the reference keyframe's image does not match its size");
    return nullptr;
  }
  return create(camera, ImageView{k.grey.data(), k.width, k.height, 1, 0}, k.planeToImage, settings, diagnostics);
}

bool TargetOcclusion::update(const ImageView& frame, const glm::dmat4& cameraToWorld) noexcept {
  // A target that fills much of the view: its mask at twice the scale (from a quarter of the
  // pixels), upsampled. Its area on the coarse grid, times four, estimates the fine one's.
  if (coarse_ && frame.valid() && frame.width == impl_->camera.width && frame.height == impl_->camera.height) {
    bool finite = true;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) finite = finite && std::isfinite(cameraToWorld[c][r]);
    if (finite && 4 * coarse_->targetArea(cameraToWorld) > impl_->s.maxTargetPixels) {
      const bool ok = coarse_->update(frame, cameraToWorld);
      impl_->upsampleFrom(*coarse_);
      impl_->mask.computedScale = coarse_->mask.scale;
      return ok;
    }
  }
  const bool ok = impl_->update(frame, cameraToWorld);
  impl_->mask.computedScale = impl_->mask.scale;
  return ok;
}
void TargetOcclusion::clear() noexcept {
  impl_->clearOutput();
  impl_->mask.computedScale = impl_->mask.scale;
}
const OcclusionMask& TargetOcclusion::mask() const noexcept { return impl_->mask; }
const CameraModel& TargetOcclusion::camera() const noexcept { return impl_->camera; }
const OcclusionSettings& TargetOcclusion::settings() const noexcept { return impl_->s; }

}  // namespace marionette::ar
