#include "motion_blur.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include "cpu_avx2.hpp"

namespace marionette::ar {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kPatchHalf = 8;    // 17x17 patches
constexpr int kMaxPatches = 64;  // spread: the points come interleaved over the target's grid
constexpr int kMaxTaps = MotionBlurScratch::kMaxLineTaps;

// A normalized line kernel of `length` along (cos a, sin a), with taps at whole steps along its
// dominant (major) axis, each on the nearest row or column across it. The taps' weights are the
// overlap of [k - 0.5, k + 0.5] with the kernel's extent along the axis: the outer two share
// `end`, the rest weigh one, all over `extent`.
struct LineGeometry {
  bool alongX = true;
  double slope = 0;
  int half = 0;
  float end = 1, scale = 1;

  explicit LineGeometry(const MotionBlur& b) noexcept {
    const double c = std::cos(b.angleRad), s = std::sin(b.angleRad);
    alongX = std::abs(c) >= std::abs(s);
    const double major = alongX ? c : s, minor = alongX ? s : c;
    slope = minor / major;
    const double extent = std::clamp(b.lengthPx * std::abs(major), 1.0, double(kMaxTaps - 1));
    half = std::max(0, static_cast<int>(std::ceil(extent * 0.5 - 0.5)));
    end = static_cast<float>(extent * 0.5 - (half - 0.5));  // in (0, 1]
    scale = static_cast<float>(1.0 / extent);
  }
  [[nodiscard]] int shift(int major) const noexcept { return static_cast<int>(std::lround(major * slope)); }
};

inline float pixel(const cv::Mat& m, int x, int y) noexcept {
  x = std::clamp(x, 0, m.cols - 1);
  y = std::clamp(y, 0, m.rows - 1);
  return m.ptr<std::uint8_t>(y)[x];
}

// The sheared rows of the line blur over `r`: row b holds pixel (major, b + shift(major)) along
// the digital line. For each row with outputs in `r`, rowSink(b, lo, hi, line, shift) with the
// outputs i = lo .. hi - 1 (major = majorBegin + i) and their taps line[lo .. hi - 1 + 2K]
// (output i's taps are line[i .. i + 2K], centred on c = i + K; its minor is b + shift[c]).
// Of each row only the span that lands in `r` is read. False when the scratch was not reserved
// for `r`.
template <bool AlongX, class RowSink>
bool forEachLineRow(const cv::Mat& image, const LineGeometry& g, const cv::Rect& r, MotionBlurScratch& scratch,
                    RowSink&& rowSink) noexcept {
  const int majorBegin = AlongX ? r.x : r.y, n = AlongX ? r.width : r.height;
  const int minorBegin = AlongX ? r.y : r.x, minorEnd = minorBegin + (AlongX ? r.height : r.width);
  if (n <= 0 || minorEnd <= minorBegin) return true;
  const int K = g.half, lineLength = n + 2 * K;
  if (static_cast<std::size_t>(lineLength) > scratch.line.capacity() ||
      static_cast<std::size_t>(lineLength) > scratch.shifts.capacity())
    return false;
  scratch.line.resize(static_cast<std::size_t>(lineLength));  // within capacity: no allocation
  scratch.shifts.resize(static_cast<std::size_t>(lineLength));
  int* line = scratch.line.data();
  int* shift = scratch.shifts.data();  // shift[j] = g.shift(majorBegin + j - K): monotonic in j
  for (int j = 0; j < lineLength; ++j) shift[j] = g.shift(majorBegin + j - K);
  const int s0 = shift[K], s1 = shift[K + n - 1];
  const bool rising = g.slope >= 0;  // shift[] is non-decreasing, else non-increasing
  const int bBegin = minorBegin - std::max(s0, s1), bEnd = minorEnd - std::min(s0, s1);
  const int rows = image.rows, cols = image.cols;
  for (int b = bBegin; b < bEnd; ++b) {
    // The outputs i of this row whose pixel (majorBegin + i, b + shift[i + K]) is in `r`: a run.
    const int* first = shift + K;
    const int lo = static_cast<int>((rising ? std::lower_bound(first, first + n, minorBegin - b)
                                            : std::lower_bound(first, first + n, minorEnd - 1 - b, std::greater<>())) - first);
    const int hi = static_cast<int>((rising ? std::lower_bound(first, first + n, minorEnd - b)
                                            : std::lower_bound(first, first + n, minorBegin - 1 - b, std::greater<>())) - first);
    if (lo >= hi) continue;
    // Taps j = lo .. hi - 1 + 2K of the line.
    const int jEnd = hi + 2 * K;
    // The taps inside the image read it directly; those past its edges clamp (a run at either
    // end: the shifts are monotonic).
    const int majorSize = AlongX ? cols : rows, minorSize = AlongX ? rows : cols;
    const int insideMinorBegin = static_cast<int>(
        (rising ? std::lower_bound(shift, shift + lineLength, -b)
                : std::lower_bound(shift, shift + lineLength, minorSize - 1 - b, std::greater<>())) - shift);
    const int insideMinorEnd = static_cast<int>(
        (rising ? std::lower_bound(shift, shift + lineLength, minorSize - b)
                : std::lower_bound(shift, shift + lineLength, -1 - b, std::greater<>())) - shift);
    const int insideBegin = std::clamp(std::max(K - majorBegin, insideMinorBegin), lo, jEnd);
    const int insideEnd = std::clamp(std::min(majorSize + K - majorBegin, insideMinorEnd), insideBegin, jEnd);
    const std::uint8_t* data = image.data;
    const std::size_t stride = image.step[0];
    auto at = [&](int major, int minor) {
      return AlongX ? data[static_cast<std::size_t>(minor) * stride + static_cast<std::size_t>(major)]
                    : data[static_cast<std::size_t>(major) * stride + static_cast<std::size_t>(minor)];
    };
    auto clamped = [&](int j) {
      line[j] = at(std::clamp(majorBegin + j - K, 0, majorSize - 1), std::clamp(b + shift[j], 0, minorSize - 1));
    };
    for (int j = lo; j < insideBegin; ++j) clamped(j);
    for (int j = insideBegin; j < insideEnd; ++j) line[j] = at(majorBegin + j - K, b + shift[j]);
    for (int j = insideEnd; j < jEnd; ++j) clamped(j);
    rowSink(b, lo, hi, static_cast<const int*>(line), static_cast<const int*>(shift));
  }
  return true;
}

// The line blur over `r`, each value handed to sink(x, y, v) once: each sheared row
// box-filtered by a running sum. The sums are integers (exact in a float: the same bits as
// summing the taps in floats, in any order).
template <bool AlongX, class Sink>
bool lineBlurAlong(const cv::Mat& image, const LineGeometry& g, const cv::Rect& r, MotionBlurScratch& scratch, Sink&& sink) noexcept {
  const int majorBegin = AlongX ? r.x : r.y, K = g.half;
  return forEachLineRow<AlongX>(image, g, r, scratch, [&](int b, int lo, int hi, const int* line, const int* shift) {
    if (K == 0) {
      for (int i = lo; i < hi; ++i) {
        const int major = majorBegin + i, minor = b + shift[i];
        if constexpr (AlongX) sink(major, minor, static_cast<float>(line[i]));
        else sink(minor, major, static_cast<float>(line[i]));
      }
      return;
    }
    // inner: the taps strictly between the two ends, c - K + 1 .. c + K - 1 for c = i + K.
    int inner = 0;
    for (int j = lo + 1; j < lo + 2 * K; ++j) inner += line[j];
    for (int i = lo; i < hi; ++i) {
      const int c = i + K;
      const float v = g.scale * (static_cast<float>(inner) + g.end * static_cast<float>(line[c - K] + line[c + K]));
      const int major = majorBegin + i, minor = b + shift[c];
      if constexpr (AlongX) sink(major, minor, v);
      else sink(minor, major, v);
      inner += line[c + K] - line[c - K + 1];
    }
  });
}

template <class Sink>
bool lineBlur(const cv::Mat& image, const LineGeometry& g, const cv::Rect& r, MotionBlurScratch& scratch, Sink&& sink) noexcept {
  return g.alongX ? lineBlurAlong<true>(image, g, r, scratch, sink) : lineBlurAlong<false>(image, g, r, scratch, sink);
}

// The line blur of square patches along one direction, for every length up to a maximum: each
// sheared row's taps read once, kept as prefix sums, so that a length reads four of them per
// pixel. The blur searches try ten or more lengths along one direction (the bisection of
// estimateMotionBlur, the golden section of refineMotionBlur); lineBlur would read every tap
// again for each. The same bits as lineBlur: the sums are integers either way.
class PatchLines {
 public:
  // Patch p covers `side` x `side` pixels from (round(points[p]) - offset); `direction` gives the
  // line's slope, `maxHalf` the longest kernel's half. False when the scratch is too small.
  bool build(const cv::Mat& image, const std::vector<cv::Point2f>& points, int count, int side, int offset,
             const LineGeometry& direction, int maxHalf, MotionBlurScratch& scratch) noexcept {
    g_ = direction, side_ = side, offset_ = offset, maxHalf_ = maxHalf;
    lineLength_ = side + 2 * maxHalf;
    rows_ = 2 * side;  // |slope| <= 1: a patch's rows span at most side + side - 1 sheared rows
    const std::size_t need = static_cast<std::size_t>(count) * static_cast<std::size_t>(rows_) *
                             static_cast<std::size_t>(lineLength_ + 1);
    const std::size_t needShifts = static_cast<std::size_t>(count) * static_cast<std::size_t>(lineLength_);
    if (need > scratch.patchLines.capacity() || needShifts > scratch.patchShifts.capacity()) return false;
    scratch.patchLines.resize(need);  // within capacity: no allocation
    scratch.patchShifts.resize(needShifts);
    prefix_ = scratch.patchLines.data();
    shifts_ = scratch.patchShifts.data();
    const int rows = image.rows, cols = image.cols;
    for (int p = 0; p < count; ++p) {
      int majorBegin = 0, minorBegin = 0;
      origin(points, p, majorBegin, minorBegin);
      int* shift = shifts_ + static_cast<std::ptrdiff_t>(p) * lineLength_;
      for (int j = 0; j < lineLength_; ++j) shift[j] = g_.shift(majorBegin + j - maxHalf_);
      const int bBegin = minorBegin - std::max(shift[maxHalf_], shift[maxHalf_ + side - 1]);
      const int used = side + std::abs(shift[maxHalf_ + side - 1] - shift[maxHalf_]);  // the rows the patch reads
      for (int r = 0; r < used; ++r) {
        int* prefix = row(p, r);
        prefix[0] = 0;
        for (int j = 0; j < lineLength_; ++j) {
          const int major = majorBegin + j - maxHalf_, minor = bBegin + r + shift[j];
          const int x = std::clamp(g_.alongX ? major : minor, 0, cols - 1), y = std::clamp(g_.alongX ? minor : major, 0, rows - 1);
          prefix[j + 1] = prefix[j] + image.ptr<std::uint8_t>(y)[x];
        }
      }
    }
    return true;
  }
  // Patch p blurred by `g` (the direction built for, g.half <= maxHalf): sink(column, row, value)
  // for every pixel of the patch.
  template <class Sink>
  void blur(const std::vector<cv::Point2f>& points, int p, const LineGeometry& g, Sink&& sink) const noexcept {
    int majorBegin = 0, minorBegin = 0;
    origin(points, p, majorBegin, minorBegin);
    const int* shift = shifts_ + static_cast<std::ptrdiff_t>(p) * lineLength_;
    const int bBegin = minorBegin - std::max(shift[maxHalf_], shift[maxHalf_ + side_ - 1]);
    const int K = g.half;
    for (int i = 0; i < side_; ++i) {
      const int c = i + maxHalf_;
      for (int m = 0; m < side_; ++m) {
        const int* prefix = row(p, minorBegin + m - shift[c] - bBegin);
        const auto tap = [&](int j) { return prefix[j + 1] - prefix[j]; };
        const float v = K == 0 ? static_cast<float>(tap(c))
                               : g.scale * (static_cast<float>(prefix[c + K] - prefix[c - K + 1]) +
                                            g.end * static_cast<float>(tap(c - K) + tap(c + K)));
        if (g_.alongX) sink(i, m, v);
        else sink(m, i, v);
      }
    }
  }
  [[nodiscard]] int maxHalf() const noexcept { return maxHalf_; }

 private:
  LineGeometry g_{MotionBlur{}};
  int side_ = 0, offset_ = 0, maxHalf_ = 0, lineLength_ = 0, rows_ = 0;
  int* prefix_ = nullptr;
  int* shifts_ = nullptr;
  void origin(const std::vector<cv::Point2f>& points, int p, int& majorBegin, int& minorBegin) const noexcept {
    const int x0 = static_cast<int>(std::lround(points[static_cast<std::size_t>(p)].x)) - offset_;
    const int y0 = static_cast<int>(std::lround(points[static_cast<std::size_t>(p)].y)) - offset_;
    majorBegin = g_.alongX ? x0 : y0;
    minorBegin = g_.alongX ? y0 : x0;
  }
  [[nodiscard]] int* row(int p, int r) const noexcept {
    return prefix_ + (static_cast<std::ptrdiff_t>(p) * rows_ + r) * (lineLength_ + 1);
  }
};

// The structure tensor of a patch (gxx, gxy, gyy), normalized by its trace.
struct Tensor {
  double xx = 0, xy = 0, yy = 0;
  void normalize() noexcept {
    const double t = xx + yy;
    if (t > 0) xx /= t, xy /= t, yy /= t;
  }
  [[nodiscard]] double along(double c, double s) const noexcept { return c * c * xx + 2 * c * s * xy + s * s * yy; }
};

// Sum over the patches of the tensors of `image` (or its blur), each patch weighted equally
// after normalizing: a strongly textured patch must not decide alone.
constexpr int kTensorSide = 2 * kPatchHalf + 3;  // one pixel more each side for the differences
static_assert(kMaxPatches <= MotionBlurScratch::kMaxSearchPatches && kTensorSide <= MotionBlurScratch::kMaxSearchSide,
              "the scratch's patch lines are reserved for the searches' patches");

// ... of `image` blurred by `line` (lines built along its direction, for its length or longer).
Tensor patchTensor(const cv::Mat& image, const std::vector<cv::Point2f>& points, int count, const LineGeometry* line,
                   const PatchLines* lines) noexcept {
  constexpr int kSide = kTensorSide;
  std::array<float, kSide * kSide> v{};
  Tensor total;
  for (int p = 0; p < count; ++p) {
    const int x0 = static_cast<int>(std::lround(points[static_cast<std::size_t>(p)].x)) - kPatchHalf - 1;
    const int y0 = static_cast<int>(std::lround(points[static_cast<std::size_t>(p)].y)) - kPatchHalf - 1;
    if (line) {
      lines->blur(points, p, *line, [&](int i, int j, float value) { v[static_cast<std::size_t>(j * kSide + i)] = value; });
    } else {
      for (int j = 0; j < kSide; ++j)
        for (int i = 0; i < kSide; ++i) v[static_cast<std::size_t>(j * kSide + i)] = pixel(image, x0 + i, y0 + j);
    }
    Tensor t;
    for (int j = 1; j < kSide - 1; ++j)
      for (int i = 1; i < kSide - 1; ++i) {
        const double gx = 0.5 * (v[static_cast<std::size_t>(j * kSide + i + 1)] - v[static_cast<std::size_t>(j * kSide + i - 1)]);
        const double gy = 0.5 * (v[static_cast<std::size_t>((j + 1) * kSide + i)] - v[static_cast<std::size_t>((j - 1) * kSide + i)]);
        t.xx += gx * gx;
        t.xy += gx * gy;
        t.yy += gy * gy;
      }
    t.normalize();
    total.xx += t.xx;
    total.xy += t.xy;
    total.yy += t.yy;
  }
  total.normalize();
  return total;
}

constexpr int kRefineSide = 2 * kPatchHalf + 1;
constexpr int kRefinePatches = 32;

// The frame around each matched point, sampled bilinearly at the offsets of the template's
// whole pixels around round(from): fixed while the blur is searched, so taken once.
void sampleFramePatches(const cv::Mat& frame, const std::vector<cv::Point2f>& from, const std::vector<cv::Point2f>& to,
                        int count, float* out) noexcept {
  for (int p = 0; p < count; ++p) {
    const cv::Point2f a = from[static_cast<std::size_t>(p)], b = to[static_cast<std::size_t>(p)];
    const int x0 = static_cast<int>(std::lround(a.x)) - kPatchHalf, y0 = static_cast<int>(std::lround(a.y)) - kPatchHalf;
    float* patch = out + static_cast<std::ptrdiff_t>(p) * kRefineSide * kRefineSide;
    for (int j = 0; j < kRefineSide; ++j)
      for (int i = 0; i < kRefineSide; ++i) {
        const double fx = b.x + (x0 + i - double(a.x)), fy = b.y + (y0 + j - double(a.y));
        const int ix = static_cast<int>(std::floor(fx)), iy = static_cast<int>(std::floor(fy));
        const double wx = fx - ix, wy = fy - iy;
        patch[j * kRefineSide + i] = static_cast<float>(
            (1 - wy) * ((1 - wx) * pixel(frame, ix, iy) + wx * pixel(frame, ix + 1, iy)) +
            wy * ((1 - wx) * pixel(frame, ix, iy + 1) + wx * pixel(frame, ix + 1, iy + 1)));
      }
  }
}

// How badly the template blurred by `line` explains the frame's patches: the sum of 1 - NCC
// (gain and bias per patch cancel).
// (Blurred from `lines` where given: built along `line`'s direction, for its length or longer.)
double mismatch(const cv::Mat& sharp, const std::vector<cv::Point2f>& from, const float* framePatches, int count,
                const LineGeometry& line, const PatchLines* lines, MotionBlurScratch& scratch) noexcept {
  std::array<float, kRefineSide * kRefineSide> t{};
  double total = 0;
  for (int p = 0; p < count; ++p) {
    const cv::Point2f a = from[static_cast<std::size_t>(p)];
    const int x0 = static_cast<int>(std::lround(a.x)) - kPatchHalf, y0 = static_cast<int>(std::lround(a.y)) - kPatchHalf;
    if (lines) {
      lines->blur(from, p, line, [&](int i, int j, float value) { t[static_cast<std::size_t>(j * kRefineSide + i)] = value; });
    } else if (!lineBlur(sharp, line, cv::Rect(x0, y0, kRefineSide, kRefineSide), scratch, [&](int x, int y, float value) {
                 t[static_cast<std::size_t>((y - y0) * kRefineSide + x - x0)] = value;
               })) {
      return 1e30;
    }
    const float* f = framePatches + static_cast<std::ptrdiff_t>(p) * kRefineSide * kRefineSide;
    double st = 0, sf = 0, stt = 0, sff = 0, stf = 0;
    for (int k = 0; k < kRefineSide * kRefineSide; ++k) {
      const double v = t[static_cast<std::size_t>(k)], w = f[k];
      st += v;
      sf += w;
      stt += v * v;
      sff += w * w;
      stf += v * w;
    }
    const double n = kRefineSide * kRefineSide;
    const double vt = stt - st * st / n, vf = sff - sf * sf / n, c = stf - st * sf / n;
    total += vt > 1 && vf > 1 ? 1 - c / std::sqrt(vt * vf) : 1;
  }
  return total;
}

}  // namespace

MotionBlur estimateMotionBlur(const cv::Mat& sharp, const cv::Mat& frame, const std::vector<cv::Point2f>& points,
                              double maxLengthPx, MotionBlurScratch& scratch) noexcept {
  MotionBlur none;
  const int count = std::min(static_cast<int>(points.size()), kMaxPatches);
  if (count < 6 || sharp.size() != frame.size() || sharp.type() != CV_8UC1 || frame.type() != CV_8UC1) return none;
  const Tensor t = patchTensor(sharp, points, count, nullptr, nullptr), f = patchTensor(frame, points, count, nullptr, nullptr);
  // The energy lost in the frame: the largest eigenvalue of T - F and its direction.
  const double a = t.xx - f.xx, b = t.xy - f.xy, d = t.yy - f.yy;
  const double mean = 0.5 * (a + d), radius = std::sqrt(0.25 * (a - d) * (a - d) + b * b);
  const double loss = mean + radius;
  // Below this the two agree up to noise and the texture's own anisotropy. Occluders reach
  // 0.1 on sharp frames, a 9 px smear of some textures less: this only proposes a blur, which
  // refineMotionBlur confirms on aligned patches (a false proposal costs that search, no KLT).
  constexpr double kMinLoss = 0.04;
  if (!(loss > kMinLoss)) return none;
  const double angle = 0.5 * std::atan2(2 * b, a - d);  // eigenvector of the largest eigenvalue
  const double c = std::cos(angle), s = std::sin(angle);
  const double goal = f.along(c, s);
  // Bisection on the length: the share of energy along the smear falls as it grows.
  double lo = 0, hi = std::clamp(maxLengthPx, 2.0, double(kMaxTaps - 1));
  PatchLines lines;
  if (!lines.build(sharp, points, count, kTensorSide, kPatchHalf + 1, LineGeometry(MotionBlur{hi, angle}),
                   LineGeometry(MotionBlur{hi, angle}).half, scratch))
    return none;
  for (int it = 0; it < 7; ++it) {
    const double mid = 0.5 * (lo + hi);
    const LineGeometry line(MotionBlur{mid, angle});
    if (patchTensor(sharp, points, count, &line, &lines).along(c, s) > goal) lo = mid;
    else hi = mid;
  }
  MotionBlur out{0.5 * (lo + hi), angle};
  if (!out.any()) return none;
  return out;
}

MotionBlur refineMotionBlur(const cv::Mat& sharp, const cv::Mat& frame, const std::vector<cv::Point2f>& from,
                            const std::vector<cv::Point2f>& to, const MotionBlur& start, double maxLengthPx,
                            MotionBlurScratch& scratch) noexcept {
  const int count = std::min({static_cast<int>(from.size()), static_cast<int>(to.size()), kRefinePatches});
  if (count < 6 || sharp.size() != frame.size() || sharp.type() != CV_8UC1 || frame.type() != CV_8UC1) return start;
  if (scratch.patches.capacity() < static_cast<std::size_t>(kRefinePatches * kRefineSide * kRefineSide)) return start;
  scratch.patches.resize(static_cast<std::size_t>(count * kRefineSide * kRefineSide));  // within capacity
  sampleFramePatches(frame, from, to, count, scratch.patches.data());
  const double maxLength = std::clamp(maxLengthPx, 2.0, double(kMaxTaps - 1));
  // Golden-section search on the length around the start (the blur changes little from one
  // frame to the next), then the direction within +-6 degrees.
  double angle = start.angleRad;
  double lo = std::max(0.0, 0.5 * start.lengthPx - 2), hi = std::min(maxLength, 1.6 * start.lengthPx + 4);
  // The lengths along the start's direction read one set of lines.
  PatchLines lines;
  const int maxHalf = LineGeometry(MotionBlur{std::max(1.0, hi), angle}).half;
  const bool haveLines = lines.build(sharp, from, count, kRefineSide, kPatchHalf, LineGeometry(MotionBlur{hi, angle}), maxHalf, scratch);
  auto cost = [&](double length, double along) {
    const LineGeometry line(MotionBlur{std::max(1.0, length), along});
    const bool cached = haveLines && along == start.angleRad && line.half <= maxHalf;
    return mismatch(sharp, from, scratch.patches.data(), count, line, cached ? &lines : nullptr, scratch);
  };
  constexpr double kGolden = 0.6180339887498949;
  double x1 = hi - kGolden * (hi - lo), x2 = lo + kGolden * (hi - lo);
  double f1 = cost(x1, angle), f2 = cost(x2, angle);
  for (int it = 0; it < 8; ++it) {
    if (f1 < f2) {
      hi = x2, x2 = x1, f2 = f1;
      x1 = hi - kGolden * (hi - lo);
      f1 = cost(x1, angle);
    } else {
      lo = x1, x1 = x2, f1 = f2;
      x2 = lo + kGolden * (hi - lo);
      f2 = cost(x2, angle);
    }
  }
  const double length = 0.5 * (lo + hi);
  double best = cost(length, angle);
  constexpr double kStep = 3.0 * kPi / 180.0;
  for (double d : {-2 * kStep, -kStep, kStep, 2 * kStep})
    if (const double c = cost(length, start.angleRad + d); c < best) best = c, angle = start.angleRad + d;
  // Sharp explains it as well: no blur.
  if (length < 2 || cost(1.0, angle) <= best * 1.02) return {};
  return {length, angle};
}

namespace {

#if MARIONETTE_TRACKING_AVX2
// Outputs lo, lo + 8, ... eight at a time, as blurredRowBytes computes them (the same integer
// sums, the same float operations per lane, truncation to an integer as the scalar cast): the
// same bits. Returns the first output not done.
[[gnu::target("avx2")]] int blurredBytesAvx2(const int* line, int lo, int hi, int K, float scale, float end,
                                             const int* prefix, std::uint8_t* out) noexcept {
  const __m256 vs = _mm256_set1_ps(scale), ve = _mm256_set1_ps(end), half = _mm256_set1_ps(0.5f);
  const __m256 zero = _mm256_setzero_ps(), top = _mm256_set1_ps(255.0f);
  int i = lo;
  for (; i + 8 <= hi; i += 8) {
    const __m256i inner = _mm256_sub_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(prefix + i + 2 * K - lo)),
                                           _mm256_loadu_si256(reinterpret_cast<const __m256i*>(prefix + i + 1 - lo)));
    const __m256i ends = _mm256_add_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(line + i)),
                                          _mm256_loadu_si256(reinterpret_cast<const __m256i*>(line + i + 2 * K)));
    const __m256 v = _mm256_mul_ps(vs, _mm256_add_ps(_mm256_cvtepi32_ps(inner), _mm256_mul_ps(ve, _mm256_cvtepi32_ps(ends))));
    const __m256i q = _mm256_cvttps_epi32(_mm256_min_ps(_mm256_max_ps(_mm256_add_ps(v, half), zero), top));
    const __m128i words = _mm_packus_epi32(_mm256_castsi256_si128(q), _mm256_extracti128_si256(q, 1));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out + i), _mm_packus_epi16(words, words));
  }
  return i;
}
#endif

// Outputs lo .. hi - 1 of a sheared row as applyMotionBlur stores them: the line blur's value
// (lineBlurAlong's, with the running sum's integers taken from prefix sums: the same integers,
// the same float operations after them), rounded and clamped to a byte; eight at a time with
// AVX2 where `wide`. `prefix` has room for hi + 2K + 1 - lo entries.
void blurredRowBytes(const int* line, int lo, int hi, int K, float scale, float end, int* prefix, std::uint8_t* out,
                     bool wide) noexcept {
  if (K == 0) {
    for (int i = lo; i < hi; ++i)
      out[i] = static_cast<std::uint8_t>(std::min(std::max(static_cast<float>(line[i]) + 0.5f, 0.0f), 255.0f));
    return;
  }
  // prefix[j - lo] = line[lo] + ... + line[j - 1]; output i's inner taps sum to
  // prefix[i + 2K - lo] - prefix[i + 1 - lo].
  const int jEnd = hi + 2 * K;
  prefix[0] = 0;
  for (int j = lo; j < jEnd; ++j) prefix[j - lo + 1] = prefix[j - lo] + line[j];
  int i = lo;
#if MARIONETTE_TRACKING_AVX2
  if (wide) i = blurredBytesAvx2(line, lo, hi, K, scale, end, prefix, out);
#endif
  static_cast<void>(wide);
  for (; i < hi; ++i) {
    const int inner = prefix[i + 2 * K - lo] - prefix[i + 1 - lo];
    const float v = scale * (static_cast<float>(inner) + end * static_cast<float>(line[i] + line[i + 2 * K]));
    out[i] = static_cast<std::uint8_t>(std::min(std::max(v + 0.5f, 0.0f), 255.0f));  // minss/maxss: no branch
  }
}

// applyMotionBlur along one axis: each sheared row's values computed together, then stored.
template <bool AlongX>
bool applyAlong(const cv::Mat& image, const LineGeometry& g, const cv::Rect& r, cv::Mat& out, MotionBlurScratch& scratch,
                bool wide) noexcept {
  const int majorBegin = AlongX ? r.x : r.y, n = AlongX ? r.width : r.height, K = g.half;
  const auto need = static_cast<std::size_t>(n + 2 * K + 1);
  if (need > scratch.prefix.capacity() || need > scratch.rowBytes.capacity()) return false;
  scratch.prefix.resize(need);  // within capacity: no allocation
  scratch.rowBytes.resize(need);
  int* prefix = scratch.prefix.data();
  std::uint8_t* bytes = scratch.rowBytes.data();
  return forEachLineRow<AlongX>(image, g, r, scratch, [&](int b, int lo, int hi, const int* line, const int* shift) {
    blurredRowBytes(line, lo, hi, K, g.scale, g.end, prefix, bytes, wide);
    std::uint8_t* const data = out.data;
    const auto step = static_cast<std::ptrdiff_t>(out.step[0]);
    for (int i = lo; i < hi; ++i) {
      const std::ptrdiff_t major = majorBegin + i, minor = b + shift[i + K];
      data[AlongX ? minor * step + major : major * step + minor] = bytes[i];
    }
  });
}

}  // namespace

void applyMotionBlur(const cv::Mat& image, const MotionBlur& blur, const cv::Rect& region, cv::Mat& out,
                     MotionBlurScratch& scratch, bool wide) noexcept {
  if (!blur.any() || image.type() != CV_8UC1 || out.size() != image.size() || out.type() != CV_8UC1) return;
  const cv::Rect r = region & cv::Rect(0, 0, image.cols, image.rows);
  const LineGeometry g(blur);
  wide = wide && cpuHasAvx2();
  (void)(g.alongX ? applyAlong<true>(image, g, r, out, scratch, wide) : applyAlong<false>(image, g, r, out, scratch, wide));
}

}  // namespace marionette::ar
