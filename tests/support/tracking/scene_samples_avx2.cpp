// Four scene samples at a time (scene_samples.hpp). Each step is the scalar loop's own
// operation in the same order (synthetic_sequence.cpp: hit, the footprint, fetchFiltered,
// fetch), in IEEE double or float lanes: [[gnu::target("avx2")]] brings no FMA, so every
// multiply and add rounds as the scalar code's. std::log2 and std::fmod stay scalar per lane,
// and so do the texel loads (faster than AVX2's gathers on this machine's AMD cores).
// SyntheticSequenceRender.WideSceneSamplesGiveTheScalarLoopsBits compares whole frames.
#include "tracking/scene_samples.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "cpu_avx2.hpp"  // the tracker's one AVX2 check (examples/ar/tracking/src)

namespace marionette::ar::synthetic {

bool sceneSamplesWideAvailable() noexcept { return cpuHasAvx2(); }

#if MARIONETTE_TRACKING_AVX2
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Rays {
  __m256d x, y;
};

[[gnu::target("avx2")]] inline Rays loadRays(const SampleSource& s, const int* xs, int y) {
  if (s.rays) {
    const double* row = s.rays + 2 * static_cast<std::ptrdiff_t>(y) * s.width;
    return {_mm256_setr_pd(row[2 * xs[0]], row[2 * xs[1]], row[2 * xs[2]], row[2 * xs[3]]),
            _mm256_setr_pd(row[2 * xs[0] + 1], row[2 * xs[1] + 1], row[2 * xs[2] + 1], row[2 * xs[3] + 1])};
  }
  return {_mm256_setr_pd(s.columnRays[xs[0]], s.columnRays[xs[1]], s.columnRays[xs[2]], s.columnRays[xs[3]]),
          _mm256_set1_pd(s.rowRays[y])};
}

// sceneSample's hit(): h * (x, y, 1) as glm evaluates it (m[0][r] x + m[1][r] y + m[2][r] * 1),
// in front (z > 0) of a ray that exists, divided through.
struct Hit {
  __m256d ok, x, y;
};
[[gnu::target("avx2")]] inline __m256d row(const double* h, int i, const Rays& r) {
  return _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(_mm256_set1_pd(h[i]), r.x), _mm256_mul_pd(_mm256_set1_pd(h[3 + i]), r.y)),
                       _mm256_set1_pd(h[6 + i]));
}
[[gnu::target("avx2")]] inline Hit hit(const double* h, const Rays& r) {
  const __m256d qx = row(h, 0, r), qy = row(h, 1, r), qz = row(h, 2, r);
  const __m256d ok = _mm256_and_pd(_mm256_cmp_pd(r.x, r.x, _CMP_ORD_Q), _mm256_cmp_pd(qz, _mm256_setzero_pd(), _CMP_GT_OQ));
  return {ok, _mm256_div_pd(qx, qz), _mm256_div_pd(qy, qz)};
}

[[gnu::target("avx2")]] inline __m256d absolute(__m256d v) { return _mm256_andnot_pd(_mm256_set1_pd(-0.0), v); }

// glm::length(pn - p) where the neighbour's ray hits the plane, else infinity.
[[gnu::target("avx2")]] inline __m256d step(const Hit& n, const Hit& p) {
  const __m256d dx = _mm256_sub_pd(n.x, p.x), dy = _mm256_sub_pd(n.y, p.y);
  const __m256d length = _mm256_sqrt_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)));
  return _mm256_blendv_pd(_mm256_set1_pd(kInf), length, n.ok);
}

// Per lane, the pyramid level one bilinear fetch reads.
struct LaneLevels {
  alignas(32) std::int64_t base[4];  // the level's first byte
  alignas(32) std::int64_t step[4];
  alignas(16) int cols[4], rows[4], wrap[4];
};

// Wrapped lanes: std::fmod (scalar, rare) where |v| >= size, then + size below 0.
[[gnu::target("avx2")]] inline __m256d wrapped(__m256d v, __m256d size, __m256d wrap) {
  const __m256d far = _mm256_andnot_pd(_mm256_cmp_pd(absolute(v), size, _CMP_LT_OQ), wrap);
  if (const int m = _mm256_movemask_pd(far)) {
    alignas(32) double vs[4], ss[4];
    _mm256_store_pd(vs, v);
    _mm256_store_pd(ss, size);
    for (int i = 0; i < 4; ++i)
      if (m >> i & 1) vs[i] = std::fmod(vs[i], ss[i]);
    v = _mm256_load_pd(vs);
  }
  return _mm256_blendv_pd(v, _mm256_add_pd(v, size), _mm256_cmp_pd(v, _mm256_setzero_pd(), _CMP_LT_OQ));
}

// Clamped lanes: std::clamp(v, 0, size - 1).
[[gnu::target("avx2")]] inline __m256d clamped(__m256d v, __m256d size) {
  const __m256d lo = _mm256_setzero_pd(), hi = _mm256_sub_pd(size, _mm256_set1_pd(1.0));
  const __m256d t = _mm256_blendv_pd(v, hi, _mm256_cmp_pd(hi, v, _CMP_LT_OQ));
  return _mm256_blendv_pd(t, lo, _mm256_cmp_pd(v, lo, _CMP_LT_OQ));
}

// A wrapped index at most one period back (v >= size); `last` is size - 1.
[[gnu::target("avx2")]] inline __m128i back(__m128i v, __m128i size, __m128i last) {
  return _mm_sub_epi32(v, _mm_and_si128(_mm_cmpgt_epi32(v, last), size));
}

// fetch(): bilinear at (x, y), edges wrapped or replicated per lane; the channels in c[3].
[[gnu::target("avx2")]] void fetch4(const LaneLevels& l, __m256d x, __m256d y, __m128 c[3]) {
  const __m128i wi = _mm_load_si128(reinterpret_cast<const __m128i*>(l.cols));
  const __m128i hi = _mm_load_si128(reinterpret_cast<const __m128i*>(l.rows));
  const __m256d w = _mm256_cvtepi32_pd(wi), h = _mm256_cvtepi32_pd(hi);  // exact
  const __m128i wrapI = _mm_load_si128(reinterpret_cast<const __m128i*>(l.wrap));
  const __m256d wrap = _mm256_castsi256_pd(_mm256_cvtepi32_epi64(wrapI));
  x = _mm256_blendv_pd(clamped(x, w), wrapped(x, w, wrap), wrap);
  y = _mm256_blendv_pd(clamped(y, h), wrapped(y, h, wrap), wrap);
  const __m256d fx = _mm256_floor_pd(x), fy = _mm256_floor_pd(y);
  const __m128 ax = _mm256_cvtpd_ps(_mm256_sub_pd(x, fx)), ay = _mm256_cvtpd_ps(_mm256_sub_pd(y, fy));
  __m128i x0 = _mm256_cvttpd_epi32(fx), y0 = _mm256_cvttpd_epi32(fy);
  const __m128i one = _mm_set1_epi32(1);
  const __m128i wm1 = _mm_sub_epi32(wi, one), hm1 = _mm_sub_epi32(hi, one);
  __m128i x1 = _mm_add_epi32(x0, one), y1 = _mm_add_epi32(y0, one);
  // Wrapped: at most one period back (x0 >= w, x1 >= w); clamped: x1 at most w - 1.
  x0 = _mm_blendv_epi8(x0, back(x0, wi, wm1), wrapI);
  y0 = _mm_blendv_epi8(y0, back(y0, hi, hm1), wrapI);
  x1 = _mm_blendv_epi8(_mm_min_epi32(x1, wm1), back(x1, wi, wm1), wrapI);
  y1 = _mm_blendv_epi8(_mm_min_epi32(y1, hm1), back(y1, hi, hm1), wrapI);
  const __m256i base = _mm256_load_si256(reinterpret_cast<const __m256i*>(l.base));
  const __m256i stride = _mm256_load_si256(reinterpret_cast<const __m256i*>(l.step));
  const __m256i row0 = _mm256_add_epi64(base, _mm256_mul_epi32(_mm256_cvtepi32_epi64(y0), stride));
  const __m256i row1 = _mm256_add_epi64(base, _mm256_mul_epi32(_mm256_cvtepi32_epi64(y1), stride));
  const __m256i twelve = _mm256_set1_epi64x(12);
  const __m256i col0 = _mm256_mul_epi32(_mm256_cvtepi32_epi64(x0), twelve);
  const __m256i col1 = _mm256_mul_epi32(_mm256_cvtepi32_epi64(x1), twelve);
  const __m256i a00 = _mm256_add_epi64(row0, col0), a01 = _mm256_add_epi64(row0, col1);
  const __m256i a10 = _mm256_add_epi64(row1, col0), a11 = _mm256_add_epi64(row1, col1);
  const __m128 onef = _mm_set1_ps(1.0f);
  const __m128 omx = _mm_sub_ps(onef, ax), omy = _mm_sub_ps(onef, ay);
  // The taps' addresses, then plain loads (0.71 of the scalar render's time against 0.74 with
  // AVX2's gathers, on this machine's AMD cores).
  alignas(32) std::int64_t at[4][4];
  _mm256_store_si256(reinterpret_cast<__m256i*>(at[0]), a00);
  _mm256_store_si256(reinterpret_cast<__m256i*>(at[1]), a01);
  _mm256_store_si256(reinterpret_cast<__m256i*>(at[2]), a10);
  _mm256_store_si256(reinterpret_cast<__m256i*>(at[3]), a11);
  auto tap = [&at](int t, int k) {
    auto f = [&](int i) { return reinterpret_cast<const float*>(static_cast<std::uintptr_t>(at[t][i]))[k]; };
    return _mm_setr_ps(f(0), f(1), f(2), f(3));
  };
  for (int k = 0; k < 3; ++k) {
    const __m128 p00 = tap(0, k), p01 = tap(1, k), p10 = tap(2, k), p11 = tap(3, k);
    const __m128 top = _mm_add_ps(_mm_mul_ps(p00, omx), _mm_mul_ps(p01, ax));
    const __m128 bottom = _mm_add_ps(_mm_mul_ps(p10, omx), _mm_mul_ps(p11, ax));
    c[k] = _mm_add_ps(_mm_mul_ps(top, omy), _mm_mul_ps(bottom, ay));
  }
}

void setLevel(LaneLevels& l, int i, const SampleLevel& level, bool wrap) {
  l.base[i] = static_cast<std::int64_t>(reinterpret_cast<std::uintptr_t>(level.data));
  l.step[i] = level.step;
  l.cols[i] = level.cols;
  l.rows[i] = level.rows;
  l.wrap[i] = wrap ? -1 : 0;
}

}  // namespace

[[gnu::target("avx2")]] int sceneSamplesAvx2(const SampleSource& s, int x, int stride, int y, int count,
                                             cv::Vec3f* out) noexcept {
  if (!sceneSamplesWideAvailable()) return 0;  // (a caller that did not ask first gets the scalar loop)
  const __m256d inf = _mm256_set1_pd(kInf), zero = _mm256_setzero_pd(), half = _mm256_set1_pd(0.5);
  const int ny = y + 1 < s.height ? y + 1 : y - 1;
  int done = 0;
  for (; done + 4 <= count; done += 4) {
    int xs[4], nxs[4];
    for (int i = 0; i < 4; ++i) {
      xs[i] = x + stride * (done + i);
      nxs[i] = xs[i] + 1 < s.width ? xs[i] + 1 : xs[i] - 1;
    }
    const Rays r = loadRays(s, xs, y);
    const int invalid = _mm256_movemask_pd(_mm256_cmp_pd(r.x, r.x, _CMP_UNORD_Q));
    int occluded = 0;
    if (s.occW > 0) {
      const Hit o = hit(s.toOccluder, r);
      __m256d in = _mm256_and_pd(o.ok, _mm256_cmp_pd(o.x, _mm256_set1_pd(s.occX0), _CMP_GE_OQ));
      in = _mm256_and_pd(in, _mm256_cmp_pd(o.x, _mm256_set1_pd(s.occX0 + s.occW), _CMP_LT_OQ));
      in = _mm256_and_pd(in, _mm256_cmp_pd(absolute(o.y), _mm256_set1_pd(0.5 * s.targetDepth), _CMP_LT_OQ));
      occluded = _mm256_movemask_pd(in);
    }
    Hit g{zero, zero, zero};
    if (s.groundOk) g = hit(s.toGround, r);
    // Sky where the ray misses the plane or meets it beyond what a double holds (as the scalar loop).
    const __m256d finite = _mm256_and_pd(_mm256_cmp_pd(absolute(g.x), inf, _CMP_LT_OQ), _mm256_cmp_pd(absolute(g.y), inf, _CMP_LT_OQ));
    const int sky = ~_mm256_movemask_pd(_mm256_and_pd(g.ok, finite)) & 15;
    // The footprint from the steps to the next sample across and down (sceneSample's loop:
    // std::max(a, b) is max_pd(b, a) and std::min(a, b) is min_pd(b, a), NaN included).
    const __m256d s0 = step(hit(s.toGround, loadRays(s, nxs, y)), g);
    const __m256d s1 = step(hit(s.toGround, loadRays(s, xs, ny)), g);
    const __m256d major0 = _mm256_max_pd(s0, zero), minor0 = _mm256_min_pd(s0, inf);
    const __m256d skip = _mm256_cmp_pd(major0, inf, _CMP_EQ_OQ);  // the loop stops at an infinite step
    const __m256d major = _mm256_blendv_pd(_mm256_max_pd(s1, major0), major0, skip);
    const __m256d minor = _mm256_blendv_pd(_mm256_min_pd(s1, minor0), minor0, skip);
    const __m256d footprint = _mm256_max_pd(_mm256_mul_pd(half, major), minor);
    const __m256d onTargetMask =
        _mm256_and_pd(_mm256_cmp_pd(absolute(g.x), _mm256_set1_pd(0.5 * s.targetWidth), _CMP_LT_OQ),
                      _mm256_cmp_pd(absolute(g.y), _mm256_set1_pd(0.5 * s.targetDepth), _CMP_LT_OQ));
    const int onTarget = _mm256_movemask_pd(onTargetMask);
    // Texture coordinates and footprints in texels, the target's and the floor's (each only
    // where a lane needs it: the divisions are most of this loop's time).
    __m256d cu = zero, cw = zero, cf = zero;
    if (onTarget != 0) {
      const __m256d texel = _mm256_set1_pd(s.texel);
      cu = _mm256_sub_pd(_mm256_add_pd(_mm256_div_pd(g.x, texel), _mm256_set1_pd(0.5 * s.targetCols)), half);
      cw = _mm256_sub_pd(_mm256_add_pd(_mm256_div_pd(g.y, texel), _mm256_set1_pd(0.5 * s.targetRows)), half);
      cf = _mm256_div_pd(footprint, texel);
    }
    if (onTarget != 15 && !s.floorEmpty) {
      const __m256d fu = _mm256_mul_pd(_mm256_div_pd(g.x, _mm256_set1_pd(s.floorPeriodX)), _mm256_set1_pd(s.floorCols));
      const __m256d fv = _mm256_mul_pd(_mm256_div_pd(g.y, _mm256_set1_pd(s.floorPeriodZ)), _mm256_set1_pd(s.floorRows));
      const __m256d ff = _mm256_div_pd(footprint, _mm256_set1_pd(s.floorTexel));
      cu = _mm256_blendv_pd(fu, cu, onTargetMask);
      cw = _mm256_blendv_pd(fv, cw, onTargetMask);
      cf = _mm256_blendv_pd(ff, cf, onTargetMask);
    }
    alignas(32) double u[4], v[4], ft[4];
    _mm256_store_pd(u, cu);
    _mm256_store_pd(v, cw);
    _mm256_store_pd(ft, cf);
    // Per lane (scalar, as fetchFiltered): the colour when it is flat, else the two levels.
    cv::Vec3f flat[4];
    int fetched = 0;
    LaneLevels l0, l1;  // every lane set below (no zeroing: it showed in the profile)
    alignas(32) double scale0[4], scale1[4];
    alignas(16) float weight[4], fade[4];
    bool second = false;
    for (int i = 0; i < 4; ++i) {
      const SampleTexture& t = onTarget >> i & 1 ? s.target : s.floor;
      scale0[i] = scale1[i] = 0;
      weight[i] = 0, fade[i] = 0;
      if (invalid >> i & 1) flat[i] = s.invalidLens;
      else if (occluded >> i & 1) flat[i] = s.occluder;
      else if (sky >> i & 1) flat[i] = s.sky;
      else if (!(onTarget >> i & 1) && s.floorEmpty) flat[i] = s.floor.mean;
      else {
        const double lod = ft[i] > 1 ? std::log2(ft[i]) : 0.0;
        const int last = t.count - 1;
        if (lod >= last + t.fade) {
          flat[i] = t.mean;
        } else {
          const int a = std::min(static_cast<int>(lod), last), b = std::min(a + 1, last);
          setLevel(l0, i, t.levels[a], t.wrap);
          setLevel(l1, i, t.levels[b], t.wrap);
          scale0[i] = 1.0 / (1 << a);
          scale1[i] = 1.0 / (1 << b);
          weight[i] = static_cast<float>(std::clamp(lod - a, 0.0, 1.0));
          second = second || weight[i] > 0;
          if (t.fade > 0 && lod > last) fade[i] = static_cast<float>((lod - last) / t.fade);
          fetched |= 1 << i;
        }
      }
      if (!(fetched >> i & 1)) {  // lanes that read nothing read texel (0, 0) of a level that exists
        setLevel(l0, i, s.target.levels[0], false);
        setLevel(l1, i, s.target.levels[0], false);
        u[i] = v[i] = 0;
      }
    }
    if (fetched) {
      const __m256d uu = _mm256_load_pd(u), vv = _mm256_load_pd(v);
      __m128 c[3], d[3];
      const __m256d k0 = _mm256_load_pd(scale0);
      fetch4(l0, _mm256_mul_pd(uu, k0), _mm256_mul_pd(vv, k0), c);
      const __m128 a = _mm_load_ps(weight), m = _mm_load_ps(fade);
      const __m128 onef = _mm_set1_ps(1.0f), zerof = _mm_setzero_ps();
      for (auto& ch : c) ch = _mm_mul_ps(ch, _mm_sub_ps(onef, a));
      if (second) {
        const __m256d k1 = _mm256_load_pd(scale1);
        fetch4(l1, _mm256_mul_pd(uu, k1), _mm256_mul_pd(vv, k1), d);
        const __m128 more = _mm_cmpgt_ps(a, zerof);
        for (int k = 0; k < 3; ++k) c[k] = _mm_blendv_ps(c[k], _mm_add_ps(c[k], _mm_mul_ps(d[k], a)), more);
      }
      const __m128 fading = _mm_cmpgt_ps(m, zerof);
      if (_mm_movemask_ps(fading)) {
        alignas(16) float mean[3][4];
        for (int i = 0; i < 4; ++i) {
          const cv::Vec3f& mu = onTarget >> i & 1 ? s.target.mean : s.floor.mean;
          for (int k = 0; k < 3; ++k) mean[k][i] = mu[k];
        }
        for (int k = 0; k < 3; ++k)
          c[k] = _mm_blendv_ps(c[k], _mm_add_ps(_mm_mul_ps(c[k], _mm_sub_ps(onef, m)), _mm_mul_ps(_mm_load_ps(mean[k]), m)),
                               fading);
      }
      alignas(16) float channel[3][4];
      for (int k = 0; k < 3; ++k) _mm_store_ps(channel[k], c[k]);
      for (int i = 0; i < 4; ++i)
        out[done + i] = fetched >> i & 1 ? cv::Vec3f(channel[0][i], channel[1][i], channel[2][i]) : flat[i];
    } else {
      for (int i = 0; i < 4; ++i) out[done + i] = flat[i];
    }
  }
  return done;
}
#else
int sceneSamplesAvx2(const SampleSource&, int, int, int, int, cv::Vec3f*) noexcept { return 0; }
#endif

}  // namespace marionette::ar::synthetic
