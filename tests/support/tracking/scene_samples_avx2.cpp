// Four scene samples at a time (scene_samples.hpp). Each step is the scalar loop's own
// operation in the same order (synthetic_sequence.cpp: hit, the footprint, fetchFiltered,
// fetch), in IEEE double or float lanes: [[gnu::target("avx2")]] brings no FMA, so every
// multiply and add rounds as the scalar code's. std::log2 and std::fmod stay scalar per lane;
// the texels are loaded as RGBA, one load each (4 bytes where a level holds whole bytes, else 16),
// and filtered per lane across the channels (faster than AVX2's gathers of single channels on
// this machine's AMD cores; the texel loads miss the cache more than anything else here).
// SyntheticSequenceRender.WideSceneSamplesGiveTheScalarLoopsBits compares whole frames.
#include "tracking/scene_samples.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iterator>
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

// Wrapped lanes: std::fmod (scalar, rare) where |v| >= size, then + size below 0.
[[gnu::target("avx2")]] inline __m256d wrapped(__m256d v, __m256d size, __m256d wrap) {
  const __m256d far = _mm256_andnot_pd(_mm256_cmp_pd(absolute(v), size, _CMP_LT_OQ), wrap);
  if (const int m = _mm256_movemask_pd(far)) {
    alignas(32) double vs[4], ss[4];
    _mm256_store_pd(vs, v);
    _mm256_store_pd(ss, size);
    // Rebuilt from registers (a vector load of the lanes' fresh stores would stall).
    auto lane = [&](int i) { return m >> i & 1 ? std::fmod(vs[i], ss[i]) : vs[i]; };
    v = _mm256_setr_pd(lane(0), lane(1), lane(2), lane(3));
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

// One RGBA texel as floats, from bytes (exact: whole numbers 0-255) or from floats.
[[gnu::target("avx2")]] inline __m128 loadTexel(std::int64_t address, bool bytes) {
  const void* p = reinterpret_cast<const void*>(static_cast<std::uintptr_t>(address));
  if (!bytes) return _mm_loadu_ps(static_cast<const float*>(p));  // (as fast when aligned)
  int packed;
  std::memcpy(&packed, p, sizeof packed);
  return _mm_cvtepi32_ps(_mm_cvtepu8_epi32(_mm_cvtsi32_si128(packed)));
}

// fetch(): bilinear at (x, y), edges wrapped or replicated per lane, for the lanes in `lanes`:
// lane i's colour in px[i] (RGBA, A unused). The coordinates four lanes wide; the filter per
// lane across the channels, each product and sum the scalar fetch's own.
// `level[i]` is lane i's pyramid level; `wrapI` has lane i set where it wraps. (The lanes'
// values are gathered from memory that is not written here: a vector load of four fresh
// scalar stores would stall on store forwarding, which showed in the profile.)
[[gnu::target("avx2")]] void fetch4(const SampleLevel* const level[4], __m128i wrapI, __m256d x, __m256d y, int lanes,
                                    __m128 px[4]) {
  const __m128i wi = _mm_setr_epi32(level[0]->cols, level[1]->cols, level[2]->cols, level[3]->cols);
  const __m128i hi = _mm_setr_epi32(level[0]->rows, level[1]->rows, level[2]->rows, level[3]->rows);
  const __m256d w = _mm256_cvtepi32_pd(wi), h = _mm256_cvtepi32_pd(hi);  // exact
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
  auto address = [&](int i) { return static_cast<long long>(reinterpret_cast<std::uintptr_t>(level[i]->data)); };
  const __m256i base = _mm256_setr_epi64x(address(0), address(1), address(2), address(3));
  const __m256i stride = _mm256_setr_epi64x(level[0]->step, level[1]->step, level[2]->step, level[3]->step);
  const __m256i row0 = _mm256_add_epi64(base, _mm256_mul_epi32(_mm256_cvtepi32_epi64(y0), stride));
  const __m256i row1 = _mm256_add_epi64(base, _mm256_mul_epi32(_mm256_cvtepi32_epi64(y1), stride));
  const __m256i texelBytes = _mm256_setr_epi64x(level[0]->texelBytes, level[1]->texelBytes, level[2]->texelBytes,
                                                 level[3]->texelBytes);
  const __m256i col0 = _mm256_mul_epi32(_mm256_cvtepi32_epi64(x0), texelBytes);
  const __m256i col1 = _mm256_mul_epi32(_mm256_cvtepi32_epi64(x1), texelBytes);
  alignas(32) std::int64_t at[4][4];
  _mm256_store_si256(reinterpret_cast<__m256i*>(at[0]), _mm256_add_epi64(row0, col0));
  _mm256_store_si256(reinterpret_cast<__m256i*>(at[1]), _mm256_add_epi64(row0, col1));
  _mm256_store_si256(reinterpret_cast<__m256i*>(at[2]), _mm256_add_epi64(row1, col0));
  _mm256_store_si256(reinterpret_cast<__m256i*>(at[3]), _mm256_add_epi64(row1, col1));
  const __m128 onef = _mm_set1_ps(1.0f);
  alignas(16) float wx[2][4], wy[2][4];  // (1 - a, a) across and down, per lane
  _mm_store_ps(wx[0], _mm_sub_ps(onef, ax));
  _mm_store_ps(wx[1], ax);
  _mm_store_ps(wy[0], _mm_sub_ps(onef, ay));
  _mm_store_ps(wy[1], ay);
  for (int i = 0; i < 4; ++i) {
    if (!(lanes >> i & 1)) continue;
    const bool bytes = level[i]->texelBytes == 4;
    auto texel = [&](int t) { return loadTexel(at[t][i], bytes); };
    const __m128 omx = _mm_set1_ps(wx[0][i]), sx = _mm_set1_ps(wx[1][i]);
    const __m128 top = _mm_add_ps(_mm_mul_ps(texel(0), omx), _mm_mul_ps(texel(1), sx));
    const __m128 bottom = _mm_add_ps(_mm_mul_ps(texel(2), omx), _mm_mul_ps(texel(3), sx));
    px[i] = _mm_add_ps(_mm_mul_ps(top, _mm_set1_ps(wy[0][i])), _mm_mul_ps(bottom, _mm_set1_ps(wy[1][i])));
  }
}

// 1 / 2^level, exact (a division per lane showed in the profile).
constexpr double kLevelScale[] = {1.0,        1.0 / 2,    1.0 / 4,    1.0 / 8,    1.0 / 16,   1.0 / 32,
                                  1.0 / 64,   1.0 / 128,  1.0 / 256,  1.0 / 512,  1.0 / 1024, 1.0 / 2048,
                                  1.0 / 4096, 1.0 / 8192, 1.0 / 16384, 1.0 / 32768};

// A group of four samples' geometry: texture coordinates and footprints in texels, and which
// lanes see what.
struct Group {
  __m256d u, v, footprint;
  int invalid, occluded, sky, onTarget;
};

// The geometry of samples xs[0..3] of row y: the rays, the planes they meet, the footprint.
[[gnu::target("avx2")]] inline void geometry(const SampleSource& s, const int* xs, int y, Group& out) {
  const __m256d inf = _mm256_set1_pd(kInf), zero = _mm256_setzero_pd(), half = _mm256_set1_pd(0.5);
  const int ny = y + 1 < s.height ? y + 1 : y - 1;
  int nxs[4];
  for (int i = 0; i < 4; ++i) nxs[i] = xs[i] + 1 < s.width ? xs[i] + 1 : xs[i] - 1;
  const Rays r = loadRays(s, xs, y);
  out.invalid = _mm256_movemask_pd(_mm256_cmp_pd(r.x, r.x, _CMP_UNORD_Q));
  out.occluded = 0;
  if (s.occW > 0) {
    const Hit o = hit(s.toOccluder, r);
    __m256d in = _mm256_and_pd(o.ok, _mm256_cmp_pd(o.x, _mm256_set1_pd(s.occX0), _CMP_GE_OQ));
    in = _mm256_and_pd(in, _mm256_cmp_pd(o.x, _mm256_set1_pd(s.occX0 + s.occW), _CMP_LT_OQ));
    in = _mm256_and_pd(in, _mm256_cmp_pd(absolute(o.y), _mm256_set1_pd(0.5 * s.targetDepth), _CMP_LT_OQ));
    out.occluded = _mm256_movemask_pd(in);
  }
  Hit g{zero, zero, zero};
  if (s.groundOk) g = hit(s.toGround, r);
  // Sky where the ray misses the plane or meets it beyond what a double holds (as the scalar loop).
  const __m256d finite = _mm256_and_pd(_mm256_cmp_pd(absolute(g.x), inf, _CMP_LT_OQ), _mm256_cmp_pd(absolute(g.y), inf, _CMP_LT_OQ));
  out.sky = ~_mm256_movemask_pd(_mm256_and_pd(g.ok, finite)) & 15;
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
  out.onTarget = _mm256_movemask_pd(onTargetMask);
  // Texture coordinates and footprints in texels, the target's and the floor's (each only
  // where a lane needs it: the divisions are most of this pass's time).
  __m256d cu = zero, cw = zero, cf = zero;
  if (out.onTarget != 0) {
    const __m256d texel = _mm256_set1_pd(s.texel);
    cu = _mm256_sub_pd(_mm256_add_pd(_mm256_div_pd(g.x, texel), _mm256_set1_pd(0.5 * s.targetCols)), half);
    cw = _mm256_sub_pd(_mm256_add_pd(_mm256_div_pd(g.y, texel), _mm256_set1_pd(0.5 * s.targetRows)), half);
    cf = _mm256_div_pd(footprint, texel);
  }
  if (out.onTarget != 15 && !s.floorEmpty) {
    const __m256d fu = _mm256_mul_pd(_mm256_div_pd(g.x, _mm256_set1_pd(s.floorPeriodX)), _mm256_set1_pd(s.floorCols));
    const __m256d fv = _mm256_mul_pd(_mm256_div_pd(g.y, _mm256_set1_pd(s.floorPeriodZ)), _mm256_set1_pd(s.floorRows));
    const __m256d ff = _mm256_div_pd(footprint, _mm256_set1_pd(s.floorTexel));
    cu = _mm256_blendv_pd(fu, cu, onTargetMask);
    cw = _mm256_blendv_pd(fv, cw, onTargetMask);
    cf = _mm256_blendv_pd(ff, cf, onTargetMask);
  }
  out.u = cu, out.v = cw, out.footprint = cf;
}

// The colours of a group whose geometry is known: flat, or filtered from two levels.
[[gnu::target("avx2")]] void shadeGroup(const SampleSource& s, const Group& g, cv::Vec3f* out) {
  alignas(32) double ft[4];
  _mm256_store_pd(ft, g.footprint);
  const int onTarget = g.onTarget;
  // Per lane (scalar, as fetchFiltered): the colour when it is flat, else the two levels.
  cv::Vec3f flat[4];
  int fetched = 0, second = 0;
  // The two levels per lane (lanes that read nothing name level 0 of the target: its size is
  // read, no texel).
  const SampleLevel* l0[4] = {s.target.levels, s.target.levels, s.target.levels, s.target.levels};
  const SampleLevel* l1[4] = {s.target.levels, s.target.levels, s.target.levels, s.target.levels};
  int a0[4] = {}, a1[4] = {};
  float weight[4], fade[4];
  for (int i = 0; i < 4; ++i) {
    const SampleTexture& t = onTarget >> i & 1 ? s.target : s.floor;
    weight[i] = 0, fade[i] = 0;
    if (g.invalid >> i & 1) flat[i] = s.invalidLens;
    else if (g.occluded >> i & 1) flat[i] = s.occluder;
    else if (g.sky >> i & 1) flat[i] = s.sky;
    else if (!(onTarget >> i & 1) && s.floorEmpty) flat[i] = s.floor.mean;
    else {
      const double lod = ft[i] > 1 ? std::log2(ft[i]) : 0.0;
      const int last = t.count - 1;
      if (lod >= last + t.fade) {
        flat[i] = t.mean;
      } else {
        const int a = std::min(static_cast<int>(lod), last), b = std::min(a + 1, last);
        l0[i] = &t.levels[a];
        l1[i] = &t.levels[b];
        a0[i] = a, a1[i] = b;
        weight[i] = static_cast<float>(std::clamp(lod - a, 0.0, 1.0));
        if (weight[i] > 0) second |= 1 << i;
        if (t.fade > 0 && lod > last) fade[i] = static_cast<float>((lod - last) / t.fade);
        fetched |= 1 << i;
      }
    }
  }
  if (!fetched) {
    for (int i = 0; i < 4; ++i) out[i] = flat[i];
    return;
  }
  // (Only fetched lanes wrap: the others' coordinates may be NaN or huge, std::fmod's slow case.)
  const int wraps = ((s.target.wrap ? onTarget : 0) | (s.floor.wrap ? ~onTarget & 15 : 0)) & fetched;
  const __m128i bit = _mm_setr_epi32(1, 2, 4, 8);
  const __m128i wrapI = _mm_cmpeq_epi32(_mm_and_si128(_mm_set1_epi32(wraps), bit), bit);
  __m128 c[4], d[4];
  const __m256d k0 = _mm256_setr_pd(kLevelScale[a0[0]], kLevelScale[a0[1]], kLevelScale[a0[2]], kLevelScale[a0[3]]);
  fetch4(l0, wrapI, _mm256_mul_pd(g.u, k0), _mm256_mul_pd(g.v, k0), fetched, c);
  if (second) {
    const __m256d k1 = _mm256_setr_pd(kLevelScale[a1[0]], kLevelScale[a1[1]], kLevelScale[a1[2]], kLevelScale[a1[3]]);
    fetch4(l1, wrapI, _mm256_mul_pd(g.u, k1), _mm256_mul_pd(g.v, k1), second, d);
  }
  for (int i = 0; i < 4; ++i) {
    if (!(fetched >> i & 1)) {
      out[i] = flat[i];
      continue;
    }
    __m128 colour = _mm_mul_ps(c[i], _mm_set1_ps(1.0f - weight[i]));
    if (second >> i & 1) colour = _mm_add_ps(colour, _mm_mul_ps(d[i], _mm_set1_ps(weight[i])));
    if (fade[i] > 0) {
      const cv::Vec3f& mu = onTarget >> i & 1 ? s.target.mean : s.floor.mean;
      colour = _mm_add_ps(_mm_mul_ps(colour, _mm_set1_ps(1.0f - fade[i])),
                          _mm_mul_ps(_mm_setr_ps(mu[0], mu[1], mu[2], 0.0f), _mm_set1_ps(fade[i])));
    }
    alignas(16) float rgba[4];
    _mm_store_ps(rgba, colour);
    out[i] = cv::Vec3f(rgba[0], rgba[1], rgba[2]);
  }
}

}  // namespace

[[gnu::target("avx2")]] int sceneSamplesAvx2(const SampleSource& s, int x, int stride, int y, int count,
                                             cv::Vec3f* out) noexcept {
  if (!sceneSamplesWideAvailable()) return 0;  // (a caller that did not ask first gets the scalar loop)
  constexpr int kLevels = static_cast<int>(std::size(kLevelScale));
  if (s.target.count > kLevels || s.floor.count > kLevels) return 0;  // (pyramids are 6-11 levels)
  // (Eight groups' geometry first, then their shading, measured no faster: the texel loads'
  // misses, not the divisions' latency, hold this loop back.)
  const int whole = count / 4 * 4;
  for (int done = 0; done < whole; done += 4) {
    int xs[4];
    for (int i = 0; i < 4; ++i) xs[i] = x + stride * (done + i);
    Group g;
    geometry(s, xs, y, g);
    shadeGroup(s, g, out + done);
  }
  return whole;
}
#else
int sceneSamplesAvx2(const SampleSource&, int, int, int, int, cv::Vec3f*) noexcept { return 0; }
#endif

}  // namespace marionette::ar::synthetic
