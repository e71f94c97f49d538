#include "perspective_warp.hpp"

#include <algorithm>
#include <cmath>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace marionette::ar {

bool invertHomography(const cv::Matx33d& h, cv::Matx33d& inverse) noexcept {
  const double c00 = h(1, 1) * h(2, 2) - h(1, 2) * h(2, 1);
  const double c01 = h(1, 2) * h(2, 0) - h(1, 0) * h(2, 2);
  const double c02 = h(1, 0) * h(2, 1) - h(1, 1) * h(2, 0);
  const double det = h(0, 0) * c00 + h(0, 1) * c01 + h(0, 2) * c02;
  if (!std::isfinite(det) || det == 0) return false;
  const double s = 1.0 / det;
  inverse = cv::Matx33d(c00 * s, (h(0, 2) * h(2, 1) - h(0, 1) * h(2, 2)) * s, (h(0, 1) * h(1, 2) - h(0, 2) * h(1, 1)) * s,
                        c01 * s, (h(0, 0) * h(2, 2) - h(0, 2) * h(2, 0)) * s, (h(0, 2) * h(1, 0) - h(0, 0) * h(1, 2)) * s,
                        c02 * s, (h(0, 1) * h(2, 0) - h(0, 0) * h(2, 1)) * s, (h(0, 0) * h(1, 1) - h(0, 1) * h(1, 0)) * s);
  for (int i = 0; i < 9; ++i)
    if (!std::isfinite(inverse.val[i])) return false;
  return true;
}

namespace {

constexpr int kSubpixelBits = 5;  // positions to 1/32 px, as OpenCV's INTER_TAB_SIZE
constexpr int kSubpixel = 1 << kSubpixelBits;
constexpr double kCoordinateLimit = 1 << 28;  // far outside any image, and safe in an int after the shift

// Round to nearest, ties to even (lrint in the default mode, as cvRound), inline: lrint is a
// libm call per coordinate.
inline int roundToInt(double v) noexcept {
#if defined(__SSE2__)
  return _mm_cvtsd_si32(_mm_set_sd(v));
#else
  return static_cast<int>(std::lrint(v));
#endif
}

}  // namespace

bool warpPerspectiveRegion(const cv::Mat& src, const cv::Matx33d& srcToDst, cv::Mat& dst, cv::Rect region,
                           std::uint8_t border) noexcept {
  if (src.type() != CV_8UC1 || dst.type() != CV_8UC1 || src.empty() || dst.empty()) return false;
  cv::Matx33d m;
  if (!invertHomography(srcToDst, m)) return false;
  region &= cv::Rect(0, 0, dst.cols, dst.rows);
  const int sw = src.cols, sh = src.rows;
  const std::uint8_t* const s = src.data;
  const auto sstep = static_cast<std::ptrdiff_t>(src.step[0]);
  const auto tap = [&](int x, int y) noexcept -> int {
    return (x >= 0 && y >= 0 && x < sw && y < sh) ? s[y * sstep + x] : border;
  };
  for (int y = region.y; y < region.y + region.height; ++y) {
    std::uint8_t* out = dst.ptr<std::uint8_t>(y);
    // The same expression per pixel as OpenCV's (not an accumulated sum): the same rounding.
    const double x0 = m(0, 1) * y + m(0, 2), y0 = m(1, 1) * y + m(1, 2), w0 = m(2, 1) * y + m(2, 2);
    for (int x = region.x; x < region.x + region.width; ++x) {
      double w = w0 + m(2, 0) * x;
      w = w != 0 ? kSubpixel / w : 0.0;
      const double fx = std::clamp((x0 + m(0, 0) * x) * w, -kCoordinateLimit, kCoordinateLimit);
      const double fy = std::clamp((y0 + m(1, 0) * x) * w, -kCoordinateLimit, kCoordinateLimit);
      const int X = roundToInt(fx), Y = roundToInt(fy);
      const int sx = X >> kSubpixelBits, sy = Y >> kSubpixelBits;  // floor
      const int ax = X & (kSubpixel - 1), ay = Y & (kSubpixel - 1);
      int p00, p01, p10, p11;
      if (sx >= 0 && sy >= 0 && sx < sw - 1 && sy < sh - 1) {
        const std::uint8_t* p = s + sy * sstep + sx;
        p00 = p[0], p01 = p[1], p10 = p[sstep], p11 = p[sstep + 1];
      } else if (sx >= sw || sx + 1 < 0 || sy >= sh || sy + 1 < 0) {
        out[x] = border;
        continue;
      } else {
        p00 = tap(sx, sy), p01 = tap(sx + 1, sy), p10 = tap(sx, sy + 1), p11 = tap(sx + 1, sy + 1);
      }
      // Weights in 1/1024: exact, and summing to 1024.
      const int v = (kSubpixel - ay) * ((kSubpixel - ax) * p00 + ax * p01) + ay * ((kSubpixel - ax) * p10 + ax * p11);
      out[x] = static_cast<std::uint8_t>((v + 512) >> 10);
    }
  }
  return true;
}

}  // namespace marionette::ar
