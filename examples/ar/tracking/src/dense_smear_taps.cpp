#include "dense_smear_taps.hpp"

#include <algorithm>

#include "cpu_avx2.hpp"

namespace marionette::ar {

namespace {

// Bilinear sample of a grey level and its gradient (the bilinear patch's, from the same four
// pixels); the caller keeps (u, v) within [0, w - 2] x [0, h - 2].
inline float bilinear(const GreyLevel& g, float u, float v, float& du, float& dv) noexcept {
  const int x0 = static_cast<int>(u), y0 = static_cast<int>(v);
  const float fx = u - static_cast<float>(x0), fy = v - static_cast<float>(y0);
  const std::uint8_t* r0 = g.row(y0) + x0;
  const std::uint8_t* r1 = r0 + g.stride;
  const float a = r0[0], b = r0[1], c = r1[0], d = r1[1];
  du = (1 - fy) * (b - a) + fy * (d - c);
  dv = (1 - fx) * (c - a) + fx * (d - b);
  return (1 - fy) * ((1 - fx) * a + fx * b) + fy * ((1 - fx) * c + fx * d);
}

void walkScalar(const GreyLevel& t, float umax, float vmax, SmearTaps& g) noexcept {
  for (int i = 0; i < g.count; ++i) {
    float sum = 0, gu = 0, gv = 0, mu = 0, mv = 0;
    bool inside = true;
    double hx = g.hx[i], hy = g.hy[i], hw = g.hw[i];
    for (int k = 0; k < g.taps[i]; ++k, hx += g.dhx[i], hy += g.dhy[i], hw += g.dhw[i]) {
      if (!(hw > 1e-12)) {
        inside = false;
        break;
      }
      const double iw = 1.0 / hw;
      const auto u = static_cast<float>(hx * iw), v = static_cast<float>(hy * iw);
      if (!(u >= 1.0f && v >= 1.0f && u <= umax && v <= vmax)) {
        inside = false;
        break;
      }
      float du = 0, dv = 0;
      sum += bilinear(t, u, v, du, dv);
      const auto c = static_cast<float>((k + 0.5) * g.step[i] - 0.5);
      gu += du, gv += dv;
      mu += c * du, mv += c * dv;
    }
    g.sum[i] = sum, g.gu[i] = gu, g.gv[i] = gv, g.mu[i] = mu, g.mv[i] = mv;
    g.inside[i] = inside;
  }
}

#if MARIONETTE_TRACKING_AVX2
// Eight doubles as two vectors of four.
struct Doubles {
  __m256d lo, hi;
};

[[gnu::target("avx2")]] inline Doubles loadDoubles(const double* p) noexcept { return {_mm256_loadu_pd(p), _mm256_loadu_pd(p + 4)}; }

[[gnu::target("avx2")]] inline __m256 toFloats(__m256d lo, __m256d hi) noexcept {
  return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm256_cvtpd_ps(lo)), _mm256_cvtpd_ps(hi), 1);
}

// A lane mask of eight floats from two of four doubles.
[[gnu::target("avx2")]] inline __m256 maskOf(__m256d lo, __m256d hi) noexcept {
  const __m256i l = _mm256_castpd_si256(lo), h = _mm256_castpd_si256(hi);
  // The low 32 bits of each 64-bit lane, in order.
  const __m256i order = _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6);
  const __m128i a = _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(l, order));
  const __m128i b = _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(h, order));
  return _mm256_castsi256_ps(_mm256_insertf128_si256(_mm256_castsi128_si256(a), b, 1));
}

// The scalar loop's operations lane by lane: doubles for the line (two vectors), floats for the
// samples, each lane stopping (its mask cleared) where the scalar loop breaks or ends; the gathers
// read only the lanes still walking. AVX2 without FMA: every multiply and add rounds as the
// scalar one does.
[[gnu::target("avx2")]] void walkAvx2(const GreyLevel& t, float umax, float vmax, SmearTaps& g) noexcept {
  int most = 0;
  for (int i = 0; i < g.count; ++i) most = g.taps[i] > most ? g.taps[i] : most;
  Doubles hx = loadDoubles(g.hx), hy = loadDoubles(g.hy), hw = loadDoubles(g.hw);
  const Doubles dhx = loadDoubles(g.dhx), dhy = loadDoubles(g.dhy), dhw = loadDoubles(g.dhw), step = loadDoubles(g.step);
  const __m256i taps = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(g.taps));
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  __m256 walking = _mm256_castsi256_ps(_mm256_cmpgt_epi32(_mm256_set1_epi32(g.count), lane));  // the lanes in use
  __m256 failed = _mm256_setzero_ps();
  __m256 sum = _mm256_setzero_ps(), gu = sum, gv = sum, mu = sum, mv = sum;
  const __m256d tiny = _mm256_set1_pd(1e-12), one = _mm256_set1_pd(1.0), halfD = _mm256_set1_pd(0.5);
  const __m256 oneF = _mm256_set1_ps(1.0f), umaxF = _mm256_set1_ps(umax), vmaxF = _mm256_set1_ps(vmax);
  const __m256i stride = _mm256_set1_epi32(static_cast<int>(t.stride)), low = _mm256_set1_epi32(0xff);
  const auto* base = reinterpret_cast<const int*>(t.data);
  const auto* below = reinterpret_cast<const int*>(t.data + t.stride);
  for (int k = 0; k < most; ++k) {
    // Lanes with taps left.
    walking = _mm256_and_ps(walking, _mm256_castsi256_ps(_mm256_cmpgt_epi32(taps, _mm256_set1_epi32(k))));
    const __m256 front = maskOf(_mm256_cmp_pd(hw.lo, tiny, _CMP_GT_OQ), _mm256_cmp_pd(hw.hi, tiny, _CMP_GT_OQ));
    const __m256d iwLo = _mm256_div_pd(one, hw.lo), iwHi = _mm256_div_pd(one, hw.hi);
    const __m256 u = toFloats(_mm256_mul_pd(hx.lo, iwLo), _mm256_mul_pd(hx.hi, iwHi));
    const __m256 v = toFloats(_mm256_mul_pd(hy.lo, iwLo), _mm256_mul_pd(hy.hi, iwHi));
    const __m256 within = _mm256_and_ps(_mm256_and_ps(_mm256_cmp_ps(u, oneF, _CMP_GE_OQ), _mm256_cmp_ps(v, oneF, _CMP_GE_OQ)),
                                        _mm256_and_ps(_mm256_cmp_ps(u, umaxF, _CMP_LE_OQ), _mm256_cmp_ps(v, vmaxF, _CMP_LE_OQ)));
    const __m256 ok = _mm256_and_ps(front, within);
    // A walking lane that fails stops here, outside.
    failed = _mm256_or_ps(failed, _mm256_andnot_ps(ok, walking));
    walking = _mm256_and_ps(walking, ok);
    if (_mm256_testz_ps(walking, walking)) break;  // lanes only ever stop
    // Where a lane is not walking its position may be anything: its index is 0 and unread.
    const __m256i x0 = _mm256_cvttps_epi32(_mm256_and_ps(u, walking)), y0 = _mm256_cvttps_epi32(_mm256_and_ps(v, walking));
    const __m256 fx = _mm256_sub_ps(u, _mm256_cvtepi32_ps(x0)), fy = _mm256_sub_ps(v, _mm256_cvtepi32_ps(y0));
    const __m256i offset = _mm256_add_epi32(_mm256_mullo_epi32(y0, stride), x0);
    const __m256i walkingI = _mm256_castps_si256(walking);
    const __m256i top = _mm256_mask_i32gather_epi32(_mm256_setzero_si256(), base, offset, walkingI, 1);
    const __m256i bottom = _mm256_mask_i32gather_epi32(_mm256_setzero_si256(), below, offset, walkingI, 1);
    const __m256 a = _mm256_cvtepi32_ps(_mm256_and_si256(top, low)), b = _mm256_cvtepi32_ps(_mm256_and_si256(_mm256_srli_epi32(top, 8), low));
    const __m256 c = _mm256_cvtepi32_ps(_mm256_and_si256(bottom, low)), d = _mm256_cvtepi32_ps(_mm256_and_si256(_mm256_srli_epi32(bottom, 8), low));
    const __m256 rx = _mm256_sub_ps(oneF, fx), ry = _mm256_sub_ps(oneF, fy);
    const __m256 du = _mm256_add_ps(_mm256_mul_ps(ry, _mm256_sub_ps(b, a)), _mm256_mul_ps(fy, _mm256_sub_ps(d, c)));
    const __m256 dv = _mm256_add_ps(_mm256_mul_ps(rx, _mm256_sub_ps(c, a)), _mm256_mul_ps(fx, _mm256_sub_ps(d, b)));
    const __m256 value = _mm256_add_ps(_mm256_mul_ps(ry, _mm256_add_ps(_mm256_mul_ps(rx, a), _mm256_mul_ps(fx, b))),
                                       _mm256_mul_ps(fy, _mm256_add_ps(_mm256_mul_ps(rx, c), _mm256_mul_ps(fx, d))));
    const __m256d kHalf = _mm256_set1_pd(k + 0.5);
    const __m256 offsetAlong = toFloats(_mm256_sub_pd(_mm256_mul_pd(kHalf, step.lo), halfD), _mm256_sub_pd(_mm256_mul_pd(kHalf, step.hi), halfD));
    // Only the walking lanes add (adding 0 elsewhere would turn a -0 sum into +0).
    sum = _mm256_blendv_ps(sum, _mm256_add_ps(sum, value), walking);
    gu = _mm256_blendv_ps(gu, _mm256_add_ps(gu, du), walking);
    gv = _mm256_blendv_ps(gv, _mm256_add_ps(gv, dv), walking);
    mu = _mm256_blendv_ps(mu, _mm256_add_ps(mu, _mm256_mul_ps(offsetAlong, du)), walking);
    mv = _mm256_blendv_ps(mv, _mm256_add_ps(mv, _mm256_mul_ps(offsetAlong, dv)), walking);
    hx = {_mm256_add_pd(hx.lo, dhx.lo), _mm256_add_pd(hx.hi, dhx.hi)};
    hy = {_mm256_add_pd(hy.lo, dhy.lo), _mm256_add_pd(hy.hi, dhy.hi)};
    hw = {_mm256_add_pd(hw.lo, dhw.lo), _mm256_add_pd(hw.hi, dhw.hi)};
  }
  _mm256_storeu_ps(g.sum, sum);
  _mm256_storeu_ps(g.gu, gu);
  _mm256_storeu_ps(g.gv, gv);
  _mm256_storeu_ps(g.mu, mu);
  _mm256_storeu_ps(g.mv, mv);
  const int failedLanes = _mm256_movemask_ps(failed);
  for (int i = 0; i < SmearTaps::kLanes; ++i) g.inside[i] = ((failedLanes >> i) & 1) == 0;
}

#endif

}  // namespace

void walkSmearTaps(const GreyLevel& keyframe, float umax, float vmax, SmearTaps& taps, bool wide) noexcept {
  // The gathers read 4 bytes from a tap's first pixel, on its row and the next: held to the
  // bounds the caller's contract gives (a looser caller would read past the image).
  umax = std::min(umax, static_cast<float>(keyframe.width - 3));
  vmax = std::min(vmax, static_cast<float>(keyframe.height - 3));
#if MARIONETTE_TRACKING_AVX2
  if (wide && cpuHasAvx2()) return walkAvx2(keyframe, umax, vmax, taps);
#endif
  static_cast<void>(wide);
  walkScalar(keyframe, umax, vmax, taps);
}

}  // namespace marionette::ar
