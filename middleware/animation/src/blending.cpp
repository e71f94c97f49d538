#include "marionette/animation/blending.hpp"

#include <algorithm>
#include <cmath>

#include "simd4.hpp"
#include "simd_dispatch.hpp"

namespace marionette {

namespace {
float sanitizeWeight(float w) noexcept { return (w > 0.0f && std::isfinite(w)) ? w : 0.0f; }

float dot(const glm::quat& a, const glm::quat& b) noexcept {
  return a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
}

// Weight of joint j in a layer: layer weight times its mask (missing mask entries count as 0).
float jointWeight(float layerWeight, std::span<const float> mask, std::size_t j) noexcept {
  if (mask.empty()) return layerWeight;
  return j < mask.size() ? layerWeight * sanitizeWeight(mask[j]) : 0.0f;
}

// Per-joint sums shared by blendPoses and BlendAccumulator.
struct JointSum {
  glm::vec3 t{0.0f}, s{0.0f};
  glm::quat q{0.0f, 0.0f, 0.0f, 0.0f};
  float w = 0.0f;
};

// Rotations are sign-aligned to the rest rotation, so the sum does not depend on layer order.
inline void accumulate(JointSum& sum, const Transform& p, const Transform& rest, float w) noexcept {
  const float sw = dot(p.rotation, rest.rotation) < 0.0f ? -w : w;
  sum.t += p.translation * w;
  sum.s += p.scale * w;
  sum.q = glm::quat(sum.q.w + p.rotation.w * sw, sum.q.x + p.rotation.x * sw, sum.q.y + p.rotation.y * sw,
                    sum.q.z + p.rotation.z * sw);
  sum.w += w;
}

inline Transform finishSum(JointSum sum, const Transform& rest) noexcept {
  if (sum.w < 1.0f) accumulate(sum, rest, rest, 1.0f - sum.w);  // rest fills the remainder
  const float inv = 1.0f / sum.w;
  Transform o;
  o.translation = sum.t * inv;
  o.scale = sum.s * inv;
  // Opposite rotations at equal weight cancel to zero: fall back to rest.
  o.rotation = dot(sum.q, sum.q) > 1e-12f ? safeNormalize(sum.q) : rest.rotation;
  return o;
}

inline void addDelta(Transform& o, const Transform& d, float w) noexcept {
  o.rotation = safeNormalize(o.rotation * slerpShortest(glm::quat(1, 0, 0, 0), d.rotation, w));
  o.translation += d.translation * w;
  o.scale *= glm::mix(glm::vec3(1.0f), d.scale, w);
}
}  // namespace

void blendPoses(std::span<const BlendLayer> layers, std::span<const Transform> rest,
                std::span<Transform> out) noexcept {
  const std::size_t n = std::min(rest.size(), out.size());
  for (std::size_t j = 0; j < n; ++j) {
    JointSum sum;
    for (const BlendLayer& layer : layers) {
      if (layer.additive || j >= layer.pose.size()) continue;
      const float w = jointWeight(sanitizeWeight(layer.weight), layer.jointWeights, j);
      if (w > 0.0f) accumulate(sum, layer.pose[j], rest[j], w);
    }
    out[j] = finishSum(sum, rest[j]);
  }
  for (const BlendLayer& layer : layers)
    if (layer.additive) applyAdditive(layer.pose, layer.weight, layer.jointWeights, out.first(n));
}

void BlendAccumulator::reset(std::size_t joints) {
  joints_ = joints;
  stride_ = (joints + 3) / 4 * 4;
  if (sums_.size() < kStreams * stride_) sums_.resize(kStreams * stride_);
  if (restRotation_.size() < 4 * stride_) restRotation_.resize(4 * stride_);
  std::fill_n(sums_.begin(), kStreams * stride_, 0.0f);
  restOf_ = nullptr;
}

namespace {
// The streams of the sums (BlendAccumulator::kStreams), indices times the stride.
constexpr std::size_t kTX = 0, kTY = 1, kTZ = 2;           // translation
constexpr std::size_t kQX = 3, kQY = 4, kQZ = 5, kQW = 6;  // rotation
constexpr std::size_t kSX = 7, kSY = 8, kSZ = 9;           // scale
constexpr std::size_t kW = 10;                             // weight
static_assert(kW + 1 == BlendAccumulator::kStreams);
}  // namespace

void BlendAccumulator::addJoint(std::size_t j, const Transform& pose, const Transform& rest, float w) noexcept {
  float* s = sums_.data() + j;
  const std::size_t k = stride_;
  JointSum sum{{s[kTX * k], s[kTY * k], s[kTZ * k]},
               {s[kSX * k], s[kSY * k], s[kSZ * k]},
               glm::quat(s[kQW * k], s[kQX * k], s[kQY * k], s[kQZ * k]),
               s[kW * k]};
  accumulate(sum, pose, rest, w);
  s[kTX * k] = sum.t.x, s[kTY * k] = sum.t.y, s[kTZ * k] = sum.t.z;
  s[kQX * k] = sum.q.x, s[kQY * k] = sum.q.y, s[kQZ * k] = sum.q.z, s[kQW * k] = sum.q.w;
  s[kSX * k] = sum.s.x, s[kSY * k] = sum.s.y, s[kSZ * k] = sum.s.z;
  s[kW * k] = sum.w;
}

Transform BlendAccumulator::finishJoint(std::size_t j, const Transform& rest) const noexcept {
  const float* s = sums_.data() + j;
  const std::size_t k = stride_;
  return finishSum({{s[kTX * k], s[kTY * k], s[kTZ * k]},
                                  {s[kSX * k], s[kSY * k], s[kSZ * k]},
                                  glm::quat(s[kQW * k], s[kQX * k], s[kQY * k], s[kQZ * k]),
                                  s[kW * k]},
                                 rest);
}

#if MARIONETTE_SIMD4
namespace {
using namespace simd4;

// sum += value * w in the lanes where `on` is set (the others are left as they are:
// adding +0 to a sum that starts at +0 changes no bit).
inline void addTo(float* sum, __m128 value, __m128 w, __m128 on) noexcept {
  _mm_storeu_ps(sum, _mm_add_ps(_mm_loadu_ps(sum), _mm_and_ps(on, _mm_mul_ps(value, w))));
}

inline void addTo(float* sum, __m128 value, __m128 w) noexcept {
  _mm_storeu_ps(sum, _mm_add_ps(_mm_loadu_ps(sum), _mm_mul_ps(value, w)));
}

// Adds four joints' transforms with per-lane weights `w`; `r` points at the rest rotations'
// streams. With `masked`, lanes with w <= 0 add nothing; without, every w must be > 0.
// The rest streams are `rk` floats apart (stride of the accumulator, or 4 for a padded tail).
template <bool masked>
inline void add4(float* s, std::size_t k, const Transforms4& p, const float* r, __m128 w, std::size_t rk = 0) noexcept {
  const __m128 zero = _mm_setzero_ps();
  if (rk == 0) rk = k;
  // Rotations are sign-aligned to the rest rotation (accumulate() in scalar form).
  const __m128 d = dot4(p.qx, p.qy, p.qz, p.qw, _mm_loadu_ps(r), _mm_loadu_ps(r + rk), _mm_loadu_ps(r + 2 * rk),
                        _mm_loadu_ps(r + 3 * rk));
  const __m128 sw = _mm_xor_ps(w, _mm_and_ps(_mm_cmplt_ps(d, zero), _mm_set1_ps(-0.0f)));
  if constexpr (masked) {
    const __m128 on = _mm_cmpgt_ps(w, zero);
    addTo(s + kTX * k, p.tx, w, on), addTo(s + kTY * k, p.ty, w, on), addTo(s + kTZ * k, p.tz, w, on);
    addTo(s + kSX * k, p.sx, w, on), addTo(s + kSY * k, p.sy, w, on), addTo(s + kSZ * k, p.sz, w, on);
    addTo(s + kQW * k, p.qw, sw, on), addTo(s + kQX * k, p.qx, sw, on), addTo(s + kQY * k, p.qy, sw, on);
    addTo(s + kQZ * k, p.qz, sw, on);
    _mm_storeu_ps(s + kW * k, _mm_add_ps(_mm_loadu_ps(s + kW * k), _mm_and_ps(on, w)));
  } else {
    addTo(s + kTX * k, p.tx, w), addTo(s + kTY * k, p.ty, w), addTo(s + kTZ * k, p.tz, w);
    addTo(s + kSX * k, p.sx, w), addTo(s + kSY * k, p.sy, w), addTo(s + kSZ * k, p.sz, w);
    addTo(s + kQW * k, p.qw, sw), addTo(s + kQX * k, p.qx, sw), addTo(s + kQY * k, p.qy, sw);
    addTo(s + kQZ * k, p.qz, sw);
    _mm_storeu_ps(s + kW * k, _mm_add_ps(_mm_loadu_ps(s + kW * k), w));
  }
}
}  // namespace
#endif

#if MARIONETTE_SIMD4
namespace {
// What the four-wide part of addNormal works on: the sums' streams (stride apart), the
// rest rotations' streams, and joints [0, n) of the layer.
struct AddNormalArgs {
  float* sums;
  std::size_t stride;
  const float* restRotation;
  std::span<const Transform> pose, rest;
  float weight;
  std::span<const float> jointWeights;
  std::size_t n;
};

[[gnu::always_inline]] inline void addNormalBody(const AddNormalArgs& a) noexcept {
  const std::size_t groups = a.n / 4 * 4;
  const __m128 layerWeight = _mm_set1_ps(a.weight);
  std::size_t j = 0;
  for (; j < groups; j += 4) {
    if (a.jointWeights.empty()) {
      add4<false>(a.sums + j, a.stride, load4(&a.pose[j]), a.restRotation + j, layerWeight);
    } else {
      alignas(16) float m[4];
      for (std::size_t k = 0; k < 4; ++k) m[k] = jointWeight(a.weight, a.jointWeights, j + k);
      add4<true>(a.sums + j, a.stride, load4(&a.pose[j]), a.restRotation + j, _mm_load_ps(m));
    }
  }
  if (j < a.n) {  // the last joints, padded to four with weight 0 (the streams have room)
    Transform tail[4], restTail[4];
    alignas(16) float m[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    for (std::size_t k = 0; j + k < a.n; ++k) {
      tail[k] = a.pose[j + k];
      restTail[k] = a.rest[j + k];
      m[k] = jointWeight(a.weight, a.jointWeights, j + k);
    }
    const Transforms4 r = load4(restTail);
    alignas(16) float restRotation[16];
    _mm_store_ps(restRotation, r.qx), _mm_store_ps(restRotation + 4, r.qy), _mm_store_ps(restRotation + 8, r.qz);
    _mm_store_ps(restRotation + 12, r.qw);
    // add4 reads the rest streams 4 apart here, the sums stride apart: two strides.
    add4<true>(a.sums + j, a.stride, load4(tail), restRotation, _mm_load_ps(m), 4);
  }
}

MARIONETTE_SIMD_KERNEL(addNormal4, AddNormalArgs, addNormalBody)
}  // namespace
#endif

void BlendAccumulator::addNormal(std::span<const Transform> pose, float weight, std::span<const float> jointWeights,
                                 std::span<const Transform> rest) noexcept {
  const float lw = sanitizeWeight(weight);
  if (lw <= 0.0f) return;
  const std::size_t n = std::min({joints_, pose.size(), rest.size()});
  std::size_t j = 0;
#if MARIONETTE_SIMD4
  const std::size_t groups = n / 4 * 4;
  if (groups > 0 && restOf_ != rest.data()) {  // the rest rotations as streams, once per reset
    for (std::size_t g = 0; g < groups; g += 4) {
      const Transforms4 r = load4(&rest[g]);
      float* o = restRotation_.data() + g;
      _mm_storeu_ps(o, r.qx), _mm_storeu_ps(o + stride_, r.qy), _mm_storeu_ps(o + 2 * stride_, r.qz);
      _mm_storeu_ps(o + 3 * stride_, r.qw);
    }
    restOf_ = rest.data();
  }
  addNormal4({sums_.data(), stride_, restRotation_.data(), pose, rest, lw, jointWeights, n});
  j = n;
#endif
  for (; j < n; ++j) {
    const float w = jointWeight(lw, jointWeights, j);
    if (w > 0.0f) addJoint(j, pose[j], rest[j], w);
  }
}

#if MARIONETTE_SIMD4
namespace {
struct FinishArgs {
  const float* sums;
  std::size_t stride;
  std::span<const Transform> rest;
  std::span<Transform> out;
  std::size_t n;
};

[[gnu::always_inline]] inline void finishBody(const FinishArgs& a) noexcept {
  const std::size_t k = a.stride, n = a.n;
  const std::span<const Transform> rest = a.rest;
  const std::span<Transform> out = a.out;
  std::size_t j = 0;
  const __m128 one = _mm_set1_ps(1.0f);
  for (; j < n; j += 4) {
    // The last joints are finished four-wide too (the streams are padded) through a
    // padded copy of the rest pose and of the result.
    const std::size_t count = std::min<std::size_t>(4, n - j);
    Transform restTail[4], outTail[4];
    if (count < 4) std::copy_n(&rest[j], count, restTail);
    const Transform* restAt = count == 4 ? &rest[j] : restTail;
    const float* s = a.sums + j;
    __m128 w = _mm_loadu_ps(s + kW * k);
    Transforms4 o{_mm_loadu_ps(s + kTX * k), _mm_loadu_ps(s + kTY * k), _mm_loadu_ps(s + kTZ * k),
                  _mm_loadu_ps(s + kQX * k), _mm_loadu_ps(s + kQY * k), _mm_loadu_ps(s + kQZ * k),
                  _mm_loadu_ps(s + kQW * k), _mm_loadu_ps(s + kSX * k), _mm_loadu_ps(s + kSY * k),
                  _mm_loadu_ps(s + kSZ * k)};
    // The rest pose fills the remainder below weight 1 (its rotation aligned with itself).
    const __m128 fill = _mm_cmplt_ps(w, one);
    const bool anyFill = _mm_movemask_ps(fill) != 0;
    if (anyFill) {
      const Transforms4 r = load4(restAt);
      const __m128 rw = _mm_sub_ps(one, w);
      const auto add = [&](__m128& sum, __m128 restValue) {
        sum = _mm_add_ps(sum, _mm_and_ps(fill, _mm_mul_ps(restValue, rw)));
      };
      add(o.tx, r.tx), add(o.ty, r.ty), add(o.tz, r.tz), add(o.sx, r.sx), add(o.sy, r.sy), add(o.sz, r.sz);
      add(o.qw, r.qw), add(o.qx, r.qx), add(o.qy, r.qy), add(o.qz, r.qz);
      w = _mm_add_ps(w, _mm_and_ps(fill, rw));
    }
    const __m128 inv = _mm_div_ps(one, w);
    o.tx = _mm_mul_ps(o.tx, inv), o.ty = _mm_mul_ps(o.ty, inv), o.tz = _mm_mul_ps(o.tz, inv);
    o.sx = _mm_mul_ps(o.sx, inv), o.sy = _mm_mul_ps(o.sy, inv), o.sz = _mm_mul_ps(o.sz, inv);
    // finishJoint's rotation: rest where opposite rotations cancelled, else safeNormalize.
    const __m128 nonzero = _mm_cmpgt_ps(safeNormalize4(o.qx, o.qy, o.qz, o.qw), _mm_set1_ps(1e-12f));
    if (_mm_movemask_ps(nonzero) != 0xF) {  // opposite rotations cancelled: the rest rotation there
      const Transforms4 r = load4(restAt);
      o.qx = select(nonzero, o.qx, r.qx), o.qy = select(nonzero, o.qy, r.qy);
      o.qz = select(nonzero, o.qz, r.qz), o.qw = select(nonzero, o.qw, r.qw);
    }
    if (count == 4) {
      store4(o, &out[j]);
    } else {
      store4(o, outTail);
      std::copy_n(outTail, count, &out[j]);
    }
  }
}

MARIONETTE_SIMD_KERNEL(finish4, FinishArgs, finishBody)
}  // namespace
#endif

void BlendAccumulator::finish(std::span<const Transform> rest, std::span<Transform> out) const noexcept {
  const std::size_t n = std::min({joints_, rest.size(), out.size()});
  std::size_t j = 0;
#if MARIONETTE_SIMD4
  finish4({sums_.data(), stride_, rest, out, n});
  j = n;
#endif
  for (; j < n; ++j) out[j] = finishJoint(j, rest[j]);
}

void applyAdditive(std::span<const Transform> delta, float weight, std::span<const float> jointWeights,
                   std::span<Transform> pose) noexcept {
  const float lw = sanitizeWeight(weight);
  if (lw <= 0.0f) return;
  const std::size_t n = std::min(delta.size(), pose.size());
  for (std::size_t j = 0; j < n; ++j) {
    const float w = jointWeight(lw, jointWeights, j);
    if (w > 0.0f) addDelta(pose[j], delta[j], w);
  }
}

void makeAdditiveDelta(std::span<const Transform> pose, std::span<const Transform> reference,
                       std::span<Transform> outDelta) noexcept {
  const std::size_t n = std::min({pose.size(), reference.size(), outDelta.size()});
  for (std::size_t j = 0; j < n; ++j) {
    const Transform& p = pose[j];
    const Transform& r = reference[j];
    Transform& d = outDelta[j];
    d.rotation = safeNormalize(glm::inverse(r.rotation) * p.rotation);
    d.translation = p.translation - r.translation;
    d.scale = glm::vec3(r.scale.x != 0.0f ? p.scale.x / r.scale.x : 1.0f, r.scale.y != 0.0f ? p.scale.y / r.scale.y : 1.0f,
                        r.scale.z != 0.0f ? p.scale.z / r.scale.z : 1.0f);
  }
}

namespace {
struct BlendOverArgs {
  std::span<Transform> pose;
  std::span<const Transform> layer;
  float weight;
  std::span<const float> jointWeights;
  std::size_t n;
};
}  // namespace

#if MARIONETTE_SIMD4
namespace {
constexpr int kOverGroups = 2;  // two groups of four joints at a time, whose slerps overlap
constexpr std::size_t kOverJoints = 4 * kOverGroups;

// blendOver of pose[0..count) (count <= kOverJoints; pose and layer hold kOverJoints),
// operation for operation as slerpShortest and glm::mix (x (1 - w) + y w) compute it:
// the same bits as one joint at a time. Joints at weight 0 keep their transform; at
// weight 1 they take the layer's as it is.
[[gnu::always_inline]] inline void blendOverJoints(Transform* pose, const Transform* layer, float lw, std::span<const float> jointWeights,
                     std::size_t first, std::size_t count) noexcept {
  const auto weightOf = [&](std::size_t k) {
    return k < count ? std::min(jointWeight(lw, jointWeights, first + k), 1.0f) : 0.0f;
  };
  __m128 wv[kOverGroups], active[kOverGroups];
  int anyActive = 0;
  for (int g = 0; g < kOverGroups; ++g) {
    const std::size_t k0 = 4 * static_cast<std::size_t>(g);
    wv[g] = jointWeights.empty() && count == kOverJoints
                ? _mm_set1_ps(lw)
                : _mm_setr_ps(weightOf(k0), weightOf(k0 + 1), weightOf(k0 + 2), weightOf(k0 + 3));
    active[g] = _mm_cmpgt_ps(wv[g], _mm_setzero_ps());
    anyActive |= _mm_movemask_ps(active[g]);
  }
  if (anyActive == 0) return;
  simd4::Transforms4 p[kOverGroups], l[kOverGroups];
  simd4::Quats4 from[kOverGroups], to[kOverGroups], q[kOverGroups];
  for (int g = 0; g < kOverGroups; ++g) {
    p[g] = simd4::load4(pose + 4 * g);
    l[g] = simd4::load4(layer + 4 * g);
    from[g] = {p[g].qx, p[g].qy, p[g].qz, p[g].qw};
    to[g] = {l[g].qx, l[g].qy, l[g].qz, l[g].qw};
  }
  simd4::slerpShortest4(from, to, wv, q);
  for (int g = 0; g < kOverGroups; ++g) {
    const __m128 w = wv[g], keep = _mm_sub_ps(_mm_set1_ps(1.0f), w), on = active[g];
    const __m128 full = _mm_cmpge_ps(w, _mm_set1_ps(1.0f));  // the layer as it is
    const auto mix = [&](__m128 a, __m128 b) {
      return simd4::select(full, b, simd4::select(on, _mm_add_ps(_mm_mul_ps(a, keep), _mm_mul_ps(b, w)), a));
    };
    const auto turn = [&](__m128 slerped, __m128 a, __m128 b) { return simd4::select(full, b, simd4::select(on, slerped, a)); };
    const simd4::Transforms4 &pg = p[g], &lg = l[g];
    const simd4::Transforms4 o{mix(pg.tx, lg.tx),
                               mix(pg.ty, lg.ty),
                               mix(pg.tz, lg.tz),
                               turn(q[g].x, pg.qx, lg.qx),
                               turn(q[g].y, pg.qy, lg.qy),
                               turn(q[g].z, pg.qz, lg.qz),
                               turn(q[g].w, pg.qw, lg.qw),
                               mix(pg.sx, lg.sx),
                               mix(pg.sy, lg.sy),
                               mix(pg.sz, lg.sz)};
    simd4::store4(o, pose + 4 * g);
  }
}


[[gnu::always_inline]] inline void blendOverBody(const BlendOverArgs& a) noexcept {
  const std::size_t n = a.n;
  std::size_t j = 0;
  for (; j + kOverJoints <= n; j += kOverJoints) blendOverJoints(&a.pose[j], &a.layer[j], a.weight, a.jointWeights, j, kOverJoints);
  if (j == n) return;
  // The last joints, padded to a whole group (the padding has weight 0).
  Transform p[kOverJoints], l[kOverJoints];
  const std::size_t rest = n - j;
  std::copy_n(&a.pose[j], rest, p);
  std::copy_n(&a.layer[j], rest, l);
  blendOverJoints(p, l, a.weight, a.jointWeights, j, rest);
  std::copy_n(p, rest, &a.pose[j]);
}

MARIONETTE_SIMD_KERNEL(blendOver8, BlendOverArgs, blendOverBody)
}  // namespace
#else
namespace {
// Without SSE2 (MARIONETTE_NO_SIMD, or a CPU without it): one joint at a time, the
// operations the 4-wide code does lane by lane.
void blendOver8(const BlendOverArgs& a) noexcept {
  for (std::size_t j = 0; j < a.n; ++j) {
    const float w = std::min(jointWeight(a.weight, a.jointWeights, j), 1.0f);
    if (!(w > 0.0f)) continue;
    Transform& p = a.pose[j];
    const Transform& l = a.layer[j];
    if (w >= 1.0f) {
      p = l;
      continue;
    }
    const float keep = 1.0f - w;
    p.translation = p.translation * keep + l.translation * w;
    p.rotation = slerpShortest(p.rotation, l.rotation, w);
    p.scale = p.scale * keep + l.scale * w;
  }
}
}  // namespace
#endif

void blendOver(std::span<Transform> pose, std::span<const Transform> layer, float weight,
               std::span<const float> jointWeights) noexcept {
  const float lw = std::min(sanitizeWeight(weight), 1.0f);
  if (lw <= 0.0f) return;
  const std::size_t n = std::min(pose.size(), layer.size());
  if (lw >= 1.0f && jointWeights.empty()) {  // the layer replaces the pose
    if (pose.data() != layer.data()) std::copy_n(layer.begin(), n, pose.begin());
    return;
  }
  blendOver8({pose, layer, lw, jointWeights, n});
}

}  // namespace marionette
