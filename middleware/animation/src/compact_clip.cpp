#include "marionette/animation/compact_clip.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <deque>
#include <type_traits>

#include "marionette/animation/clip_error.hpp"
#include "marionette/animation/pose.hpp"
#include "marionette/animation/sampling.hpp"
#include "compact_clip_format.hpp"

namespace marionette {

namespace {

using namespace compact;

// A float track to compact: its keys as rows of `width` floats (3, or 4 for x, y, z, w).
struct Source {
  int joint = -1;
  CompactTrack::Property property = CompactTrack::Property::Translation;
  int width = 3;
  const float* values = nullptr;
  std::uint32_t keys = 0;
  bool step = false;
  float start = 0.0f, rate = 0.0f;
  const float* times = nullptr;  // keys off any grid: their times (else even, from start and rate)
  const std::uint16_t* frames = nullptr;  // sparse keys on the grid of start and rate: their frame numbers
  // Rotations: the component to drop (never small over the track) and its smallest size.
  int dropped = 3;
  float droppedMin = 0.0f;
  float lo[3] = {0, 0, 0}, range[3] = {0, 0, 0};  // smallest value and extent of each stored component
};

// Keys on a frame grid with frames left out (as FBX exports hold them): the number of
// frames of that grid (resampling on it is exact), or 0 when the keys are off any grid
// (curves an exporter subdivided) or the grid would be much longer than the keys.
std::size_t frameGrid(const std::vector<float>& times) {
  float dt = INFINITY;
  for (std::size_t k = 1; k < times.size(); ++k) dt = std::min(dt, times[k] - times[k - 1]);
  if (!(dt > 0.0f) || !std::isfinite(dt)) return 0;
  for (float t : times) {
    const float m = (t - times.front()) / dt;
    if (std::fabs(m - std::round(m)) > 1e-3f) return 0;
  }
  const float frames = std::round((times.back() - times.front()) / dt) + 1.0f;
  return frames <= 4.0f * static_cast<float>(times.size()) ? static_cast<std::size_t>(frames) : 0;
}

// A track on a frame grid keeps its keys sparse (with 16-bit frame numbers) when it has
// at most one key in this many frames: 2 bytes a key for the numbers against 3 or 6 for
// each frame filled in, and a short search to sample it (compact_clip_sampling.cpp).
constexpr std::size_t kSparseKeysPerFrame = 3;

// The track's value at `t`, as the float sampler gives it for linear and step keys.
template <class T>
T valueAt(const Track<T>& track, float t) {
  const std::vector<float>& times = track.times;
  std::size_t i = 0;
  while (i + 2 < times.size() && t >= times[i + 1]) ++i;
  if (times.size() < 2 || !(t > times[0])) return track.values[0];
  if (t >= times.back()) return track.values.back();
  if (track.interpolation == Interpolation::Step) return track.values[i];
  const float u = std::clamp((t - times[i]) / (times[i + 1] - times[i]), 0.0f, 1.0f);
  if constexpr (std::is_same_v<T, glm::quat>)
    return nlerpShortest(track.values[i], track.values[i + 1], u);
  else
    return track.values[i] + (track.values[i + 1] - track.values[i]) * u;
}

// Keys evenly spaced (to a thousandth of their spacing): start and rate, else false.
bool evenKeys(const std::vector<float>& times, float& start, float& rate) {
  start = times.front();
  rate = 0.0f;
  if (times.size() < 2) return true;
  const float dt = (times.back() - times.front()) / static_cast<float>(times.size() - 1);
  if (!(dt > 0.0f)) return false;
  for (std::size_t k = 0; k < times.size(); ++k)
    if (std::fabs(times[k] - (start + static_cast<float>(k) * dt)) > 1e-3f * dt) return false;
  rate = 1.0f / dt;
  return true;
}

// The stored components of key k of a source (rotations: sign-aligned, dropped component removed).
void stored(const Source& s, std::uint32_t k, float out[4], bool full) {
  const float* v = s.values + static_cast<std::size_t>(k) * s.width;
  if (s.property != CompactTrack::Property::Rotation || full) {
    for (int c = 0; c < s.width; ++c) out[c] = v[c];
    return;
  }
  const float sign = v[s.dropped] < 0.0f ? -1.0f : 1.0f;
  int o = 0;
  for (int c = 0; c < 4; ++c)
    if (c != s.dropped) out[o++] = v[c] * sign;
}

void analyze(Source& s) {
  if (s.property == CompactTrack::Property::Rotation) {
    float best = -1.0f;
    for (int c = 0; c < 4; ++c) {
      float smallest = INFINITY;
      for (std::uint32_t k = 0; k < s.keys; ++k) smallest = std::min(smallest, std::fabs(s.values[k * 4 + c]));
      if (smallest > best) best = smallest, s.dropped = c;
    }
    s.droppedMin = best;
  }
  float lo[4], hi[4], v[4];
  std::fill_n(lo, 4, INFINITY);
  std::fill_n(hi, 4, -INFINITY);
  for (std::uint32_t k = 0; k < s.keys; ++k) {
    stored(s, k, v, false);
    for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], v[c]), hi[c] = std::max(hi[c], v[c]);
  }
  for (int c = 0; c < 3; ++c) s.lo[c] = lo[c], s.range[c] = hi[c] - lo[c];
}

// A rotation dropping a component smaller than this is stored as floats: rebuilding it
// from the other three would magnify their quantization error (by about 1 / its size).
constexpr float kSmallestDropped = 0.3f;

void padTo(std::vector<std::uint8_t>& data, std::size_t alignment) {
  data.resize((data.size() + alignment - 1) / alignment * alignment, 0);
}

void append(std::vector<std::uint8_t>& data, const void* bytes, std::size_t size) {
  const auto* b = static_cast<const std::uint8_t*>(bytes);
  data.insert(data.end(), b, b + size);
}

void encode(const Source& s, int bits, CompactClip& out) {
  CompactTrack t;
  if (s.times || s.frames) {
    padTo(out.data, 4);
    t.times = static_cast<std::uint32_t>(out.data.size());
    if (s.times)
      append(out.data, s.times, s.keys * sizeof(float));
    else
      append(out.data, s.frames, s.keys * sizeof(std::uint16_t));
  }
  t.joint = s.joint;
  t.property = s.property;
  t.step = s.step;
  t.keys = s.keys;
  t.start = s.start;
  t.rate = s.rate;
  if (s.property == CompactTrack::Property::Rotation && (s.droppedMin < kSmallestDropped || bits == 32)) bits = 64;
  if (s.keys == 1) bits = 32;  // a constant: its value as it is, read without decoding
  t.bits = static_cast<std::uint8_t>(bits);
  t.dropped = static_cast<std::uint8_t>(s.dropped);
  padTo(out.data, 4);
  t.offset = static_cast<std::uint32_t>(out.data.size());
  if (bits == 64) {
    padTo(out.data, 8);
    t.offset = static_cast<std::uint32_t>(out.data.size());
    for (std::uint32_t k = 0; k < s.keys; ++k) {
      const float* q = s.values + static_cast<std::size_t>(k) * 4;
      int largest = 0;
      for (int c = 1; c < 4; ++c)
        if (std::fabs(q[c]) > std::fabs(q[largest])) largest = c;
      const float sign = q[largest] < 0.0f ? -1.0f : 1.0f;
      std::uint64_t word = static_cast<std::uint64_t>(largest) << 60;
      for (int c = 0, shift = 40; c < 4; ++c) {
        if (c == largest) continue;
        const float v = std::clamp(q[c] * sign, -kS3Half, kS3Half);
        word |= static_cast<std::uint64_t>(std::round((v + kS3Half) / (2.0f * kS3Half) * kS3Levels)) << shift;
        shift -= 20;
      }
      append(out.data, &word, 8);
    }
    out.tracks.push_back(t);
    return;
  }
  const bool full = bits == 32;
  const int n = full ? s.width : 3;
  float v[4];
  if (!full) {  // the ranges analyze() found
    const float levels = static_cast<float>((1u << bits) - 1u);
    for (int c = 0; c < 3; ++c) t.min[c] = s.lo[c], t.scale[c] = s.range[c] / levels;
  }
  for (std::uint32_t k = 0; k < s.keys; ++k) {
    stored(s, k, v, full);
    for (int c = 0; c < n; ++c) {
      if (full) {
        append(out.data, &v[c], 4);
        continue;
      }
      const float levels = static_cast<float>((1u << bits) - 1u);
      const float q = t.scale[c] > 0.0f ? std::round((v[c] - t.min[c]) / t.scale[c]) : 0.0f;
      const auto code = static_cast<std::uint32_t>(std::clamp(q, 0.0f, levels));
      if (bits == 8) {
        out.data.push_back(static_cast<std::uint8_t>(code));
      } else {
        const auto c16 = static_cast<std::uint16_t>(code);
        append(out.data, &c16, 2);
      }
    }
  }
  out.tracks.push_back(t);
}

CompactClip build(const std::vector<Source>& sources, const std::vector<int>& bits, float duration) {
  CompactClip c;
  c.duration = duration;
  for (std::size_t i = 0; i < sources.size(); ++i) encode(sources[i], bits[i], c);
  // Runs of quantized rotations, then quantized translations and scales, then the other
  // animated tracks, then the constants. Within each of the first two runs, the evenly
  // keyed tracks come first (stable: by joint within each): the sampler finds the
  // intervals of a group of four evenly keyed tracks at once, and of four sparse tracks
  // at once when their hints hold; a group mixing the two takes each lane on its own.
  const auto rank = [](const CompactTrack& t) {
    if (t.keys == 1) return 6;
    if (t.bits != 8 && t.bits != 16) return 4;
    const int uneven = t.times == CompactTrack::kEvenKeys ? 0 : 1;
    return (t.property == CompactTrack::Property::Rotation ? 0 : 2) + uneven;
  };
  std::stable_sort(c.tracks.begin(), c.tracks.end(), [&](const CompactTrack& a, const CompactTrack& b) { return rank(a) < rank(b); });
  for (const CompactTrack& t : c.tracks) {
    if (rank(t) < 2) ++c.rotations;
    else if (rank(t) < 4) ++c.vectors;
    else if (rank(t) == 6) ++c.constants;
  }
  // The four-wide decoder reads a quantized key as 8 (16-bit) or 4 (8-bit) bytes: a key ends
  // at most 2 bytes before the next track, and these 4 bytes keep the last one's read in bounds.
  c.data.resize(c.data.size() + compact::kReadPastKey, 0);
  c.data.shrink_to_fit();
  return c;
}

// How far a track's quantization at `bits` can move a point `lever` away (model units):
// the bit choice's first guess and its ranking of which track to refine.
float proxyError(const Source& s, int bits, float lever, float parentScale) {
  if (bits >= 32) return 0.0f;
  if (s.property == CompactTrack::Property::Rotation && s.droppedMin < kSmallestDropped) return 0.0f;  // 64 bits anyway
  const float levels = static_cast<float>((1u << bits) - 1u);
  const float step = std::max({s.range[0], s.range[1], s.range[2]}) / levels;
  const float component = 0.5f * step * std::sqrt(3.0f);
  switch (s.property) {
    case CompactTrack::Property::Rotation:  // angle ~ twice the quaternion's error, the dropped part magnified
      return 2.0f * component * (1.0f + 1.0f / s.droppedMin) * lever;
    case CompactTrack::Property::Scale:
      return component * lever;
    default:
      return component * parentScale;
  }
}

// Key reduction of an evenly keyed, linear track: greedily, from each kept key, the
// farthest key (at most kMaxSpan frames on) whose interpolation from it recovers every
// key between within `tolerance` (component units: a rotation's 4 components, sign-
// aligned, as the sampler's nlerp gives them). The kept keys' frame numbers, or none
// when too few would go for the track to be kept sparse.
constexpr std::uint32_t kMaxSpan = 128;

std::vector<std::uint16_t> keysToKeep(const Source& s, float tolerance) {
  if (s.keys < 2 * kSparseKeysPerFrame || s.step || s.times || s.frames || s.keys > 65536 || !(tolerance > 0.0f)) return {};
  const auto w = static_cast<std::size_t>(s.width);
  const auto value = [&](std::uint32_t k, std::size_t c) { return s.values[k * w + c]; };
  const auto quat = [&](std::uint32_t k) { return glm::quat(value(k, 3), value(k, 0), value(k, 1), value(k, 2)); };
  const auto within = [&](const glm::quat& q, const glm::quat& r) {
    const float sign = glm::dot(q, r) < 0.0f ? -1.0f : 1.0f;
    const glm::quat d(q.w - sign * r.w, q.x - sign * r.x, q.y - sign * r.y, q.z - sign * r.z);
    return glm::dot(d, d) <= tolerance * tolerance;
  };
  // Every key between a and b, and for rotations every midpoint between those keys too:
  // nlerp over a longer span moves at another pace, so matching at the keys alone
  // would leave the reduced curve off between them. The track's own midpoints
  // (between keys k - 1 and k) are the same for every span: computed once.
  const bool rotation = s.property == CompactTrack::Property::Rotation;
  std::vector<glm::quat> midpoint(rotation ? s.keys : 0);
  for (std::uint32_t k = 1; k < midpoint.size(); ++k) midpoint[k] = nlerpShortest(quat(k - 1), quat(k), 0.5f);
  const auto recovered = [&](std::uint32_t a, std::uint32_t b) {
    const auto span = static_cast<float>(b - a);
    const glm::quat qa = rotation ? quat(a) : glm::quat(), qb = rotation ? quat(b) : glm::quat();
    for (std::uint32_t k = a + 1; k < b; ++k) {
      const float u = static_cast<float>(k - a) / span;
      if (rotation) {
        if (!within(nlerpShortest(qa, qb, u), quat(k))) return false;
        if (!within(nlerpShortest(qa, qb, (static_cast<float>(k - a) - 0.5f) / span), midpoint[k])) return false;
        if (k + 1 == b && !within(nlerpShortest(qa, qb, (span - 0.5f) / span), midpoint[b])) return false;
        continue;
      }
      float err2 = 0.0f;
      for (std::size_t c = 0; c < 3; ++c) {
        const float e = value(a, c) + (value(b, c) - value(a, c)) * u - value(k, c);
        err2 += e * e;
      }
      if (!(err2 <= tolerance * tolerance)) return false;
    }
    return true;
  };
  std::vector<std::uint16_t> kept{0};
  for (std::uint32_t a = 0; a + 1 < s.keys;) {
    std::uint32_t b = a + 1;
    while (b + 1 < s.keys && b + 1 - a <= kMaxSpan && recovered(a, b + 1)) ++b;
    kept.push_back(static_cast<std::uint16_t>(b));
    a = b;
  }
  if (kept.size() * kSparseKeysPerFrame > s.keys) return {};
  return kept;
}

// A track's reduction tolerance in its own units, from a distance at a virtual vertex.
float componentTolerance(const Source& s, float distance, float lever, float parentScale) {
  switch (s.property) {
    case CompactTrack::Property::Rotation:  // a quaternion's components move by about half the angle
      return 0.5f * distance / lever;
    case CompactTrack::Property::Scale:
      return distance / lever;
    default:
      return distance / parentScale;
  }
}

CompactClip compactClipOnce(const Clip& clip, const Skeleton& skeleton, const CompactClipOptions& options,
                            CompactClipStats& stats);

}  // namespace

CompactClip compactClip(const Clip& clip, const Skeleton& skeleton, const CompactClipOptions& options,
                        CompactClipStats* statsOut) {
  CompactClipStats local;
  CompactClipStats& stats = statsOut ? *statsOut : local;
  CompactClip c = compactClipOnce(clip, skeleton, options, stats);
  if (c.empty() && options.keyReductionShare > 0.0f && stats.keysDropped > 0) {
    CompactClipOptions without = options;
    without.keyReductionShare = 0.0f;
    c = compactClipOnce(clip, skeleton, without, stats);
    stats.keyReductionUndone = true;
  }
  return c;
}

namespace {

CompactClip compactClipOnce(const Clip& clip, const Skeleton& skeleton, const CompactClipOptions& options,
                            CompactClipStats& stats) {
  stats = {};
  const std::size_t joints = skeleton.jointCount();
  std::vector<Source> sources;
  std::deque<std::vector<float>> resampled;  // keys put on their frame grid (a deque: pointers stay)
  std::deque<std::vector<std::uint16_t>> frameNumbers;  // sparse tracks' keys
  float fastest = 0.0f;
  const auto add = [&](int joint, CompactTrack::Property p, const auto& track, int width) -> bool {
    if (track.empty()) return true;
    stats.floatBytes += track.times.size() * sizeof(float) + track.values.size() * sizeof(track.values[0]);
    if (track.interpolation == Interpolation::CubicSpline) return stats.reason = "a cubic-spline track", false;
    Source s;
    s.joint = joint;
    s.property = p;
    s.width = width;
    s.values = reinterpret_cast<const float*>(track.values.data());
    s.keys = static_cast<std::uint32_t>(track.times.size());
    s.step = track.interpolation == Interpolation::Step;
    for (std::size_t i = 0; i < track.values.size() * static_cast<std::size_t>(width); ++i)
      if (!std::isfinite(s.values[i])) return stats.reason = "a key that is not finite", false;
    if (!evenKeys(track.times, s.start, s.rate)) {
      const std::size_t frames = frameGrid(track.times);
      if (frames < 2) {  // keys off any grid keep their times
        s.times = track.times.data();
        s.rate = 0.0f;
        ++stats.tracksTimed;
        // The check runs at least as finely as these keys come (to 480 a second).
        for (std::size_t k = 1; k < track.times.size(); ++k)
          fastest = std::max(fastest, std::min(480.0f, 1.0f / (track.times[k] - track.times[k - 1])));
        analyze(s);
        sources.push_back(s);
        return true;
      }
      using Value = typename std::decay_t<decltype(track.values)>::value_type;
      const float dt = (track.times.back() - track.times.front()) / static_cast<float>(frames - 1);
      s.start = track.times.front();
      s.rate = 1.0f / dt;
      if (track.times.size() * kSparseKeysPerFrame <= frames && frames <= 65536) {
        // Few keys (the optimizer removed the rest, which interpolation recovers): kept
        // as they are, with their frame numbers, rather than filling every frame.
        std::vector<std::uint16_t>& numbers = frameNumbers.emplace_back(track.times.size());
        for (std::size_t k = 0; k < track.times.size(); ++k)
          numbers[k] = static_cast<std::uint16_t>(std::lround((track.times[k] - track.times.front()) / dt));
        s.frames = numbers.data();
        ++stats.tracksSparse;
      } else {
        std::vector<float>& grid = resampled.emplace_back(frames * static_cast<std::size_t>(width));
        for (std::size_t f = 0; f < frames; ++f) {
          const Value v = valueAt(track, track.times.front() + static_cast<float>(f) * dt);
          std::memcpy(&grid[f * static_cast<std::size_t>(width)], &v, sizeof(float) * static_cast<std::size_t>(width));
        }
        s.values = grid.data();
        s.keys = static_cast<std::uint32_t>(frames);
        ++stats.tracksResampled;
      }
    }
    fastest = std::max(fastest, s.rate);
    analyze(s);
    sources.push_back(s);
    return true;
  };
  for (const JointTrack& jt : clip.tracks) {
    if (jt.joint < 0 || static_cast<std::size_t>(jt.joint) >= joints) continue;
    if (!add(jt.joint, CompactTrack::Property::Translation, jt.translation, 3) || !add(jt.joint, CompactTrack::Property::Rotation, jt.rotation, 4) ||
        !add(jt.joint, CompactTrack::Property::Scale, jt.scale, 3))
      return {};
  }
  if (sources.empty()) {
    stats.reason = "no joint tracks";
    return {};
  }

  // Levers from the rest pose: how far each joint's rotation can swing a virtual vertex
  // (its farthest descendant plus the vertex distance), and the scale above each joint.
  const std::vector<glm::mat4> restModel = skeleton.restModelMatrices();
  std::vector<float> lever(joints, options.virtualVertexDistance);
  for (std::size_t j = 0; j < joints; ++j)
    for (int a = static_cast<int>(j); a >= 0; a = skeleton.parents[static_cast<std::size_t>(a)]) {
      const auto ai = static_cast<std::size_t>(a);
      lever[ai] = std::max(lever[ai], glm::length(glm::vec3(restModel[j][3]) - glm::vec3(restModel[ai][3])) +
                                          options.virtualVertexDistance);
    }
  const auto scaleAbove = [&](int joint) {
    const int p = skeleton.parents[static_cast<std::size_t>(joint)];
    const glm::mat4& m = p < 0 ? skeleton.rootTransform : restModel[static_cast<std::size_t>(p)];
    return std::max({glm::length(glm::vec3(m[0])), glm::length(glm::vec3(m[1])), glm::length(glm::vec3(m[2]))});
  };

  // Key reduction, within its share of the budget: tracks left with few keys keep them sparse.
  std::deque<std::vector<float>> reduced;
  for (Source& src : sources) {
    const float tolerance = componentTolerance(src, options.keyReductionShare * options.errorBudget,
                                               lever[static_cast<std::size_t>(src.joint)], scaleAbove(src.joint));
    std::vector<std::uint16_t> keep = keysToKeep(src, tolerance);
    if (keep.empty()) continue;
    std::vector<float>& values = reduced.emplace_back();
    for (const std::uint16_t k : keep)
      values.insert(values.end(), src.values + k * static_cast<std::size_t>(src.width), src.values + (k + 1) * static_cast<std::size_t>(src.width));
    stats.keysDropped += static_cast<int>(src.keys - keep.size());
    ++stats.tracksSparse;
    src.values = values.data();
    src.keys = static_cast<std::uint32_t>(keep.size());
    src.frames = frameNumbers.emplace_back(std::move(keep)).data();
    analyze(src);
  }

  // First guess: each track within half the budget on its own (the check then refines).
  const float share = 0.5f * options.errorBudget;
  std::vector<int> bits(sources.size());
  for (std::size_t i = 0; i < sources.size(); ++i) {
    const Source& s = sources[i];
    const float l = lever[static_cast<std::size_t>(s.joint)], ps = scaleAbove(s.joint);
    bits[i] = s.keys == 1 ? 32 : proxyError(s, 8, l, ps) <= share ? 8 : proxyError(s, 16, l, ps) <= share ? 16 : 32;
  }

  // Check at the keys: the float clip and the compact one, through the hierarchy.
  const float duration = clip.duration;
  // Bounded work whatever the clip: at most ~2 million joint evaluations a check, 48 checks.
  const int frameCap = std::max(2, static_cast<int>(2'000'000 / std::max<std::size_t>(joints, 1)));
  const float wanted = std::ceil(std::min(duration * fastest, 1e6f)) + 1.0f;
  const int frames = fastest > 0.0f && duration > 0.0f ? std::clamp(static_cast<int>(wanted), 2, std::min(1000, frameCap)) : 1;
  std::vector<glm::mat4> reference(static_cast<std::size_t>(frames) * joints), model(joints);
  std::vector<Transform> pose(joints);
  const auto frameTime = [&](int f) { return frames > 1 ? duration * static_cast<float>(f) / static_cast<float>(frames - 1) : 0.0f; };
  for (int f = 0; f < frames; ++f) {
    sampleClip(clip, frameTime(f), skeleton.restPose, pose);
    localToModel(skeleton, pose, std::span<glm::mat4>(reference).subspan(static_cast<std::size_t>(f) * joints, joints));
  }
  std::vector<float> perJoint(joints), worstPerJoint(joints);
  CompactClip compact;
  const int maxChecks = std::min(48, 4 * static_cast<int>(sources.size()) + 4);  // then the float clip stays
  for (stats.checks = 1;; ++stats.checks) {
    compact = build(sources, bits, duration);
    std::fill(worstPerJoint.begin(), worstPerJoint.end(), 0.0f);
    for (int f = 0; f < frames; ++f) {
      sampleCompactClip(compact, frameTime(f), skeleton.restPose, pose);
      localToModel(skeleton, pose, model);
      virtualVertexError(std::span<const glm::mat4>(reference).subspan(static_cast<std::size_t>(f) * joints, joints), model,
                         options.virtualVertexDistance, perJoint);
      for (std::size_t j = 0; j < joints; ++j) worstPerJoint[j] = std::max(worstPerJoint[j], perJoint[j]);
    }
    const auto worst = std::max_element(worstPerJoint.begin(), worstPerJoint.end());
    stats.maxError = *worst;
    if (stats.maxError <= options.errorBudget || stats.checks >= maxChecks) break;
    // Refine the track, on the worst joint's chain, whose quantization moves it most.
    const auto w = static_cast<std::size_t>(worst - worstPerJoint.begin());
    int pick = -1;
    float most = -1.0f;
    for (std::size_t i = 0; i < sources.size(); ++i) {
      if (bits[i] >= 32) continue;
      const auto j = static_cast<std::size_t>(sources[i].joint);
      bool above = false;
      for (int a = static_cast<int>(w); a >= 0; a = skeleton.parents[static_cast<std::size_t>(a)]) above |= static_cast<std::size_t>(a) == j;
      if (!above) continue;
      const float l = glm::length(glm::vec3(restModel[w][3]) - glm::vec3(restModel[j][3])) + options.virtualVertexDistance;
      const float e = proxyError(sources[i], bits[i], l, scaleAbove(sources[i].joint));
      if (e > most) most = e, pick = static_cast<int>(i);
    }
    if (pick < 0) break;  // every track above it is float already: the error is the time grid's
    bits[static_cast<std::size_t>(pick)] = bits[static_cast<std::size_t>(pick)] == 8 ? 16 : 32;
  }
  for (const CompactTrack& t : compact.tracks)
    (t.bits == 8 ? stats.tracks8 : t.bits == 16 ? stats.tracks16 : t.bits == 32 ? stats.tracks32 : stats.tracks64)++;
  stats.compactBytes = compact.bytes();
  if (stats.maxError > options.errorBudget) {
    stats.reason = "the budget was not met at every key (the float clip is kept)";
    return {};
  }
  stats.compacted = true;
  return compact;
}

}  // namespace

}  // namespace marionette
