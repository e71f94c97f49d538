#include "lucas_kanade.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>

namespace marionette::ar {

namespace {

// Reflect-101 (cv::BORDER_REFLECT_101: ... 2 1 | 0 1 2 ... n-1 | n-2 ...), any distance out.
int reflect101(int i, int n) noexcept {
  if (n == 1) return 0;
  while (i < 0 || i >= n) i = i < 0 ? -i : 2 * n - 2 - i;
  return i;
}

constexpr int kLanes = 8;  // independent partial sums: vectorizable, and the same order every time
constexpr std::size_t padded(int n) noexcept { return static_cast<std::size_t>((n + kLanes - 1) / kLanes * kLanes); }

}  // namespace

bool ImagePyramid::configure(int width, int height, int levels) {
  if (width < 1 || height < 1 || levels < 0 || levels > kMaxLevels) return false;
  width_ = width;
  height_ = height;
  configured_ = levels;
  built_ = 0;
  int w = width, h = height;
  for (int l = 1; l <= levels; ++l) {
    w = (w + 1) / 2;
    h = (h + 1) / 2;
    auto& buffer = storage_[static_cast<std::size_t>(l - 1)];
    buffer.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0);
    views_[static_cast<std::size_t>(l)] = GreyLevel{buffer.data(), w, h, w};
  }
  columnSums_.assign(static_cast<std::size_t>(2 * width + 8), 0);
  return true;
}

bool ImagePyramid::start(const cv::Mat& image) noexcept {
  built_ = 0;
  if (image.type() != CV_8UC1 || image.cols != width_ || image.rows != height_ || columnSums_.empty()) return false;
  views_[0] = GreyLevel{image.data, image.cols, image.rows, static_cast<std::ptrdiff_t>(image.step[0])};
  return true;
}

bool ImagePyramid::build(const cv::Mat& image) noexcept {
  if (!start(image)) return false;
  for (int l = 1; l <= configured_; ++l) {
    const GreyLevel& d = views_[static_cast<std::size_t>(l)];
    downsample(l, cv::Rect(0, 0, d.width, d.height));
  }
  built_ = configured_;
  return true;
}

bool ImagePyramid::buildRegion(const cv::Mat& image, cv::Rect region, std::uint8_t outside) noexcept {
  if (!start(image)) return false;
  cv::Rect r = region & cv::Rect(0, 0, width_, height_);
  for (int l = 1; l <= configured_; ++l) {
    const GreyLevel& d = views_[static_cast<std::size_t>(l)];
    std::memset(const_cast<std::uint8_t*>(d.data), outside, static_cast<std::size_t>(d.stride * d.height));
    if (r.empty()) continue;
    // Halved and rounded outwards, plus a pixel: the outputs whose 5-tap footprint reaches in.
    const int x0 = std::max(0, r.x / 2 - 1), y0 = std::max(0, r.y / 2 - 1);
    const int x1 = std::min(d.width, (r.x + r.width + 1) / 2 + 1), y1 = std::min(d.height, (r.y + r.height + 1) / 2 + 1);
    r = cv::Rect(x0, y0, x1 - x0, y1 - y0);
    downsample(l, r);
  }
  built_ = configured_;
  return true;
}

cv::Mat ImagePyramid::levelMat(int l) const noexcept {
  const GreyLevel& v = level(l);
  if (!v.data) return {};
  return cv::Mat(v.height, v.width, CV_8UC1, const_cast<std::uint8_t*>(v.data), static_cast<std::size_t>(v.stride));
}

void ImagePyramid::downsample(int level, cv::Rect dstRegion) noexcept {
  const GreyLevel& s = views_[static_cast<std::size_t>(level - 1)];
  const GreyLevel& d = views_[static_cast<std::size_t>(level)];
  // Source columns c0..c1 feed the outputs x0..x1 - 1 (2x - 2 .. 2x + 2).
  const int c0 = 2 * dstRegion.x - 2, c1 = 2 * (dstRegion.x + dstRegion.width - 1) + 2;
  const int inner0 = std::max(c0, 0), inner1 = std::min(c1, s.width - 1);
  int* sums = columnSums_.data();
  for (int y = dstRegion.y; y < dstRegion.y + dstRegion.height; ++y) {
    const std::uint8_t* r0 = s.row(reflect101(2 * y - 2, s.height));
    const std::uint8_t* r1 = s.row(reflect101(2 * y - 1, s.height));
    const std::uint8_t* r2 = s.row(reflect101(2 * y, s.height));
    const std::uint8_t* r3 = s.row(reflect101(2 * y + 1, s.height));
    const std::uint8_t* r4 = s.row(reflect101(2 * y + 2, s.height));
    const auto vertical = [&](int c) noexcept { return r0[c] + r4[c] + 4 * (r1[c] + r3[c]) + 6 * r2[c]; };
    for (int c = c0; c < inner0; ++c) sums[c - c0] = vertical(reflect101(c, s.width));
    for (int c = inner0; c <= inner1; ++c) sums[c - c0] = vertical(c);
    for (int c = std::max(inner1 + 1, c0); c <= c1; ++c) sums[c - c0] = vertical(reflect101(c, s.width));
    std::uint8_t* out = const_cast<std::uint8_t*>(d.row(y));
    for (int x = dstRegion.x; x < dstRegion.x + dstRegion.width; ++x) {
      const int* q = sums + (2 * x - 2 - c0);
      const int v = q[0] + q[4] + 4 * (q[1] + q[3]) + 6 * q[2];
      out[x] = static_cast<std::uint8_t>((v + 128) >> 8);
    }
  }
}

LucasKanade::LucasKanade()
    : patch_(static_cast<std::size_t>((kMaxWindow + 2) * (kMaxWindow + 2))),
      values_(static_cast<std::size_t>(kMaxWindow) * padded(kMaxWindow)),
      gx_(values_.size()),
      gy_(values_.size()),
      diff_(values_.size()) {}

namespace {

// Bilinear samples of `img` over a cols x rows grid whose first sample is at (x + ax, y + ay).
// Fixed-width rows of 16 (the window of 15 padded) get a loop the compiler vectorizes.
template <int kCols>
void sampleRows(const GreyLevel& img, int x, int y, float w00, float w01, float w10, float w11, int cols, int rows,
                float* out) noexcept {
  const int n = kCols > 0 ? kCols : cols;
  for (int r = 0; r < rows; ++r) {
    const std::uint8_t* a = img.row(y + r) + x;
    const std::uint8_t* b = a + img.stride;
    float* o = out + r * n;
    for (int c = 0; c < n; ++c) o[c] = w00 * a[c] + w01 * a[c + 1] + w10 * b[c] + w11 * b[c + 1];
  }
}

void sampleGrid(const GreyLevel& img, int x, int y, float ax, float ay, int cols, int rows, float* out) noexcept {
  const float w00 = (1 - ax) * (1 - ay), w01 = ax * (1 - ay), w10 = (1 - ax) * ay, w11 = ax * ay;
  if (x >= 0 && y >= 0 && x + cols < img.width && y + rows < img.height) {
    if (cols == 16) sampleRows<16>(img, x, y, w00, w01, w10, w11, cols, rows, out);
    else sampleRows<0>(img, x, y, w00, w01, w10, w11, cols, rows, out);
    return;
  }
  // Near or past the border: reflect-101, as OpenCV's padded pyramids.
  for (int r = 0; r < rows; ++r) {
    const std::uint8_t* a = img.row(reflect101(y + r, img.height));
    const std::uint8_t* b = img.row(reflect101(y + r + 1, img.height));
    float* o = out + r * cols;
    for (int c = 0; c < cols; ++c) {
      const int c0 = reflect101(x + c, img.width), c1 = reflect101(x + c + 1, img.width);
      o[c] = w00 * a[c0] + w01 * a[c1] + w10 * b[c0] + w11 * b[c1];
    }
  }
}

}  // namespace

bool LucasKanade::trackOne(const GreyLevel& t, const GreyLevel& f, cv::Point2f prev, cv::Point2f& next, int n,
                           const LucasKanadeParams& params) noexcept {
  const float half = static_cast<float>(n - 1) * 0.5f;
  const cv::Point2f p = prev - cv::Point2f(half, half);
  const int ix = static_cast<int>(std::floor(p.x)), iy = static_cast<int>(std::floor(p.y));
  if (ix < -n || ix >= t.width || iy < -n || iy >= t.height) return false;
  // The template and its gradient over the window, from samples one pixel beyond it (bilinear
  // sampling at a fixed offset commutes with the gradient filter: the gradient of the samples is
  // the sampled gradient).
  const int m = n + 2;
  // Rows of the window padded to whole lanes: the padding has zero gradient, so it adds
  // exactly nothing to the sums whatever the frame's samples there.
  const int stride = static_cast<int>(padded(n));
  const auto lanes = static_cast<std::size_t>(n * stride);
  std::fill_n(values_.begin(), lanes, 0.f);
  std::fill_n(gx_.begin(), lanes, 0.f);
  std::fill_n(gy_.begin(), lanes, 0.f);
  sampleGrid(t, ix - 1, iy - 1, p.x - static_cast<float>(ix), p.y - static_cast<float>(iy), m, m, patch_.data());
  const float* P = patch_.data();
  for (int r = 0; r < n; ++r) {
    const float* up = P + r * m + 1;
    const float* mid = up + m;
    const float* down = mid + m;
    float* v = values_.data() + r * stride;
    float* gx = gx_.data() + r * stride;
    float* gy = gy_.data() + r * stride;
    if (params.gradient == LkGradient::Scharr) {
      for (int c = 0; c < n; ++c) {
        gx[c] = (3 * (up[c + 1] - up[c - 1] + down[c + 1] - down[c - 1]) + 10 * (mid[c + 1] - mid[c - 1])) * (1.f / 32);
        gy[c] = (3 * (down[c - 1] - up[c - 1] + down[c + 1] - up[c + 1]) + 10 * (down[c] - up[c])) * (1.f / 32);
      }
    } else {
      for (int c = 0; c < n; ++c) {
        gx[c] = (mid[c + 1] - mid[c - 1]) * 0.5f;
        gy[c] = (down[c] - up[c]) * 0.5f;
      }
    }
    for (int c = 0; c < n; ++c) v[c] = mid[c];
  }
  float s11[kLanes] = {}, s12[kLanes] = {}, s22[kLanes] = {};
  for (std::size_t k = 0; k < lanes; k += kLanes)
    for (int l = 0; l < kLanes; ++l) {
      const std::size_t i = k + static_cast<std::size_t>(l);
      s11[l] += gx_[i] * gx_[i];
      s12[l] += gx_[i] * gy_[i];
      s22[l] += gy_[i] * gy_[i];
    }
  double a11 = 0, a12 = 0, a22 = 0;
  for (int l = 0; l < kLanes; ++l) a11 += s11[l], a12 += s12[l], a22 += s22[l];
  const int count = n * n;
  // OpenCV's units: its gradients are 32x, its sums scaled by 2^-20.
  const double minEig = (a11 + a22 - std::sqrt((a11 - a22) * (a11 - a22) + 4 * a12 * a12)) / (2.0 * count * 1024.0);
  const double det = a11 * a22 - a12 * a12;
  if (!(minEig >= params.minEigThreshold) || !(det / (1024.0 * 1024.0) >= FLT_EPSILON)) return false;
  const double inv = 1.0 / det;

  cv::Point2f q = next - cv::Point2f(half, half), previousDelta(0, 0);
  const double eps2 = params.epsilon * params.epsilon;
  for (int j = 0; j < params.maxIterations; ++j) {
    if (!std::isfinite(q.x) || !std::isfinite(q.y)) return false;
    const int jx = static_cast<int>(std::floor(q.x)), jy = static_cast<int>(std::floor(q.y));
    if (jx < -n || jx >= f.width || jy < -n || jy >= f.height) return false;  // left the image
    sampleGrid(f, jx, jy, q.x - static_cast<float>(jx), q.y - static_cast<float>(jy), stride, n, diff_.data());
    float s1[kLanes] = {}, s2[kLanes] = {};
    for (std::size_t k = 0; k < lanes; k += kLanes)
      for (int l = 0; l < kLanes; ++l) {
        const std::size_t i = k + static_cast<std::size_t>(l);
        const float d = diff_[i] - values_[i];
        s1[l] += d * gx_[i];
        s2[l] += d * gy_[i];
      }
    double b1 = 0, b2 = 0;
    for (int l = 0; l < kLanes; ++l) {
      b1 += s1[l];
      b2 += s2[l];
    }
    const cv::Point2f delta(static_cast<float>((a12 * b2 - a22 * b1) * inv), static_cast<float>((a12 * b1 - a11 * b2) * inv));
    q += delta;
    next = q + cv::Point2f(half, half);
    if (double(delta.x) * delta.x + double(delta.y) * delta.y <= eps2) break;
    // Bouncing between two positions: their middle.
    if (j > 0 && std::abs(delta.x + previousDelta.x) < 0.01f && std::abs(delta.y + previousDelta.y) < 0.01f) {
      next -= delta * 0.5f;
      break;
    }
    previousDelta = delta;
  }
  return true;
}

int LucasKanade::track(const ImagePyramid& templ, const ImagePyramid& frame, std::span<const cv::Point2f> from,
                       std::span<cv::Point2f> to, std::span<std::uint8_t> status, const LucasKanadeParams& params) noexcept {
  const std::size_t count = std::min({from.size(), to.size(), status.size()});
  for (std::size_t i = 0; i < status.size(); ++i) status[i] = 0;
  const int n = params.window;
  const int coarse = params.coarseWindow > 0 ? params.coarseWindow : n;
  if (n < 3 || n > kMaxWindow || n % 2 == 0 || coarse < 3 || coarse > kMaxWindow || coarse % 2 == 0 ||
      params.maxIterations < 1 || !(params.epsilon >= 0) || !(params.minEigThreshold >= 0))
    return 0;
  const GreyLevel& t0 = templ.level(0);
  const GreyLevel& f0 = frame.level(0);
  if (!t0.data || !f0.data || t0.width != f0.width || t0.height != f0.height) return 0;
  int top = std::min({params.levels, templ.levels(), frame.levels()});
  while (top > 0 && (templ.level(top).width <= coarse || templ.level(top).height <= coarse)) --top;
  if (top < 0) top = 0;
  int found = 0;
  for (std::size_t i = 0; i < count; ++i) {
    if (!std::isfinite(from[i].x) || !std::isfinite(from[i].y) || !std::isfinite(to[i].x) || !std::isfinite(to[i].y))
      continue;
    cv::Point2f next;
    bool ok = false;
    for (int level = top; level >= 0; --level) {
      const float scale = 1.f / static_cast<float>(1 << level);
      next = level == top ? to[i] * scale : next * 2.f;
      // A coarse level without a result leaves the guess as it was; level 0 decides.
      ok = trackOne(templ.level(level), frame.level(level), from[i] * scale, next, level == 0 ? n : coarse, params);
    }
    to[i] = next;
    if (ok && std::isfinite(next.x) && std::isfinite(next.y)) {
      status[i] = 1;
      ++found;
    }
  }
  return found;
}

}  // namespace marionette::ar
