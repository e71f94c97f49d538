#include "perspective_warp.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include "cpu_avx2.hpp"

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

// One output pixel from its source position in 1/32 px (X, Y): the bilinear mix of the four
// taps, or `border` where all four are outside the source.
struct WarpSource {
  const std::uint8_t* s;
  std::ptrdiff_t step;
  int sw, sh;
  std::uint8_t border;
  [[nodiscard]] std::uint8_t at(int X, int Y) const noexcept {
    const int sx = X >> kSubpixelBits, sy = Y >> kSubpixelBits;  // floor
    const int ax = X & (kSubpixel - 1), ay = Y & (kSubpixel - 1);
    int p00, p01, p10, p11;
    if (sx >= 0 && sy >= 0 && sx < sw - 1 && sy < sh - 1) {
      const std::uint8_t* p = s + sy * step + sx;
      p00 = p[0], p01 = p[1], p10 = p[step], p11 = p[step + 1];
    } else if (sx >= sw || sx + 1 < 0 || sy >= sh || sy + 1 < 0) {
      return border;
    } else {
      const auto tap = [&](int x, int y) noexcept -> int {
        return (x >= 0 && y >= 0 && x < sw && y < sh) ? s[y * step + x] : border;
      };
      p00 = tap(sx, sy), p01 = tap(sx + 1, sy), p10 = tap(sx, sy + 1), p11 = tap(sx + 1, sy + 1);
    }
    // Weights in 1/1024: exact, and summing to 1024.
    const int v = (kSubpixel - ay) * ((kSubpixel - ax) * p00 + ax * p01) + ay * ((kSubpixel - ax) * p10 + ax * p11);
    return static_cast<std::uint8_t>((v + 512) >> 10);
  }
};

// Pixel x's source position, in 1/32 px, on the row whose terms are bx, by, bw (m's second and
// third columns at y). The same expression per pixel as OpenCV's (not an accumulated sum): the
// same rounding.
inline void sourcePosition(const cv::Matx33d& m, double bx, double by, double bw, int x, int& X, int& Y) noexcept {
  double w = bw + m(2, 0) * x;
  w = w != 0 ? kSubpixel / w : 0.0;
  X = roundToInt(std::clamp((bx + m(0, 0) * x) * w, -kCoordinateLimit, kCoordinateLimit));
  Y = roundToInt(std::clamp((by + m(1, 0) * x) * w, -kCoordinateLimit, kCoordinateLimit));
}

// Pixels x0 .. x1 - 1 of row y.
void warpRow(const WarpSource& src, const cv::Matx33d& m, int y, int x0, int x1, std::uint8_t* out) noexcept {
  const double bx = m(0, 1) * y + m(0, 2), by = m(1, 1) * y + m(1, 2), bw = m(2, 1) * y + m(2, 2);
  for (int x = x0; x < x1; ++x) {
    int X = 0, Y = 0;
    sourcePosition(m, bx, by, bw, x, X, Y);
    out[x] = src.at(X, Y);
  }
}

#if MARIONETTE_TRACKING_AVX2
// The same row with AVX2, in chunks: the source positions of the chunk four pixels at a time
// (the same double operations per lane, AVX2 without FMA: a multiply and an add round as the
// scalar ones do; the same rounding to an integer, the current mode, as cvtsd2si), then the
// taps eight pixels at a time by gathers where all eight lie inside the source, the scalar
// mix elsewhere (the same integers). So the same bits. A NaN position clamps to the limit
// here and to INT_MIN in the scalar loop: both are outside the source, so both give `border`.
[[gnu::target("avx2")]] void warpRowAvx2(const WarpSource& src, const cv::Matx33d& m, int y, int x0, int x1,
                                         std::uint8_t* out) noexcept {
  const double bx = m(0, 1) * y + m(0, 2), by = m(1, 1) * y + m(1, 2), bw = m(2, 1) * y + m(2, 2);
  const __m256d vbx = _mm256_set1_pd(bx), vby = _mm256_set1_pd(by), vbw = _mm256_set1_pd(bw);
  const __m256d m00 = _mm256_set1_pd(m(0, 0)), m10 = _mm256_set1_pd(m(1, 0)), m20 = _mm256_set1_pd(m(2, 0));
  const __m256d sub = _mm256_set1_pd(kSubpixel), zero = _mm256_setzero_pd();
  const __m256d lo = _mm256_set1_pd(-kCoordinateLimit), hi = _mm256_set1_pd(kCoordinateLimit);
  const __m256d lanes = _mm256_setr_pd(0, 1, 2, 3);
  // Gathers read 4 bytes from a tap pair's first: the fast path needs 2 columns to spare,
  // and a row below.
  const __m256i zeroI = _mm256_setzero_si256(), maxX = _mm256_set1_epi32(src.sw - 4), maxY = _mm256_set1_epi32(src.sh - 2);
  const __m256i minusOne = _mm256_set1_epi32(-1), lastX = _mm256_set1_epi32(src.sw - 1), lastY = _mm256_set1_epi32(src.sh - 1);
  const __m256i step = _mm256_set1_epi32(static_cast<int>(src.step)), low5 = _mm256_set1_epi32(kSubpixel - 1);
  const __m256i full = _mm256_set1_epi32(kSubpixel), byte = _mm256_set1_epi32(0xff), half = _mm256_set1_epi32(512);
  const auto* base = reinterpret_cast<const int*>(src.s);
  const auto* below = reinterpret_cast<const int*>(src.s + src.step);
  constexpr int kChunk = 64;
  alignas(32) std::int32_t X[kChunk], Y[kChunk];
  for (int c0 = x0; c0 < x1; c0 += kChunk) {
    const int n = std::min(kChunk, x1 - c0);
    int i = 0;
    for (; i + 4 <= n; i += 4) {
      const __m256d vx = _mm256_add_pd(_mm256_set1_pd(c0 + i), lanes);
      __m256d w = _mm256_add_pd(vbw, _mm256_mul_pd(m20, vx));
      w = _mm256_and_pd(_mm256_div_pd(sub, w), _mm256_cmp_pd(w, zero, _CMP_NEQ_UQ));
      const __m256d fx = _mm256_min_pd(_mm256_max_pd(_mm256_mul_pd(_mm256_add_pd(vbx, _mm256_mul_pd(m00, vx)), w), lo), hi);
      const __m256d fy = _mm256_min_pd(_mm256_max_pd(_mm256_mul_pd(_mm256_add_pd(vby, _mm256_mul_pd(m10, vx)), w), lo), hi);
      _mm_store_si128(reinterpret_cast<__m128i*>(X + i), _mm256_cvtpd_epi32(fx));
      _mm_store_si128(reinterpret_cast<__m128i*>(Y + i), _mm256_cvtpd_epi32(fy));
    }
    for (; i < n; ++i) sourcePosition(m, bx, by, bw, c0 + i, X[i], Y[i]);
    std::uint8_t* o = out + c0;
    i = 0;
    for (; i + 8 <= n; i += 8) {
      const __m256i vX = _mm256_load_si256(reinterpret_cast<const __m256i*>(X + i));
      const __m256i vY = _mm256_load_si256(reinterpret_cast<const __m256i*>(Y + i));
      const __m256i sx = _mm256_srai_epi32(vX, kSubpixelBits), sy = _mm256_srai_epi32(vY, kSubpixelBits);
      const __m256i outside = _mm256_or_si256(_mm256_or_si256(_mm256_cmpgt_epi32(zeroI, sx), _mm256_cmpgt_epi32(sx, maxX)),
                                              _mm256_or_si256(_mm256_cmpgt_epi32(zeroI, sy), _mm256_cmpgt_epi32(sy, maxY)));
      if (!_mm256_testz_si256(outside, outside)) {
        // All eight wholly outside the source (no tap inside): the border, as at() gives it.
        const __m256i away = _mm256_or_si256(
            _mm256_or_si256(_mm256_cmpgt_epi32(sx, lastX), _mm256_cmpgt_epi32(minusOne, sx)),
            _mm256_or_si256(_mm256_cmpgt_epi32(sy, lastY), _mm256_cmpgt_epi32(minusOne, sy)));
        if (_mm256_movemask_epi8(away) == -1) {
          std::memset(o + i, src.border, 8);
          continue;
        }
        for (int k = 0; k < 8; ++k) o[i + k] = src.at(X[i + k], Y[i + k]);
        continue;
      }
      const __m256i offset = _mm256_add_epi32(_mm256_mullo_epi32(sy, step), sx);
      const __m256i top = _mm256_i32gather_epi32(base, offset, 1), bottom = _mm256_i32gather_epi32(below, offset, 1);
      const __m256i ax = _mm256_and_si256(vX, low5), ay = _mm256_and_si256(vY, low5);
      const __m256i rx = _mm256_sub_epi32(full, ax), ry = _mm256_sub_epi32(full, ay);
      const __m256i p00 = _mm256_and_si256(top, byte), p01 = _mm256_and_si256(_mm256_srli_epi32(top, 8), byte);
      const __m256i p10 = _mm256_and_si256(bottom, byte), p11 = _mm256_and_si256(_mm256_srli_epi32(bottom, 8), byte);
      const __m256i upper = _mm256_add_epi32(_mm256_mullo_epi32(rx, p00), _mm256_mullo_epi32(ax, p01));
      const __m256i lower = _mm256_add_epi32(_mm256_mullo_epi32(rx, p10), _mm256_mullo_epi32(ax, p11));
      const __m256i v = _mm256_srai_epi32(
          _mm256_add_epi32(_mm256_add_epi32(_mm256_mullo_epi32(ry, upper), _mm256_mullo_epi32(ay, lower)), half), 10);
      // 0..255 in every lane: pack to bytes in lane order.
      const __m128i words = _mm_packus_epi32(_mm256_castsi256_si128(v), _mm256_extracti128_si256(v, 1));
      _mm_storel_epi64(reinterpret_cast<__m128i*>(o + i), _mm_packus_epi16(words, words));
    }
    for (; i < n; ++i) o[i] = src.at(X[i], Y[i]);
  }
}

#endif

}  // namespace

bool warpPerspectiveRegion(const cv::Mat& src, const cv::Matx33d& srcToDst, cv::Mat& dst, cv::Rect region,
                           std::uint8_t border, bool wide) noexcept {
  if (src.type() != CV_8UC1 || dst.type() != CV_8UC1 || src.empty() || dst.empty()) return false;
  cv::Matx33d m;
  if (!invertHomography(srcToDst, m)) return false;
  region &= cv::Rect(0, 0, dst.cols, dst.rows);
  const WarpSource source{src.data, static_cast<std::ptrdiff_t>(src.step[0]), src.cols, src.rows, border};
#if MARIONETTE_TRACKING_AVX2
  if (wide && cpuHasAvx2()) {
    for (int y = region.y; y < region.y + region.height; ++y)
      warpRowAvx2(source, m, y, region.x, region.x + region.width, dst.ptr<std::uint8_t>(y));
    return true;
  }
#endif
  static_cast<void>(wide);
  for (int y = region.y; y < region.y + region.height; ++y)
    warpRow(source, m, y, region.x, region.x + region.width, dst.ptr<std::uint8_t>(y));
  return true;
}

}  // namespace marionette::ar
