#include "lucas_kanade.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include "cpu_avx2.hpp"

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

bool ImagePyramid::configure(int width, int height, int levels, bool wide) {
  if (width < 1 || height < 1 || levels < 0 || levels > kMaxLevels) return false;
  wide_ = wide;
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
  columnSums_.assign(static_cast<std::size_t>(2 * width + 40), 0);  // + what the AVX2 loads read past a row
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

namespace {

#if MARIONETTE_TRACKING_AVX2

// The vertical 5-tap sums of columns c .. c + count - 1 (inside the rows), sixteen at a time
// in 16 bits (at most 16 x 255): the same integers as the scalar loop. Returns the columns done.
[[gnu::target("avx2")]] int verticalSumsAvx2(const std::uint8_t* const r[5], int c, int count, std::uint16_t* out) noexcept {
  int done = 0;
  for (; done + 16 <= count; done += 16) {
    __m256i v[5];
    for (int k = 0; k < 5; ++k) v[k] = _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(r[k] + c + done)));
    const __m256i s = _mm256_add_epi16(_mm256_add_epi16(_mm256_add_epi16(v[0], v[4]), _mm256_slli_epi16(_mm256_add_epi16(v[1], v[3]), 2)),
                                       _mm256_mullo_epi16(v[2], _mm256_set1_epi16(6)));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + done), s);
  }
  return done;
}

// Outputs x .. x + count - 1 of a row from the vertical sums, eight at a time: each 32-bit lane
// of a load holds a pair (even, odd) of sums, and loads one and two pairs further give the
// rest of the 5 taps; the sum (at most 65280 + 128) and the shift are the scalar loop's.
// `q` points at the sums of output x's first tap; reads one sum past the last output's.
[[gnu::target("avx2")]] int horizontalAvx2(const std::uint16_t* q, int count, std::uint8_t* out) noexcept {
  const __m256i low = _mm256_set1_epi32(0xffff), round = _mm256_set1_epi32(128);
  int done = 0;
  for (; done + 8 <= count; done += 8) {
    const std::uint16_t* p = q + 2 * done;
    const __m256i v0 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p));
    const __m256i v1 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p + 2));
    const __m256i v2 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p + 4));
    const __m256i q0 = _mm256_and_si256(v0, low), q1 = _mm256_srli_epi32(v0, 16);
    const __m256i q2 = _mm256_and_si256(v1, low), q3 = _mm256_srli_epi32(v1, 16), q4 = _mm256_and_si256(v2, low);
    const __m256i sum = _mm256_add_epi32(_mm256_add_epi32(_mm256_add_epi32(q0, q4), _mm256_slli_epi32(_mm256_add_epi32(q1, q3), 2)),
                                         _mm256_mullo_epi32(q2, _mm256_set1_epi32(6)));
    const __m256i v = _mm256_srli_epi32(_mm256_add_epi32(sum, round), 8);
    const __m128i words = _mm_packus_epi32(_mm256_castsi256_si128(v), _mm256_extracti128_si256(v, 1));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out + done), _mm_packus_epi16(words, words));
  }
  return done;
}
#endif

}  // namespace

void ImagePyramid::downsample(int level, cv::Rect dstRegion) noexcept {
  const GreyLevel& s = views_[static_cast<std::size_t>(level - 1)];
  const GreyLevel& d = views_[static_cast<std::size_t>(level)];
  // Source columns c0..c1 feed the outputs x0..x1 - 1 (2x - 2 .. 2x + 2).
  const int c0 = 2 * dstRegion.x - 2, c1 = 2 * (dstRegion.x + dstRegion.width - 1) + 2;
  const int inner0 = std::max(c0, 0), inner1 = std::min(c1, s.width - 1);
  std::uint16_t* sums = columnSums_.data();
  [[maybe_unused]] const bool wide = wide_ && cpuHasAvx2();
  for (int y = dstRegion.y; y < dstRegion.y + dstRegion.height; ++y) {
    const std::uint8_t* const r[5] = {s.row(reflect101(2 * y - 2, s.height)), s.row(reflect101(2 * y - 1, s.height)),
                                      s.row(reflect101(2 * y, s.height)), s.row(reflect101(2 * y + 1, s.height)),
                                      s.row(reflect101(2 * y + 2, s.height))};
    const auto vertical = [&](int c) noexcept {
      return static_cast<std::uint16_t>(r[0][c] + r[4][c] + 4 * (r[1][c] + r[3][c]) + 6 * r[2][c]);
    };
    for (int c = c0; c < inner0; ++c) sums[c - c0] = vertical(reflect101(c, s.width));
    int c = inner0;
#if MARIONETTE_TRACKING_AVX2
    if (wide && inner1 >= inner0) c += verticalSumsAvx2(r, inner0, inner1 + 1 - inner0, sums + (inner0 - c0));
#endif
    for (; c <= inner1; ++c) sums[c - c0] = vertical(c);
    for (c = std::max(inner1 + 1, c0); c <= c1; ++c) sums[c - c0] = vertical(reflect101(c, s.width));
    std::uint8_t* out = const_cast<std::uint8_t*>(d.row(y));
    int x = dstRegion.x;
#if MARIONETTE_TRACKING_AVX2
    if (wide) x += horizontalAvx2(sums + (2 * x - 2 - c0), dstRegion.x + dstRegion.width - x, out + x);
#endif
    for (; x < dstRegion.x + dstRegion.width; ++x) {
      const std::uint16_t* q = sums + (2 * x - 2 - c0);
      const int v = q[0] + q[4] + 4 * (q[1] + q[3]) + 6 * q[2];
      out[x] = static_cast<std::uint8_t>((v + 128) >> 8);
    }
  }
}

LucasKanade::LucasKanade()
    : patch_(static_cast<std::size_t>((kMaxWindow + 2) * padded(kMaxWindow + 2) + kLanes)),  // + the last lanes' reads
      values_(static_cast<std::size_t>(kMaxWindow) * padded(kMaxWindow)),
      gx_(values_.size()),
      gy_(values_.size()),
      samples_(values_.size()),
      border_(static_cast<std::size_t>((kMaxWindow + 3) * (padded(kMaxWindow + 2) + 1))) {}

namespace {

// Fixed point, as cv::calcOpticalFlowPyrLK: bilinear weights in 1/2^14, samples with 5
// fractional bits (0..8160), gradients 32 times the grey levels' per pixel (+-4080). Products
// of a difference and a gradient (+-2^25) sum exactly in 32 bits over a row of up to 64 pixels
// (two products per lane and 8-pixel group), and rows sum in 64 bits: the same bits with or
// without SIMD, on any machine.
constexpr int kWeightBits = 14, kFraction = 5, kShift = kWeightBits - kFraction;

struct Weights {
  std::int16_t w00, w01, w10, w11;
};

// lround of a weight (>= 0: ax, ay are fractions in [0, 1)): x + 0.5 is exact in a double and
// truncation floors it, so this is lround's half-away-from-zero, inline (lround is a libm call).
inline int roundWeight(float x) noexcept { return static_cast<int>(static_cast<double>(x) + 0.5); }

Weights weightsOf(float ax, float ay) noexcept {
  const float scale = static_cast<float>(1 << kWeightBits);
  const int w00 = roundWeight((1 - ax) * (1 - ay) * scale);
  const int w01 = roundWeight(ax * (1 - ay) * scale);
  const int w10 = roundWeight((1 - ax) * ay * scale);
  const int w11 = (1 << kWeightBits) - w00 - w01 - w10;
  return {static_cast<std::int16_t>(w00), static_cast<std::int16_t>(w01), static_cast<std::int16_t>(w10),
          static_cast<std::int16_t>(w11)};
}

// rows x cols8 samples (cols8 a multiple of 8) of a u8 image whose rows start at `first` and are
// `stride` bytes apart, the sample (r, c) from pixels (r, c), (r, c + 1), (r + 1, c), (r + 1, c + 1).
// Reads columns up to cols8 and rows up to `rows`.
void sampleFixedPortable(const std::uint8_t* first, std::ptrdiff_t stride, Weights w, int cols8, int rows,
                         std::int16_t* out) noexcept {
  for (int r = 0; r < rows; ++r) {
    const std::uint8_t* a = first + r * stride;
    const std::uint8_t* b = a + stride;
    std::int16_t* o = out + r * cols8;
    for (int c = 0; c < cols8; ++c)
      o[c] = static_cast<std::int16_t>((a[c] * w.w00 + a[c + 1] * w.w01 + b[c] * w.w10 + b[c + 1] * w.w11 +
                                        (1 << (kShift - 1))) >> kShift);
  }
}

// Sums over rows x cols8 of d * gx and d * gy, d = samples - values (all rows cols8 apart).
void sumProductsPortable(const std::int16_t* samples, const std::int16_t* values, const std::int16_t* gx,
                         const std::int16_t* gy, int cols8, int rows, std::int64_t& sx, std::int64_t& sy) noexcept {
  sx = 0, sy = 0;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols8; ++c) {
      const std::ptrdiff_t i = static_cast<std::ptrdiff_t>(r) * cols8 + c;
      const int d = samples[i] - values[i];
      sx += d * gx[i];
      sy += d * gy[i];
    }
  }
}

#if defined(__SSE2__)
void sampleFixedSse2(const std::uint8_t* first, std::ptrdiff_t stride, Weights w, int cols8, int rows,
                     std::int16_t* out) noexcept {
  const __m128i top = _mm_set1_epi32(static_cast<int>(static_cast<std::uint16_t>(w.w00)) |
                                     (static_cast<int>(static_cast<std::uint16_t>(w.w01)) << 16));
  const __m128i bottom = _mm_set1_epi32(static_cast<int>(static_cast<std::uint16_t>(w.w10)) |
                                        (static_cast<int>(static_cast<std::uint16_t>(w.w11)) << 16));
  const __m128i round = _mm_set1_epi32(1 << (kShift - 1));
  const __m128i zero = _mm_setzero_si128();
  for (int r = 0; r < rows; ++r) {
    const std::uint8_t* a = first + r * stride;
    const std::uint8_t* b = a + stride;
    std::int16_t* o = out + r * cols8;
    for (int c = 0; c < cols8; c += 8) {
      // Pixel pairs (c, c + 1) as 16-bit lanes, then one multiply-add per row of the pair.
      const __m128i pa = _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(a + c)),
                                           _mm_loadl_epi64(reinterpret_cast<const __m128i*>(a + c + 1)));
      const __m128i pb = _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(b + c)),
                                           _mm_loadl_epi64(reinterpret_cast<const __m128i*>(b + c + 1)));
      const __m128i lo = _mm_add_epi32(_mm_madd_epi16(_mm_unpacklo_epi8(pa, zero), top),
                                       _mm_madd_epi16(_mm_unpacklo_epi8(pb, zero), bottom));
      const __m128i hi = _mm_add_epi32(_mm_madd_epi16(_mm_unpackhi_epi8(pa, zero), top),
                                       _mm_madd_epi16(_mm_unpackhi_epi8(pb, zero), bottom));
      const __m128i v = _mm_packs_epi32(_mm_srai_epi32(_mm_add_epi32(lo, round), kShift),
                                        _mm_srai_epi32(_mm_add_epi32(hi, round), kShift));
      _mm_storeu_si128(reinterpret_cast<__m128i*>(o + c), v);
    }
  }
}

void sumProductsSse2(const std::int16_t* samples, const std::int16_t* values, const std::int16_t* gx,
                     const std::int16_t* gy, int cols8, int rows, std::int64_t& sx, std::int64_t& sy) noexcept {
  sx = 0, sy = 0;
  for (int r = 0; r < rows; ++r) {
    // Per lane at most cols8 / 4 products of +-2^25: exact in 32 bits for rows up to 64.
    __m128i ax = _mm_setzero_si128(), ay = _mm_setzero_si128();
    const std::ptrdiff_t row = static_cast<std::ptrdiff_t>(r) * cols8;
    for (int c = 0; c < cols8; c += 8) {
      const std::ptrdiff_t i = row + c;
      const __m128i d = _mm_sub_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(samples + i)),
                                      _mm_loadu_si128(reinterpret_cast<const __m128i*>(values + i)));
      ax = _mm_add_epi32(ax, _mm_madd_epi16(d, _mm_loadu_si128(reinterpret_cast<const __m128i*>(gx + i))));
      ay = _mm_add_epi32(ay, _mm_madd_epi16(d, _mm_loadu_si128(reinterpret_cast<const __m128i*>(gy + i))));
    }
    alignas(16) std::int32_t lx[4], ly[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(lx), ax);
    _mm_store_si128(reinterpret_cast<__m128i*>(ly), ay);
    sx += std::int64_t{lx[0]} + lx[1] + lx[2] + lx[3];
    sy += std::int64_t{ly[0]} + ly[1] + ly[2] + ly[3];
  }
}

// The template's values, gradients and gradient matrix over an n x n window (trackOne), 8 lanes
// at a time: the same integers as the scalar loop. Each gradient is a pair (A, B) weighted
// (3, 10) for Scharr, (0, 16) for the central difference, by one multiply-add into 32 bits;
// lanes past n are zero (the padding's gradient must be). Reads up to 2 values past a patch
// row's padded width (the buffer has room).
void gradientsSse2(const std::int16_t* P, int patchStride, int n, int stride, bool scharr, std::int16_t* values,
                   std::int16_t* gx, std::int16_t* gy, std::int64_t& a11, std::int64_t& a12, std::int64_t& a22) noexcept {
  const __m128i weights = scharr ? _mm_set1_epi32(3 | (10 << 16)) : _mm_set1_epi32(16 << 16);
  const __m128i round = _mm_set1_epi32(16);
  const __m128i lane = _mm_setr_epi16(0, 1, 2, 3, 4, 5, 6, 7);
  const __m128i limit = _mm_set1_epi16(static_cast<std::int16_t>(n));
  auto load = [](const std::int16_t* q) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(q)); };
  auto weigh = [&](__m128i a, __m128i b) {  // (3a + 10b + 16) >> 5 (or 16b), as 16 bits
    const __m128i lo = _mm_srai_epi32(_mm_add_epi32(_mm_madd_epi16(_mm_unpacklo_epi16(a, b), weights), round), kFraction);
    const __m128i hi = _mm_srai_epi32(_mm_add_epi32(_mm_madd_epi16(_mm_unpackhi_epi16(a, b), weights), round), kFraction);
    return _mm_packs_epi32(lo, hi);
  };
  a11 = a12 = a22 = 0;
  for (int r = 0; r < n; ++r) {
    const std::int16_t* up = P + r * patchStride + 1;
    const std::int16_t* mid = up + patchStride;
    const std::int16_t* down = mid + patchStride;
    __m128i s11 = _mm_setzero_si128(), s12 = _mm_setzero_si128(), s22 = _mm_setzero_si128();
    for (int c = 0; c < stride; c += 8) {
      const __m128i ul = load(up + c - 1), uc = load(up + c), ur = load(up + c + 1);
      const __m128i ml = load(mid + c - 1), mc = load(mid + c), mr = load(mid + c + 1);
      const __m128i dl = load(down + c - 1), dc = load(down + c), dr = load(down + c + 1);
      const __m128i inside = _mm_cmplt_epi16(_mm_add_epi16(lane, _mm_set1_epi16(static_cast<std::int16_t>(c))), limit);
      const __m128i x = _mm_and_si128(
          weigh(_mm_add_epi16(_mm_sub_epi16(ur, ul), _mm_sub_epi16(dr, dl)), _mm_sub_epi16(mr, ml)), inside);
      const __m128i y = _mm_and_si128(
          weigh(_mm_add_epi16(_mm_sub_epi16(dl, ul), _mm_sub_epi16(dr, ur)), _mm_sub_epi16(dc, uc)), inside);
      const std::ptrdiff_t i = static_cast<std::ptrdiff_t>(r) * stride + c;
      _mm_storeu_si128(reinterpret_cast<__m128i*>(gx + i), x);
      _mm_storeu_si128(reinterpret_cast<__m128i*>(gy + i), y);
      _mm_storeu_si128(reinterpret_cast<__m128i*>(values + i), _mm_and_si128(mc, inside));
      s11 = _mm_add_epi32(s11, _mm_madd_epi16(x, x));
      s12 = _mm_add_epi32(s12, _mm_madd_epi16(x, y));
      s22 = _mm_add_epi32(s22, _mm_madd_epi16(y, y));
    }
    // A row's sums fit 32 bits (at most 64 * 4080^2), as in the scalar loop.
    alignas(16) std::int32_t l11[4], l12[4], l22[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(l11), s11);
    _mm_store_si128(reinterpret_cast<__m128i*>(l12), s12);
    _mm_store_si128(reinterpret_cast<__m128i*>(l22), s22);
    a11 += static_cast<std::int32_t>(l11[0] + l11[1] + l11[2] + l11[3]);
    a12 += static_cast<std::int32_t>(l12[0] + l12[1] + l12[2] + l12[3]);
    a22 += static_cast<std::int32_t>(l22[0] + l22[1] + l22[2] + l22[3]);
  }
}
#endif

#if MARIONETTE_TRACKING_AVX2
// Loads for the AVX2 loops (lambdas would not inherit their target).
[[gnu::target("avx2")]] inline __m256i widenBytes(const std::uint8_t* q) noexcept {
  return _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(q)));
}
[[gnu::target("avx2")]] inline __m256i load16(const std::int16_t* q) noexcept {
  return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(q));
}
[[gnu::target("avx2")]] inline __m256i load8Low(const std::int16_t* q) noexcept {  // the high half zero
  return _mm256_zextsi128_si256(_mm_loadu_si128(reinterpret_cast<const __m128i*>(q)));
}
// Eight 32-bit lanes as four 64-bit sums of two (exact), and four 64-bit lanes' total.
[[gnu::target("avx2")]] inline __m256i widenSum(__m256i v) noexcept {
  return _mm256_add_epi64(_mm256_cvtepi32_epi64(_mm256_castsi256_si128(v)), _mm256_cvtepi32_epi64(_mm256_extracti128_si256(v, 1)));
}
[[gnu::target("avx2")]] inline std::int64_t horizontalSum(__m256i v) noexcept {
  alignas(32) std::int64_t l[4];
  _mm256_store_si256(reinterpret_cast<__m256i*>(l), v);
  return l[0] + l[1] + l[2] + l[3];
}
// (3a + 10b + 16) >> 5 per lane (or (16b + 16) >> 5), as 16 bits: `weights` pairs (3, 10) or (0, 16).
[[gnu::target("avx2")]] inline __m256i weighGradient(__m256i a, __m256i b, __m256i weights) noexcept {
  const __m256i round = _mm256_set1_epi32(16);
  const __m256i lo =
      _mm256_srai_epi32(_mm256_add_epi32(_mm256_madd_epi16(_mm256_unpacklo_epi16(a, b), weights), round), kFraction);
  const __m256i hi =
      _mm256_srai_epi32(_mm256_add_epi32(_mm256_madd_epi16(_mm256_unpackhi_epi16(a, b), weights), round), kFraction);
  return _mm256_packs_epi32(lo, hi);
}

// The same three loops sixteen lanes at a time (and a last eight where a row's padded width is
// not a multiple of 16): the same integers, summed in the same exact widths, so the same bits.
// AVX2 keeps its 128-bit halves apart in unpack and pack, which pair up here: each half's
// products pack back in order.
[[gnu::target("avx2")]] void sampleFixedAvx2(const std::uint8_t* first, std::ptrdiff_t stride, Weights w, int cols8,
                                             int rows, std::int16_t* out) noexcept {
  const __m256i top = _mm256_set1_epi32(static_cast<int>(static_cast<std::uint16_t>(w.w00)) |
                                        (static_cast<int>(static_cast<std::uint16_t>(w.w01)) << 16));
  const __m256i bottom = _mm256_set1_epi32(static_cast<int>(static_cast<std::uint16_t>(w.w10)) |
                                           (static_cast<int>(static_cast<std::uint16_t>(w.w11)) << 16));
  const __m256i round = _mm256_set1_epi32(1 << (kShift - 1));
  const int wide = cols8 & ~15;
  for (int r = 0; r < rows; ++r) {
    const std::uint8_t* a = first + r * stride;
    const std::uint8_t* b = a + stride;
    std::int16_t* o = out + r * cols8;
    for (int c = 0; c < wide; c += 16) {
      const __m256i a0 = widenBytes(a + c), a1 = widenBytes(a + c + 1), b0 = widenBytes(b + c), b1 = widenBytes(b + c + 1);
      const __m256i lo = _mm256_add_epi32(_mm256_madd_epi16(_mm256_unpacklo_epi16(a0, a1), top),
                                          _mm256_madd_epi16(_mm256_unpacklo_epi16(b0, b1), bottom));
      const __m256i hi = _mm256_add_epi32(_mm256_madd_epi16(_mm256_unpackhi_epi16(a0, a1), top),
                                          _mm256_madd_epi16(_mm256_unpackhi_epi16(b0, b1), bottom));
      const __m256i v = _mm256_packs_epi32(_mm256_srai_epi32(_mm256_add_epi32(lo, round), kShift),
                                           _mm256_srai_epi32(_mm256_add_epi32(hi, round), kShift));
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(o + c), v);
    }
    if (wide < cols8) sampleFixedSse2(a + wide, stride, w, 8, 1, o + wide);
  }
}

[[gnu::target("avx2")]] void sumProductsAvx2(const std::int16_t* samples, const std::int16_t* values,
                                             const std::int16_t* gx, const std::int16_t* gy, int cols8, int rows,
                                             std::int64_t& sx, std::int64_t& sy) noexcept {
  const int wide = cols8 & ~15;
  __m256i sumX = _mm256_setzero_si256(), sumY = _mm256_setzero_si256();  // 64-bit lanes
  for (int r = 0; r < rows; ++r) {
    // A row in 32-bit lanes (exact: see the SSE2 loop), then widened: no lane-by-lane sum per row.
    __m256i ax = _mm256_setzero_si256(), ay = _mm256_setzero_si256();
    const std::ptrdiff_t row = static_cast<std::ptrdiff_t>(r) * cols8;
    for (int c = 0; c < wide; c += 16) {
      const std::ptrdiff_t i = row + c;
      const __m256i d = _mm256_sub_epi16(load16(samples + i), load16(values + i));
      ax = _mm256_add_epi32(ax, _mm256_madd_epi16(d, load16(gx + i)));
      ay = _mm256_add_epi32(ay, _mm256_madd_epi16(d, load16(gy + i)));
    }
    if (wide < cols8) {  // the last eight in the low half (the high half's zeros add nothing)
      const std::ptrdiff_t i = row + wide;
      const __m256i d = _mm256_sub_epi16(load8Low(samples + i), load8Low(values + i));
      ax = _mm256_add_epi32(ax, _mm256_madd_epi16(d, load8Low(gx + i)));
      ay = _mm256_add_epi32(ay, _mm256_madd_epi16(d, load8Low(gy + i)));
    }
    sumX = _mm256_add_epi64(sumX, widenSum(ax));
    sumY = _mm256_add_epi64(sumY, widenSum(ay));
  }
  sx = horizontalSum(sumX);
  sy = horizontalSum(sumY);
}

[[gnu::target("avx2")]] void gradientsAvx2(const std::int16_t* P, int patchStride, int n, int stride, bool scharr,
                                           std::int16_t* values, std::int16_t* gx, std::int16_t* gy, std::int64_t& a11,
                                           std::int64_t& a12, std::int64_t& a22) noexcept {
  const __m256i weights = scharr ? _mm256_set1_epi32(3 | (10 << 16)) : _mm256_set1_epi32(16 << 16);
  const __m256i lane = _mm256_setr_epi16(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const __m256i limit = _mm256_set1_epi16(static_cast<std::int16_t>(n));
  __m256i t11 = _mm256_setzero_si256(), t12 = _mm256_setzero_si256(), t22 = _mm256_setzero_si256();  // 64-bit lanes
  for (int r = 0; r < n; ++r) {
    const std::int16_t* up = P + r * patchStride + 1;
    const std::int16_t* mid = up + patchStride;
    const std::int16_t* down = mid + patchStride;
    __m256i s11 = _mm256_setzero_si256(), s12 = _mm256_setzero_si256(), s22 = _mm256_setzero_si256();
    // Sixteen at a time; where the padded width ends halfway, the last lanes read past the
    // row (inside the patch buffer, which has rows to spare), are masked out of the sums
    // (lane >= n) and are not stored.
    for (int c = 0; c < stride; c += 16) {
      const __m256i ul = load16(up + c - 1), uc = load16(up + c), ur = load16(up + c + 1);
      const __m256i ml = load16(mid + c - 1), mc = load16(mid + c), mr = load16(mid + c + 1);
      const __m256i dl = load16(down + c - 1), dc = load16(down + c), dr = load16(down + c + 1);
      const __m256i inside =
          _mm256_cmpgt_epi16(limit, _mm256_add_epi16(lane, _mm256_set1_epi16(static_cast<std::int16_t>(c))));
      const __m256i x = _mm256_and_si256(
          weighGradient(_mm256_add_epi16(_mm256_sub_epi16(ur, ul), _mm256_sub_epi16(dr, dl)), _mm256_sub_epi16(mr, ml), weights),
          inside);
      const __m256i y = _mm256_and_si256(
          weighGradient(_mm256_add_epi16(_mm256_sub_epi16(dl, ul), _mm256_sub_epi16(dr, ur)), _mm256_sub_epi16(dc, uc), weights),
          inside);
      const std::ptrdiff_t i = static_cast<std::ptrdiff_t>(r) * stride + c;
      if (c + 16 <= stride) {
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(gx + i), x);
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(gy + i), y);
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(values + i), _mm256_and_si256(mc, inside));
      } else {  // the last eight of the row
        _mm_storeu_si128(reinterpret_cast<__m128i*>(gx + i), _mm256_castsi256_si128(x));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(gy + i), _mm256_castsi256_si128(y));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(values + i), _mm256_castsi256_si128(_mm256_and_si256(mc, inside)));
      }
      s11 = _mm256_add_epi32(s11, _mm256_madd_epi16(x, x));
      s12 = _mm256_add_epi32(s12, _mm256_madd_epi16(x, y));
      s22 = _mm256_add_epi32(s22, _mm256_madd_epi16(y, y));
    }
    // A row's sums fit 32 bits (at most 64 * 4080^2), as in the scalar loop.
    t11 = _mm256_add_epi64(t11, widenSum(s11));
    t12 = _mm256_add_epi64(t12, widenSum(s12));
    t22 = _mm256_add_epi64(t22, widenSum(s22));
  }
  a11 = horizontalSum(t11);
  a12 = horizontalSum(t12);
  a22 = horizontalSum(t22);
}

#endif

void sampleFixed(LkKernels k, const std::uint8_t* first, std::ptrdiff_t stride, Weights w, int cols8, int rows,
                 std::int16_t* out) noexcept {
#if MARIONETTE_TRACKING_AVX2
  if (k == LkKernels::Avx2) return sampleFixedAvx2(first, stride, w, cols8, rows, out);
#endif
#if defined(__SSE2__)
  if (k != LkKernels::Portable) return sampleFixedSse2(first, stride, w, cols8, rows, out);
#endif
  static_cast<void>(k);
  sampleFixedPortable(first, stride, w, cols8, rows, out);
}

void sumProducts(LkKernels k, const std::int16_t* samples, const std::int16_t* values, const std::int16_t* gx,
                 const std::int16_t* gy, int cols8, int rows, std::int64_t& sx, std::int64_t& sy) noexcept {
#if MARIONETTE_TRACKING_AVX2
  if (k == LkKernels::Avx2) return sumProductsAvx2(samples, values, gx, gy, cols8, rows, sx, sy);
#endif
#if defined(__SSE2__)
  if (k != LkKernels::Portable) return sumProductsSse2(samples, values, gx, gy, cols8, rows, sx, sy);
#endif
  static_cast<void>(k);
  sumProductsPortable(samples, values, gx, gy, cols8, rows, sx, sy);
}

}  // namespace

// Samples of `img` over a rows x cols8 grid whose first sample is at (x + ax, y + ay): read in
// place, or near the border from a reflect-101 copy (as OpenCV's padded pyramids).
void LucasKanade::sample(const GreyLevel& img, int x, int y, float ax, float ay, int cols8, int rows,
                         std::int16_t* out, LkKernels kernels) noexcept {
  const Weights w = weightsOf(ax, ay);
  if (x >= 0 && y >= 0 && x + cols8 < img.width && y + rows < img.height) {
    sampleFixed(kernels, img.row(y) + x, img.stride, w, cols8, rows, out);
    return;
  }
  const int width = cols8 + 1;
  for (int r = 0; r <= rows; ++r) {
    const std::uint8_t* src = img.row(reflect101(y + r, img.height));
    std::uint8_t* dst = border_.data() + static_cast<std::ptrdiff_t>(r) * width;
    for (int c = 0; c < width; ++c) dst[c] = src[reflect101(x + c, img.width)];
  }
  // The SIMD loads read up to 8 bytes from the last pair's start: the buffer has room.
  sampleFixed(kernels, border_.data(), width, w, cols8, rows, out);
}

bool LucasKanade::trackOne(const GreyLevel& t, const GreyLevel& f, cv::Point2f prev, cv::Point2f& next, int n,
                           const LucasKanadeOptions& params, LkKernels kernels) noexcept {
  const float half = static_cast<float>(n - 1) * 0.5f;
  const cv::Point2f p = prev - cv::Point2f(half, half);
  const int ix = static_cast<int>(std::floor(p.x)), iy = static_cast<int>(std::floor(p.y));
  if (ix < -n || ix >= t.width || iy < -n || iy >= t.height) return false;
  // The template and its gradient over the window, from samples one pixel beyond it (bilinear
  // sampling at a fixed offset commutes with the gradient filter: the gradient of the samples is
  // the sampled gradient).
  const int m = n + 2;
  const int patchStride = static_cast<int>(padded(m));
  // Rows of the window padded to whole lanes: the padding has zero gradient, so it adds
  // exactly nothing to the sums whatever the frame's samples there.
  const int stride = static_cast<int>(padded(n));
  const auto lanes = static_cast<std::size_t>(n * stride);
  sample(t, ix - 1, iy - 1, p.x - static_cast<float>(ix), p.y - static_cast<float>(iy), patchStride, m, patch_.data(), kernels);
  const std::int16_t* P = patch_.data();
  std::int64_t a11i = 0, a12i = 0, a22i = 0;
  const bool scharr = params.gradient == LkGradient::Scharr;
  bool simdGradients = false;
#if MARIONETTE_TRACKING_AVX2
  if (kernels == LkKernels::Avx2) {
    gradientsAvx2(P, patchStride, n, stride, scharr, values_.data(), gx_.data(), gy_.data(), a11i, a12i, a22i);
    simdGradients = true;
  }
#endif
#if defined(__SSE2__)
  if (kernels == LkKernels::Sse2) {
    gradientsSse2(P, patchStride, n, stride, scharr, values_.data(), gx_.data(), gy_.data(), a11i, a12i, a22i);
    simdGradients = true;
  }
#endif
  if (!simdGradients) {
    std::fill_n(values_.begin(), lanes, std::int16_t{0});
    std::fill_n(gx_.begin(), lanes, std::int16_t{0});
    std::fill_n(gy_.begin(), lanes, std::int16_t{0});
  }
  for (int r = 0; r < n && !simdGradients; ++r) {
    const std::int16_t* up = P + r * patchStride + 1;
    const std::int16_t* mid = up + patchStride;
    const std::int16_t* down = mid + patchStride;
    std::int16_t* v = values_.data() + r * stride;
    std::int16_t* gx = gx_.data() + r * stride;
    std::int16_t* gy = gy_.data() + r * stride;
    std::int32_t s11 = 0, s12 = 0, s22 = 0;  // a row: at most 64 * 4080^2 < 2^31
    for (int c = 0; c < n; ++c) {
      int x, y;
      if (scharr) {
        x = 3 * (up[c + 1] - up[c - 1] + down[c + 1] - down[c - 1]) + 10 * (mid[c + 1] - mid[c - 1]);
        y = 3 * (down[c - 1] - up[c - 1] + down[c + 1] - up[c + 1]) + 10 * (down[c] - up[c]);
      } else {
        x = 16 * (mid[c + 1] - mid[c - 1]);
        y = 16 * (down[c] - up[c]);
      }
      // 32 times the gradient per pixel: the Scharr sum is 32 times it, the samples 32 times.
      gx[c] = static_cast<std::int16_t>((x + 16) >> kFraction);
      gy[c] = static_cast<std::int16_t>((y + 16) >> kFraction);
      v[c] = mid[c];
      s11 += gx[c] * gx[c];
      s12 += gx[c] * gy[c];
      s22 += gy[c] * gy[c];
    }
    a11i += s11, a12i += s12, a22i += s22;
  }
  // The gradient matrix per grey level (the gradients are 32 times).
  const double a11 = static_cast<double>(a11i) / 1024.0, a12 = static_cast<double>(a12i) / 1024.0,
               a22 = static_cast<double>(a22i) / 1024.0;
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
    sample(f, jx, jy, q.x - static_cast<float>(jx), q.y - static_cast<float>(jy), stride, n, samples_.data(), kernels);
    std::int64_t sx = 0, sy = 0;
    sumProducts(kernels, samples_.data(), values_.data(), gx_.data(), gy_.data(), stride, n, sx, sy);
    // Per grey level: the differences are 32 times, the gradients 32 times.
    const double b1 = static_cast<double>(sx) / 1024.0, b2 = static_cast<double>(sy) / 1024.0;
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
                       std::span<cv::Point2f> to, std::span<std::uint8_t> status, const LucasKanadeOptions& params) noexcept {
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
  LkKernels kernels = params.simd ? LkKernels::Sse2 : LkKernels::Portable;
  if (params.simd && params.wide && cpuHasAvx2()) kernels = LkKernels::Avx2;
#if !defined(__SSE2__)
  if (kernels == LkKernels::Sse2) kernels = LkKernels::Portable;
#endif
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
      ok = trackOne(templ.level(level), frame.level(level), from[i] * scale, next, level == 0 ? n : coarse, params, kernels);
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
