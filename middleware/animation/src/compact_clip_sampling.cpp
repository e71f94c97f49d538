// Sampling a compact clip (compact_clip.hpp): per-frame code, no allocation.
#include <algorithm>
#include <cstring>
#include <cmath>
#include <cstddef>

#include "compact_clip_format.hpp"
#include "simd4.hpp"
#include "marionette/animation/compact_clip.hpp"

namespace marionette {

namespace {

// A lane mask of all ones as a float (memcpy: emscripten's libc++ 14 has no std::bit_cast).
inline float allBitsSet() noexcept {
  const std::uint32_t bits = 0xFFFFFFFFu;
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

using namespace compact;

// The three stored components of key k, for a track of `Bits` bits (8 or 16: within the
// track's range; 32: floats, `Width` of them).
template <int Bits>
inline void storedKey(const CompactTrack& t, const std::uint8_t* data, std::uint32_t k, float* out) noexcept {
  if constexpr (Bits == 8) {
    const std::uint8_t* p = data + k * 3;
    for (int c = 0; c < 3; ++c) out[c] = t.min[c] + static_cast<float>(p[c]) * t.scale[c];
  } else {
    const std::uint8_t* p = data + k * 6;
    for (int c = 0; c < 3; ++c) out[c] = t.min[c] + static_cast<float>(readAt<std::uint16_t>(p + 2 * c)) * t.scale[c];
  }
}

inline glm::quat assemble(const float kept[3], int dropped) noexcept {
  float q[4];  // x, y, z, w
  const int* at = kKept[dropped];
  q[at[0]] = kept[0], q[at[1]] = kept[1], q[at[2]] = kept[2];
  q[dropped] = std::sqrt(std::max(0.0f, 1.0f - kept[0] * kept[0] - kept[1] * kept[1] - kept[2] * kept[2]));
  return glm::quat(q[3], q[0], q[1], q[2]);
}

inline glm::quat smallestThreeKey(const std::uint8_t* data, std::uint32_t k) noexcept {
  const auto word = readAt<std::uint64_t>(data + k * 8);
  const float step = 2.0f * kS3Half / kS3Levels;
  const float kept[3] = {static_cast<float>((word >> 40) & 0xFFFFF) * step - kS3Half,
                         static_cast<float>((word >> 20) & 0xFFFFF) * step - kS3Half,
                         static_cast<float>(word & 0xFFFFF) * step - kS3Half};
  return assemble(kept, static_cast<int>(word >> 60));
}

template <int Bits>
inline glm::quat quatKey(const CompactTrack& t, const std::uint8_t* data, std::uint32_t k) noexcept {
  if constexpr (Bits == 64) {
    return smallestThreeKey(data, k);
  } else if constexpr (Bits == 32) {
    const std::uint8_t* q = data + k * 16;
    return glm::quat(readAt<float>(q + 12), readAt<float>(q), readAt<float>(q + 4), readAt<float>(q + 8));
  } else {
    float kept[3];
    storedKey<Bits>(t, data, k, kept);
    return assemble(kept, t.dropped);
  }
}

template <int Bits>
inline glm::vec3 vec3Key(const CompactTrack& t, const std::uint8_t* data, std::uint32_t k) noexcept {
  if constexpr (Bits == 32) {
    const std::uint8_t* v = data + k * 12;
    return {readAt<float>(v), readAt<float>(v + 4), readAt<float>(v + 8)};
  } else {
    float v[3];
    storedKey<Bits>(t, data, k, v);
    return {v[0], v[1], v[2]};
  }
}

struct KeyAt {
  std::uint32_t i = 0;
  float f = 0.0f;
  bool single = true;
};

// The key interval [key lo, key lo + 1) holding `at` among n increasing key positions
// (key(k) gives position k), for key(0) < at < key(n - 1): the hinted interval or the
// next one when they hold it (a player moves forward a little each frame), else a
// binary search. Either way the same interval; the hint is updated.
template <class Key>
inline std::uint32_t interval(std::uint32_t n, float at, Key key, std::uint32_t* hint) noexcept {
  if (hint && *hint < n - 1) {  // a hint out of range (another clip's) is ignored
    const std::uint32_t h = *hint;
    if (key(h) <= at) {
      if (at < key(h + 1)) return h;
      if (h + 2 < n && at < key(h + 2)) return *hint = h + 1;
    }
  }
  std::uint32_t lo = 0, hi = n - 1;  // key(lo) <= at < key(hi)
  while (hi - lo > 1) {
    const std::uint32_t mid = (lo + hi) / 2;
    (at >= key(mid) ? lo : hi) = mid;
  }
  if (hint) *hint = lo;
  return lo;
}

// The key interval holding `time`; NaN and times before the first key hold key 0.
inline KeyAt locate(const CompactTrack& t, const std::uint8_t* base, float time, std::uint32_t* hint) noexcept {
  if (t.keys <= 1) return {};
  if (t.times != CompactTrack::kEvenKeys && t.rate > 0.0f) {  // sparse keys: their frame numbers
    const std::uint8_t* frames = base + t.times;
    const auto frame = [frames](std::uint32_t k) { return static_cast<float>(readAt<std::uint16_t>(frames + k * 2)); };
    const float u = (time - t.start) * t.rate;
    if (!(u > frame(0))) return {};
    if (u >= frame(t.keys - 1)) return {t.keys - 1, 0.0f, true};
    const std::uint32_t lo = interval(t.keys, u, frame, hint);
    const float a = frame(lo), b = frame(lo + 1);
    return {lo, std::clamp((u - a) / (b - a), 0.0f, 1.0f), false};
  }
  if (t.times != CompactTrack::kEvenKeys) {  // keys at float times, as the float sampler's
    const std::uint8_t* times = base + t.times;
    const auto timeOf = [times](std::uint32_t k) { return readAt<float>(times + k * 4); };
    if (!(time > timeOf(0))) return {};
    if (time >= timeOf(t.keys - 1)) return {t.keys - 1, 0.0f, true};
    const std::uint32_t lo = interval(t.keys, time, timeOf, hint);
    const float a = timeOf(lo), b = timeOf(lo + 1);
    return {lo, b > a ? std::clamp((time - a) / (b - a), 0.0f, 1.0f) : 0.0f, false};
  }
  const float u = (time - t.start) * t.rate;
  if (!(u > 0.0f)) return {};
  const auto last = static_cast<float>(t.keys - 1);
  if (u >= last) return {t.keys - 1, 0.0f, true};
  const auto i = static_cast<std::uint32_t>(u);
  return {i, u - static_cast<float>(i), false};
}

template <int Bits>
inline void sampleRotation(const CompactTrack& t, const std::uint8_t* data, const KeyAt& k, glm::quat& out) noexcept {
  const glm::quat a = quatKey<Bits>(t, data, k.i);
  // A held key is unit already: floats as the float clip holds them, a rebuilt component by construction.
  out = k.single || t.step ? a : nlerpShortest(a, quatKey<Bits>(t, data, k.i + 1), k.f);
}

template <int Bits>
inline void sampleVec3(const CompactTrack& t, const std::uint8_t* data, const KeyAt& k, glm::vec3& out) noexcept {
  const glm::vec3 a = vec3Key<Bits>(t, data, k.i);
  out = k.single || t.step ? a : a + (vec3Key<Bits>(t, data, k.i + 1) - a) * k.f;
}

// Data is 4-aligned (8 for 64-bit keys): the encoder pads each track's start.
inline void sampleTrack(const CompactTrack& t, const std::uint8_t* base, float time, Transform& o,
                        std::uint32_t* hint = nullptr) noexcept {
  const std::uint8_t* data = base + t.offset;
  const KeyAt k = locate(t, base, time, hint);
  if (t.property == CompactTrack::Property::Rotation) {
    switch (t.bits) {
      case 8: return sampleRotation<8>(t, data, k, o.rotation);
      case 16: return sampleRotation<16>(t, data, k, o.rotation);
      case 32: return sampleRotation<32>(t, data, k, o.rotation);
      default: return sampleRotation<64>(t, data, k, o.rotation);
    }
  }
  glm::vec3& v = t.property == CompactTrack::Property::Translation ? o.translation : o.scale;
  switch (t.bits) {
    case 8: return sampleVec3<8>(t, data, k, v);
    case 16: return sampleVec3<16>(t, data, k, v);
    default: return sampleVec3<32>(t, data, k, v);
  }
}

}  // namespace

void sampleCompactClipTracksScalar(const CompactClip& clip, float time, std::span<Transform> out) noexcept {
  const std::uint8_t* data = clip.data.data();
  const std::size_t n = out.size();
  for (const CompactTrack& t : clip.tracks)
    if (t.joint >= 0 && static_cast<std::size_t>(t.joint) < n) sampleTrack(t, data, time, out[static_cast<std::size_t>(t.joint)]);
}

#if MARIONETTE_SIMD4
namespace {

// Four quantized tracks (8 or 16 bits each) decoded and interpolated at once, lane k =
// track k: the operations of sampleRotation / sampleVec3, in their order, four-wide.
using namespace simd4;

// One key's three stored components as the low 16-bit lanes of a register: one load of
// 8 (or 4) bytes, which the data's padding keeps in bounds (kReadPastKey); the bytes past
// the key land in lanes that are never used.
inline __m128i keyLanes(const std::uint8_t* key, int bits) noexcept {
  if (bits == 8)
    return _mm_unpacklo_epi8(_mm_cvtsi32_si128(static_cast<int>(readAt<std::uint32_t>(key))), _mm_setzero_si128());
  return _mm_loadl_epi64(reinterpret_cast<const __m128i*>(key));
}

// locate()'s even-keys branch for four tracks at once (all evenly keyed, two keys or
// more): the same operations, four-wide, so the same interval and fraction.
struct Intervals4 {
  alignas(16) std::uint32_t first[4], second[4];  // the keys interpolated (the same key when held)
  __m128 f, hold;                                  // hold: lanes whose first key is the value
};

// The four tracks' key counts and their times in frames, u = (time - start) * rate as
// locate() computes it, lane k = track k.
struct Timing4 {
  __m128i keys;
  __m128 u;
};
inline Timing4 timingOf(const CompactTrack* const (&t)[4], float time) noexcept {
  static_assert(offsetof(CompactTrack, offset) == offsetof(CompactTrack, keys) + 4 &&
                    offsetof(CompactTrack, start) == offsetof(CompactTrack, keys) + 8 &&
                    offsetof(CompactTrack, rate) == offsetof(CompactTrack, keys) + 12,
                "CompactTrack: keys, offset, start, rate");
  const auto row = [&](int k) {  // keys, offset, start, rate
    return _mm_loadu_ps(reinterpret_cast<const float*>(reinterpret_cast<const std::uint8_t*>(t[k]) + offsetof(CompactTrack, keys)));
  };
  __m128 keys = row(0), offset = row(1), start = row(2), rate = row(3);
  _MM_TRANSPOSE4_PS(keys, offset, start, rate);
  (void)offset;
  return {_mm_castps_si128(keys), _mm_mul_ps(_mm_sub_ps(_mm_set1_ps(time), start), rate)};
}

inline __m128i stepMask(const CompactTrack* const (&t)[4]) noexcept {
  return _mm_setr_epi32(-static_cast<int>(t[0]->step), -static_cast<int>(t[1]->step), -static_cast<int>(t[2]->step),
                        -static_cast<int>(t[3]->step));
}

inline void evenIntervals4(const CompactTrack* const (&t)[4], float time, Intervals4& out) noexcept {
  const Timing4 timing = timingOf(t, time);
  const __m128i lastKey = _mm_sub_epi32(timing.keys, _mm_set1_epi32(1));
  const __m128 u = timing.u;
  const __m128 started = _mm_cmpgt_ps(u, _mm_setzero_ps());  // u > 0: false for NaN, which holds key 0
  const __m128 after = _mm_cmpge_ps(u, _mm_cvtepi32_ps(lastKey));
  const __m128 inside = _mm_andnot_ps(after, started);
  const __m128i whole = _mm_cvttps_epi32(u);
  const __m128i i = _mm_or_si128(_mm_and_si128(_mm_castps_si128(inside), whole),
                                 _mm_and_si128(_mm_castps_si128(after), lastKey));  // 0 before the first key
  out.f = _mm_and_ps(inside, _mm_sub_ps(u, _mm_cvtepi32_ps(whole)));
  out.hold = _mm_or_ps(_mm_xor_ps(inside, _mm_castsi128_ps(_mm_set1_epi32(-1))), _mm_castsi128_ps(stepMask(t)));
  _mm_store_si128(reinterpret_cast<__m128i*>(out.first), i);
  _mm_store_si128(reinterpret_cast<__m128i*>(out.second), _mm_sub_epi32(i, _mm_castps_si128(inside)));  // + 1 inside
}

// locate()'s sparse branch for four tracks at once (all sparse, two keys or more) where
// the time lies strictly inside a track's hinted interval or the one after it, as a
// player moving forward finds it nearly every frame: the same interval, fraction and
// hint as interval() then. Returns the lanes it found (bit k = lane k); the others are
// left to locate(). `count` (1..4): lanes from `count` on repeat the last track, and
// their hints (another track's) are neither read nor written.
inline int sparseIntervals4(const CompactTrack* const (&t)[4], std::size_t count, const std::uint8_t* base, float time,
                            std::uint32_t* hints, Intervals4& out) noexcept {
  const Timing4 timing = timingOf(t, time);
  alignas(16) std::uint32_t hint[4];
  std::uint64_t frames[4];  // frames h .. h + 3 of each lane's hint h
  int valid = 0;
  for (std::size_t k = 0; k < 4; ++k) {
    const std::uint32_t h = hints[std::min(k, count - 1)];
    const bool ok = h < t[k]->keys - 1;  // a hint out of range (another clip's) is ignored
    hint[k] = ok ? h : 0;
    valid |= static_cast<int>(ok) << k;
    // 8 bytes from frame h < keys - 1: at most 4 bytes past the frame numbers, which
    // the track's own keys follow (two keys or more: 6 bytes or more).
    frames[k] = readAt<std::uint64_t>(base + t[k]->times + hint[k] * 2);
  }
  // Frames h, h + 1 and h + 2 of the four lanes, as floats lane by lane (a 16-bit transpose).
  const __m128i w01 = _mm_set_epi64x(static_cast<long long>(frames[1]), static_cast<long long>(frames[0]));
  const __m128i w23 = _mm_set_epi64x(static_cast<long long>(frames[3]), static_cast<long long>(frames[2]));
  const __m128i ac = _mm_unpacklo_epi16(w01, w23), bd = _mm_unpackhi_epi16(w01, w23);
  const __m128i f01 = _mm_unpacklo_epi16(ac, bd), f23 = _mm_unpackhi_epi16(ac, bd);
  const __m128i zero = _mm_setzero_si128();
  const __m128 f0 = _mm_cvtepi32_ps(_mm_unpacklo_epi16(f01, zero)), f1 = _mm_cvtepi32_ps(_mm_unpackhi_epi16(f01, zero));
  const __m128 f2 = _mm_cvtepi32_ps(_mm_unpacklo_epi16(f23, zero));
  const __m128 u = timing.u;  // NaN fails every comparison: left to locate()
  const __m128i h = _mm_load_si128(reinterpret_cast<const __m128i*>(hint));
  const __m128 here = _mm_and_ps(_mm_cmplt_ps(f0, u), _mm_cmplt_ps(u, f1));
  const __m128i nextExists = _mm_cmplt_epi32(_mm_add_epi32(h, _mm_set1_epi32(2)), timing.keys);  // h + 2 < keys
  const __m128 next = _mm_and_ps(_mm_and_ps(_mm_cmplt_ps(f1, u), _mm_cmplt_ps(u, f2)), _mm_castsi128_ps(nextExists));
  const int found = _mm_movemask_ps(_mm_or_ps(here, next)) & valid;
  const __m128i lo = _mm_sub_epi32(h, _mm_castps_si128(next));  // + 1 in the next interval
  const __m128 a = select(next, f1, f0), b = select(next, f2, f1);
  out.f = _mm_min_ps(_mm_max_ps(_mm_div_ps(_mm_sub_ps(u, a), _mm_sub_ps(b, a)), _mm_setzero_ps()), _mm_set1_ps(1.0f));
  out.hold = _mm_castsi128_ps(stepMask(t));
  _mm_store_si128(reinterpret_cast<__m128i*>(out.first), lo);
  _mm_store_si128(reinterpret_cast<__m128i*>(out.second), _mm_add_epi32(lo, _mm_set1_epi32(1)));
  for (std::size_t k = 0; k < count; ++k)
    if (found >> k & 1) hints[k] = out.first[k];
  return found;
}

// Four tracks' keys (lane k = track k) as floats per component: a transpose in registers.
inline void componentsOf(const __m128i (&key)[4], __m128 (&out)[3]) noexcept {
  const __m128i zero = _mm_setzero_si128();
  const __m128i t01 = _mm_unpacklo_epi16(key[0], key[1]), t23 = _mm_unpacklo_epi16(key[2], key[3]);
  const __m128i lo = _mm_unpacklo_epi32(t01, t23);  // component 0 of the four, then 1
  out[0] = _mm_cvtepi32_ps(_mm_unpacklo_epi16(lo, zero));
  out[1] = _mm_cvtepi32_ps(_mm_unpackhi_epi16(lo, zero));
  out[2] = _mm_cvtepi32_ps(_mm_unpacklo_epi16(_mm_unpackhi_epi32(t01, t23), zero));
}

// The four tracks' ranges, min[c] and scale[c] lane by lane, read from the tracks
// themselves (min and scale are adjacent: two loads and two transposes). Storing them
// transposed per group beside the tracks was no faster here (Stage/Sample, same run) and
// took 112 bytes a group.
struct Ranges4 {
  __m128 min[3], scale[3];
};
static_assert(offsetof(CompactTrack, scale) == offsetof(CompactTrack, min) + 3 * sizeof(float) &&
                  offsetof(CompactTrack, scale) + 3 * sizeof(float) <= sizeof(CompactTrack),
              "CompactTrack: min[3] then scale[3]");
inline Ranges4 rangesOf(const CompactTrack* const (&t)[4]) noexcept {
  const auto at = [&](int k, std::size_t floats) {  // min0 min1 min2 scale0, or min2 scale0 scale1 scale2
    return _mm_loadu_ps(reinterpret_cast<const float*>(reinterpret_cast<const std::uint8_t*>(t[k]) + offsetof(CompactTrack, min)) + floats);
  };
  __m128 a0 = at(0, 0), a1 = at(1, 0), a2 = at(2, 0), a3 = at(3, 0);
  __m128 b0 = at(0, 2), b1 = at(1, 2), b2 = at(2, 2), b3 = at(3, 2);
  _MM_TRANSPOSE4_PS(a0, a1, a2, a3);
  _MM_TRANSPOSE4_PS(b0, b1, b2, b3);
  return {{a0, a1, a2}, {b1, b2, b3}};
}

// A run's last tracks make a padded group when at least this many are left; one alone is
// cheaper by itself.
constexpr std::size_t kLeastGroup = 2;

enum class Run { Rotations, Vectors };

// `count` (1..4) tracks from `first`; the missing lanes repeat the last track, unwritten.
template <Run R>
void sample4(const CompactTrack* first, std::size_t count, const std::uint8_t* base, float time, std::span<Transform> out,
             std::uint32_t* hints) noexcept {
  const CompactTrack* t[4];
  for (std::size_t k = 0; k < 4; ++k) t[k] = first + std::min(k, count - 1);  // padding repeats the last
  const auto even = [](const CompactTrack* x) { return x->times == CompactTrack::kEvenKeys && x->keys > 1; };
  const auto sparse = [](const CompactTrack* x) { return x->times != CompactTrack::kEvenKeys && x->rate > 0.0f && x->keys > 1; };
  Intervals4 in;
  int found = 0;  // lanes whose interval is known; the rest go through locate()
  if (even(t[0]) && even(t[1]) && even(t[2]) && even(t[3])) {
    evenIntervals4(t, time, in);
    found = 0xF;
  } else if (hints && sparse(t[0]) && sparse(t[1]) && sparse(t[2]) && sparse(t[3])) {
    found = sparseIntervals4(t, count, base, time, hints, in);
  }
  __m128 at, held;
  if (found == 0xF) {
    at = in.f, held = in.hold;
  } else {
    alignas(16) float f[4], hold[4];
    if (found) _mm_store_ps(f, in.f), _mm_store_ps(hold, in.hold);
    for (std::size_t k = 0; k < 4; ++k) {
      if (found >> k & 1) continue;
      if (k >= count) {  // the last track again: its lane's result
        in.first[k] = in.first[k - 1], in.second[k] = in.second[k - 1], f[k] = f[k - 1], hold[k] = hold[k - 1];
        continue;
      }
      const KeyAt key = locate(*t[k], base, time, hints ? hints + k : nullptr);
      in.first[k] = key.i, in.second[k] = key.single ? key.i : key.i + 1;
      f[k] = key.f;
      hold[k] = key.single || t[k]->step ? allBitsSet() : 0.0f;
    }
    at = _mm_load_ps(f), held = _mm_load_ps(hold);
  }
  __m128i ka[4], kb[4];
  for (std::size_t k = 0; k < 4; ++k) {
    const std::uint8_t* data = base + t[k]->offset;
    const std::uint32_t stride = t[k]->bits == 8 ? 3 : 6;
    ka[k] = keyLanes(data + in.first[k] * stride, t[k]->bits);
    kb[k] = keyLanes(data + in.second[k] * stride, t[k]->bits);
  }
  __m128 qa[3], qb[3];
  componentsOf(ka, qa);
  componentsOf(kb, qb);
  const Ranges4 range = rangesOf(t);
  __m128 a[3], b[3];
  for (int c = 0; c < 3; ++c) {
    a[c] = _mm_add_ps(range.min[c], _mm_mul_ps(qa[c], range.scale[c]));
    b[c] = _mm_add_ps(range.min[c], _mm_mul_ps(qb[c], range.scale[c]));
  }
  const auto owner = [&](std::size_t k) -> Transform* {
    const auto j = static_cast<std::size_t>(t[k]->joint);
    return k < count && t[k]->joint >= 0 && j < out.size() ? &out[j] : nullptr;
  };
  if constexpr (R == Run::Vectors) {
    // a + (b - a) * f, as sampleVec3; then one vec3 per lane, stored as 8 + 4 bytes.
    __m128 v[4];
    for (int c = 0; c < 3; ++c) v[c] = select(held, a[c], _mm_add_ps(a[c], _mm_mul_ps(_mm_sub_ps(b[c], a[c]), at)));
    v[3] = _mm_setzero_ps();
    _MM_TRANSPOSE4_PS(v[0], v[1], v[2], v[3]);
    for (std::size_t k = 0; k < 4; ++k) {
      Transform* o = owner(k);
      if (!o) continue;
      float* p = t[k]->property == CompactTrack::Property::Translation ? &o->translation.x : &o->scale.x;
      _mm_storel_pi(reinterpret_cast<__m64*>(p), v[k]);
      _mm_store_ss(p + 2, _mm_movehl_ps(v[k], v[k]));
    }
  } else {
    const __m128 one = _mm_set1_ps(1.0f), zero = _mm_setzero_ps();
    const __m128i which = _mm_setr_epi32(t[0]->dropped, t[1]->dropped, t[2]->dropped, t[3]->dropped);
    const auto is = [&](int c) { return _mm_castsi128_ps(_mm_cmpeq_epi32(which, _mm_set1_epi32(c))); };
    const __m128 is0 = is(0), is1 = is(1), is2 = is(2), is3 = is(3);
    // One key of the four tracks, assembled as x, y, z, w (assemble() four-wide).
    const auto key = [&](const __m128 (&kept)[3], __m128& x, __m128& y, __m128& z, __m128& w) {
      // std::max(0, v) is (0 < v ? v : 0); _mm_max_ps(v, 0) is (v > 0 ? v : 0): the same, NaN included.
      const __m128 rebuilt = _mm_sqrt_ps(_mm_max_ps(
          _mm_sub_ps(_mm_sub_ps(_mm_sub_ps(one, _mm_mul_ps(kept[0], kept[0])), _mm_mul_ps(kept[1], kept[1])),
                     _mm_mul_ps(kept[2], kept[2])),
          zero));
      x = select(is0, rebuilt, kept[0]);
      y = select(is0, kept[0], select(is1, rebuilt, kept[1]));
      z = select(_mm_or_ps(is0, is1), kept[1], select(is2, rebuilt, kept[2]));
      w = select(is3, rebuilt, kept[2]);
    };
    __m128 ax, ay, az, aw, bx, by, bz, bw;
    key(a, ax, ay, az, aw);
    key(b, bx, by, bz, bw);
    // nlerpShortest(a, b, f), then safeNormalize.
    const __m128 d = dot4(ax, ay, az, aw, bx, by, bz, bw);
    const __m128 s = _mm_xor_ps(at, _mm_and_ps(_mm_cmplt_ps(d, zero), _mm_set1_ps(-0.0f)));
    const __m128 u = _mm_sub_ps(one, at);
    __m128 rw = _mm_add_ps(_mm_mul_ps(u, aw), _mm_mul_ps(s, bw)), rx = _mm_add_ps(_mm_mul_ps(u, ax), _mm_mul_ps(s, bx));
    __m128 ry = _mm_add_ps(_mm_mul_ps(u, ay), _mm_mul_ps(s, by)), rz = _mm_add_ps(_mm_mul_ps(u, az), _mm_mul_ps(s, bz));
    safeNormalize4(rx, ry, rz, rw);
    // Back to one quaternion (x, y, z, w) per register, each stored whole.
    __m128 q0 = select(held, ax, rx), q1 = select(held, ay, ry), q2 = select(held, az, rz), q3 = select(held, aw, rw);
    _MM_TRANSPOSE4_PS(q0, q1, q2, q3);
    const __m128 q[4] = {q0, q1, q2, q3};
    for (std::size_t k = 0; k < 4; ++k)
      if (Transform* o = owner(k)) _mm_storeu_ps(&o->rotation.x, q[k]);
  }
}

}  // namespace
#endif

void sampleCompactClipAnimated(const CompactClip& clip, float time, std::span<Transform> out, std::uint32_t* hints) noexcept {
  const std::uint8_t* data = clip.data.data();
  const CompactTrack* t = clip.tracks.data();
  const std::size_t n = out.size();
  const std::size_t animated = clip.tracks.size() - clip.constants;
  std::size_t i = 0;
  const auto hint = [&](std::size_t k) { return hints ? hints + k : nullptr; };
  const auto one = [&](std::size_t end) {
    for (; i < end; ++i)
      if (t[i].joint >= 0 && static_cast<std::size_t>(t[i].joint) < n)
        sampleTrack(t[i], data, time, out[static_cast<std::size_t>(t[i].joint)], hint(i));
  };
#if MARIONETTE_SIMD4
  const std::size_t endRotations = clip.rotations, endVectors = endRotations + clip.vectors;
  // Groups of four; a run's last two or three tracks make a padded group, its last one is sampled alone.
  for (; i + kLeastGroup <= endRotations; i += 4)
    sample4<Run::Rotations>(t + i, std::min<std::size_t>(4, endRotations - i), data, time, out, hint(i));
  i = std::min(i, endRotations);
  one(endRotations);
  for (; i + kLeastGroup <= endVectors; i += 4)
    sample4<Run::Vectors>(t + i, std::min<std::size_t>(4, endVectors - i), data, time, out, hint(i));
  i = std::min(i, endVectors);
#endif
  one(animated);
}

void applyCompactClipConstants(const CompactClip& clip, std::span<Transform> pose) noexcept {
  const std::uint8_t* data = clip.data.data();
  const std::size_t n = pose.size();
  for (std::size_t i = clip.tracks.size() - clip.constants; i < clip.tracks.size(); ++i) {  // one key, floats, copied as they are
    const CompactTrack& c = clip.tracks[i];
    const auto j = static_cast<std::size_t>(c.joint);
    if (c.joint < 0 || j >= n) continue;
    const std::uint8_t* v = data + c.offset;
    if (c.property == CompactTrack::Property::Rotation)
      pose[j].rotation = glm::quat(readAt<float>(v + 12), readAt<float>(v), readAt<float>(v + 4), readAt<float>(v + 8));
    else
      (c.property == CompactTrack::Property::Translation ? pose[j].translation : pose[j].scale) =
          glm::vec3(readAt<float>(v), readAt<float>(v + 4), readAt<float>(v + 8));
  }
}

void sampleCompactClipTracks(const CompactClip& clip, float time, std::span<Transform> out, std::uint32_t* hints) noexcept {
  sampleCompactClipAnimated(clip, time, out, hints);
  applyCompactClipConstants(clip, out);
}

void sampleCompactClip(const CompactClip& clip, float time, std::span<const Transform> rest, std::span<Transform> out,
                       std::uint32_t* hints) noexcept {
  const std::size_t n = std::min(rest.size(), out.size());
  std::copy_n(rest.begin(), n, out.begin());
  sampleCompactClipTracks(clip, time, out.first(n), hints);
}

}  // namespace marionette
