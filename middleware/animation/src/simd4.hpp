// 4-wide SSE2 building blocks of the pose code (pose.cpp, blending.cpp).
//
// SSE2 is part of x86-64, the baseline the library ships with (no -march). Its add,
// multiply, divide and square root are IEEE correctly rounded, and these helpers do
// the same operations in the same order as the scalar code they replace (no reciprocal
// estimates), so results are bit-identical to the scalar forms on every x86-64 CPU;
// tests/animation/simd_pose_test.cpp holds them to that. The FMA build of the loops that use
// them (simd_dispatch.hpp) fuses their multiply-adds: the one exception, by choice.
//
// Poses stay arrays of Transform (what behaviors and the public API use); four joints
// are turned into structure-of-arrays registers on load and back on store.
#pragma once
#include <cstddef>

#include "marionette/core/transform.hpp"

#if defined(__SSE2__) && !defined(MARIONETTE_NO_SIMD)
#define MARIONETTE_SIMD4 1
#include <emmintrin.h>

namespace marionette::simd4 {

// The loads below read Transform as 10 packed floats: translation, rotation (x, y, z, w), scale.
static_assert(sizeof(Transform) == 10 * sizeof(float), "Transform must be 10 packed floats");
static_assert(offsetof(Transform, translation) == 0 && offsetof(Transform, rotation) == 12 &&
                  offsetof(Transform, scale) == 28,
              "Transform layout: translation, rotation, scale");
static_assert(sizeof(glm::quat) == 16 && offsetof(glm::quat, x) == 0 && offsetof(glm::quat, w) == 12,
              "glm::quat must store x, y, z, w (GLM_FORCE_QUAT_DATA_WXYZ is not supported)");

// Four joints' transforms, one component per register, lane k = joint k.
struct Transforms4 {
  __m128 tx, ty, tz, qx, qy, qz, qw, sx, sy, sz;
};

template <int I>
inline __m128 broadcast(__m128 v) noexcept {
  return _mm_shuffle_ps(v, v, _MM_SHUFFLE(I, I, I, I));
}

// Per lane: a where mask is set, else b.
inline __m128 select(__m128 mask, __m128 a, __m128 b) noexcept {
  return _mm_or_ps(_mm_and_ps(mask, a), _mm_andnot_ps(mask, b));
}

// Four quaternion dot products in the scalar code's order (blending.cpp, nlerpShortest): w, x, y, z.
inline __m128 dot4(__m128 ax, __m128 ay, __m128 az, __m128 aw, __m128 bx, __m128 by, __m128 bz, __m128 bw) noexcept {
  return _mm_add_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(aw, bw), _mm_mul_ps(ax, bx)), _mm_mul_ps(ay, by)),
                    _mm_mul_ps(az, bz));
}

// safeNormalize (transform.hpp) of four quaternions in place: identity where the squared
// length is not in (1e-30, 1e30). Returns the squared lengths.
inline __m128 safeNormalize4(__m128& x, __m128& y, __m128& z, __m128& w) noexcept {
  const __m128 one = _mm_set1_ps(1.0f), zero = _mm_setzero_ps();
  const __m128 len2 = dot4(x, y, z, w, x, y, z, w);
  const __m128 ok = _mm_and_ps(_mm_cmpgt_ps(len2, _mm_set1_ps(1e-30f)), _mm_cmplt_ps(len2, _mm_set1_ps(1e30f)));
  const __m128 inv = _mm_div_ps(one, _mm_sqrt_ps(len2));
  x = select(ok, _mm_mul_ps(x, inv), zero), y = select(ok, _mm_mul_ps(y, inv), zero);
  z = select(ok, _mm_mul_ps(z, inv), zero), w = select(ok, _mm_mul_ps(w, inv), one);
  return len2;
}

// Four quaternions as registers (lane k = joint k).
struct Quats4 {
  __m128 x, y, z, w;
};

// slerpShortest (core/transform.cpp) of N groups of four pairs for t in [0, 1], operation
// for operation (the arc halved in the same lanes, the same series): the scalar bits.
// The groups go through each step together: the steps are a chain of long latencies
// (two square roots and divisions), which the groups then overlap.
// always_inline: each build (simd_dispatch.hpp) must compile its own copy, with its own
// instructions, rather than call one shared out-of-line copy.
template <int N>
[[gnu::always_inline]] inline void slerpShortest4(const Quats4 (&a)[N], const Quats4 (&b)[N], const __m128 (&t)[N], Quats4 (&r)[N]) noexcept {
  const __m128 one = _mm_set1_ps(1.0f), half = _mm_set1_ps(0.5f);
  Quats4 p[N], q[N];
  __m128 c[N], u[N], halve[N];
  int anyHalved = 0;
  for (int k = 0; k < N; ++k) {
    __m128 d = dot4(a[k].x, a[k].y, a[k].z, a[k].w, b[k].x, b[k].y, b[k].z, b[k].w);
    const __m128 sign = select(_mm_cmplt_ps(d, _mm_setzero_ps()), _mm_set1_ps(-1.0f), one);
    d = _mm_mul_ps(d, sign);
    p[k] = a[k];
    q[k] = {_mm_mul_ps(b[k].x, sign), _mm_mul_ps(b[k].y, sign), _mm_mul_ps(b[k].z, sign), _mm_mul_ps(b[k].w, sign)};
    c[k] = select(_mm_cmplt_ps(one, d), one, d);
    u[k] = t[k];
    halve[k] = _mm_cmplt_ps(c[k], _mm_set1_ps(slerp_series::kHalveBelow));
    anyHalved |= _mm_movemask_ps(halve[k]);
  }
  if (anyHalved != 0) {  // past 90 degrees in some lane: those take the half of the arc that holds t
    for (int k = 0; k < N; ++k) {
      const __m128 ch = _mm_sqrt_ps(_mm_mul_ps(_mm_add_ps(one, c[k]), half));
      const __m128 h = _mm_div_ps(half, ch);
      const Quats4 m{_mm_mul_ps(_mm_add_ps(a[k].x, q[k].x), h), _mm_mul_ps(_mm_add_ps(a[k].y, q[k].y), h),
                     _mm_mul_ps(_mm_add_ps(a[k].z, q[k].z), h), _mm_mul_ps(_mm_add_ps(a[k].w, q[k].w), h)};
      const __m128 low = _mm_cmplt_ps(t[k], half);
      const __m128 lowHalf = _mm_and_ps(halve[k], low), highHalf = _mm_andnot_ps(low, halve[k]);
      p[k] = {select(highHalf, m.x, p[k].x), select(highHalf, m.y, p[k].y), select(highHalf, m.z, p[k].z),
              select(highHalf, m.w, p[k].w)};
      q[k] = {select(lowHalf, m.x, q[k].x), select(lowHalf, m.y, q[k].y), select(lowHalf, m.z, q[k].z),
              select(lowHalf, m.w, q[k].w)};
      const __m128 t2 = _mm_mul_ps(t[k], _mm_set1_ps(2.0f));
      u[k] = select(halve[k], select(low, t2, _mm_sub_ps(t2, one)), t[k]);
      c[k] = select(halve[k], ch, c[k]);
    }
  }
  __m128 v[N], y[N], u2[N], v2[N], ru[N], rv[N];
  for (int k = 0; k < N; ++k) {
    v[k] = _mm_sub_ps(one, u[k]);
    y[k] = _mm_sub_ps(c[k], one), u2[k] = _mm_mul_ps(u[k], u[k]), v2[k] = _mm_mul_ps(v[k], v[k]);
    ru[k] = one, rv[k] = one;
  }
  for (int i = slerp_series::kTerms; i >= 1; --i) {
    const __m128 scale = _mm_set1_ps(slerp_series::kScale[i]), offset = _mm_set1_ps(slerp_series::kOffset[i]);
    for (int k = 0; k < N; ++k) {
      ru[k] = _mm_add_ps(one, _mm_mul_ps(_mm_mul_ps(_mm_sub_ps(_mm_mul_ps(u2[k], scale), offset), y[k]), ru[k]));
      rv[k] = _mm_add_ps(one, _mm_mul_ps(_mm_mul_ps(_mm_sub_ps(_mm_mul_ps(v2[k], scale), offset), y[k]), rv[k]));
    }
  }
  for (int k = 0; k < N; ++k) {
    const __m128 wp = _mm_mul_ps(v[k], rv[k]), wq = _mm_mul_ps(u[k], ru[k]);
    r[k] = {_mm_add_ps(_mm_mul_ps(wp, p[k].x), _mm_mul_ps(wq, q[k].x)), _mm_add_ps(_mm_mul_ps(wp, p[k].y), _mm_mul_ps(wq, q[k].y)),
            _mm_add_ps(_mm_mul_ps(wp, p[k].z), _mm_mul_ps(wq, q[k].z)), _mm_add_ps(_mm_mul_ps(wp, p[k].w), _mm_mul_ps(wq, q[k].w))};
  }
  for (int k = 0; k < N; ++k) safeNormalize4(r[k].x, r[k].y, r[k].z, r[k].w);
}

// Four consecutive transforms (t[0..3] must all exist).
inline Transforms4 load4(const Transform* t) noexcept {
  const float* p = reinterpret_cast<const float*>(t);
  __m128 a0 = _mm_loadu_ps(p), a1 = _mm_loadu_ps(p + 10), a2 = _mm_loadu_ps(p + 20), a3 = _mm_loadu_ps(p + 30);
  __m128 b0 = _mm_loadu_ps(p + 4), b1 = _mm_loadu_ps(p + 14), b2 = _mm_loadu_ps(p + 24), b3 = _mm_loadu_ps(p + 34);
  const auto low2 = [](const float* q) { return _mm_castpd_ps(_mm_load_sd(reinterpret_cast<const double*>(q))); };
  const __m128 c01 = _mm_unpacklo_ps(low2(p + 8), low2(p + 18));  // sy0 sy1 sz0 sz1
  const __m128 c23 = _mm_unpacklo_ps(low2(p + 28), low2(p + 38));
  _MM_TRANSPOSE4_PS(a0, a1, a2, a3);
  _MM_TRANSPOSE4_PS(b0, b1, b2, b3);
  return {a0, a1, a2, a3, b0, b1, b2, b3, _mm_movelh_ps(c01, c23), _mm_movehl_ps(c23, c01)};
}

// Writes four consecutive transforms (t[0..3] must all exist).
inline void store4(const Transforms4& v, Transform* t) noexcept {
  float* p = reinterpret_cast<float*>(t);
  __m128 a0 = v.tx, a1 = v.ty, a2 = v.tz, a3 = v.qx;
  __m128 b0 = v.qy, b1 = v.qz, b2 = v.qw, b3 = v.sx;
  _MM_TRANSPOSE4_PS(a0, a1, a2, a3);
  _MM_TRANSPOSE4_PS(b0, b1, b2, b3);
  _mm_storeu_ps(p, a0);
  _mm_storeu_ps(p + 4, b0);
  _mm_storeu_ps(p + 10, a1);
  _mm_storeu_ps(p + 14, b1);
  _mm_storeu_ps(p + 20, a2);
  _mm_storeu_ps(p + 24, b2);
  _mm_storeu_ps(p + 30, a3);
  _mm_storeu_ps(p + 34, b3);
  const __m128 lo = _mm_unpacklo_ps(v.sy, v.sz), hi = _mm_unpackhi_ps(v.sy, v.sz);  // sy0 sz0 sy1 sz1 | sy2 sz2 sy3 sz3
  _mm_storel_pi(reinterpret_cast<__m64*>(p + 8), lo);
  _mm_storeh_pi(reinterpret_cast<__m64*>(p + 18), lo);
  _mm_storel_pi(reinterpret_cast<__m64*>(p + 28), hi);
  _mm_storeh_pi(reinterpret_cast<__m64*>(p + 38), hi);
}

// Columns of an affine 4x4 matrix.
struct Mat4 {
  __m128 c0, c1, c2, c3;
};

inline Mat4 loadMat(const glm::mat4& m) noexcept {
  const float* p = &m[0][0];
  return {_mm_loadu_ps(p), _mm_loadu_ps(p + 4), _mm_loadu_ps(p + 8), _mm_loadu_ps(p + 12)};
}

inline void storeMat(const Mat4& m, glm::mat4& out) noexcept {
  float* p = &out[0][0];
  _mm_storeu_ps(p, m.c0);
  _mm_storeu_ps(p + 4, m.c1);
  _mm_storeu_ps(p + 8, m.c2);
  _mm_storeu_ps(p + 12, m.c3);
}

// a * b for affine matrices, as affineMultiply (pose.hpp) computes it, term by term.
inline Mat4 affineMultiply(const Mat4& a, const Mat4& b) noexcept {
  const auto column = [&](__m128 bc) {
    return _mm_add_ps(_mm_add_ps(_mm_mul_ps(a.c0, broadcast<0>(bc)), _mm_mul_ps(a.c1, broadcast<1>(bc))),
                      _mm_mul_ps(a.c2, broadcast<2>(bc)));
  };
  return {column(b.c0), column(b.c1), column(b.c2), _mm_add_ps(column(b.c3), a.c3)};
}

// The elements of four joints' local matrices (Transform::matrix, T * R * S), computed
// term by term as Transform::matrix does: out[e][k] is element e of joint k, for columns
// 0..3 and rows 0..2 in order (the last row is 0, 0, 0, 1).
inline void composeElements4(const Transforms4& v, float out[12][4]) noexcept {
  const __m128 one = _mm_set1_ps(1.0f), two = _mm_set1_ps(2.0f);
  const __m128 xx = _mm_mul_ps(v.qx, v.qx), yy = _mm_mul_ps(v.qy, v.qy), zz = _mm_mul_ps(v.qz, v.qz);
  const __m128 xy = _mm_mul_ps(v.qx, v.qy), xz = _mm_mul_ps(v.qx, v.qz), yz = _mm_mul_ps(v.qy, v.qz);
  const __m128 wx = _mm_mul_ps(v.qw, v.qx), wy = _mm_mul_ps(v.qw, v.qy), wz = _mm_mul_ps(v.qw, v.qz);
  const auto diag = [&](__m128 a, __m128 b, __m128 s) {
    return _mm_mul_ps(_mm_sub_ps(one, _mm_mul_ps(two, _mm_add_ps(a, b))), s);
  };
  const auto twice = [&](__m128 a, __m128 s) { return _mm_mul_ps(_mm_mul_ps(two, a), s); };
  _mm_store_ps(out[0], diag(yy, zz, v.sx));
  _mm_store_ps(out[1], twice(_mm_add_ps(xy, wz), v.sx));
  _mm_store_ps(out[2], twice(_mm_sub_ps(xz, wy), v.sx));
  _mm_store_ps(out[3], twice(_mm_sub_ps(xy, wz), v.sy));
  _mm_store_ps(out[4], diag(xx, zz, v.sy));
  _mm_store_ps(out[5], twice(_mm_add_ps(yz, wx), v.sy));
  _mm_store_ps(out[6], twice(_mm_add_ps(xz, wy), v.sz));
  _mm_store_ps(out[7], twice(_mm_sub_ps(yz, wx), v.sz));
  _mm_store_ps(out[8], diag(xx, yy, v.sz));
  _mm_store_ps(out[9], v.tx);
  _mm_store_ps(out[10], v.ty);
  _mm_store_ps(out[11], v.tz);
}

}  // namespace marionette::simd4
#endif
