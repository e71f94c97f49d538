// Compact clips: the keys of a clip quantized under an error budget, in the spirit of
// ACL (Animation Compression Library). What the runtime samples when a clip allows it.
//
// - Evenly spaced keys are found from the time by one multiply, no search. Keys on a
//   frame grid with frames left out (as FBX exports hold them) are resampled on that
//   grid, which is exact for linear and step keys. Keys off any grid (curves an exporter
//   subdivided) keep their float times and are found by a binary search.
// - Each component is stored in 8 or 16 bits within the track's own range [min, max]
//   (a rotation drops the component that is never small over the track and rebuilds it
//   as sqrt(1 - the others' squares)). A rotation that needs more, or has no such
//   component, takes 64 bits a key (smallest three); a translation or scale, floats.
// - The bits are chosen per track so that virtual vertices a few centimetres from each
//   joint (ACL's error metric: clip_error.hpp) stay within the budget in model space,
//   checked at every key of the clip against the float clip, with the hierarchy's
//   accumulation included. The stats say what the error came to.
//
// Linear and step tracks are compacted; a clip with a cubic-spline track stays float.
// Morph-weight tracks are not part of it (they stay in the float clip).
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "marionette/animation/clip.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette {

struct CompactClipOptions {
  float errorBudget = 1e-4f;            // metres at a virtual vertex (0.1 mm)
  float virtualVertexDistance = 0.03f;  // metres from each joint (3 cm, ACL's default)
  // Key reduction: a track's keys that interpolation recovers within this share of the
  // budget (at its joint's lever) are dropped, and the track keeps the rest sparse with
  // their frame numbers when that is at most a third of its frames. 0 turns it off. When
  // the clip then misses the budget, it is compacted again without (stats say so).
  float keyReductionShare = 0.25f;
};

// One property of one joint.
struct CompactTrack {
  enum class Property : std::uint8_t { Translation, Rotation, Scale };
  std::int32_t joint = -1;
  Property property = Property::Translation;
  // Per stored component: 8 or 16 (within the track's range, a rotation dropping one
  // component), 32 (floats), or for rotations 64: each key in 64 bits, the largest
  // component dropped (2 bits say which) and the other three in 20 bits each.
  std::uint8_t bits = 32;
  std::uint8_t dropped = 3;   // rotations in 8 / 16 bits: the component rebuilt (x, y, z, w = 0..3)
  bool step = false;          // step interpolation (else linear)
  std::uint32_t keys = 0;
  std::uint32_t offset = 0;   // bytes into CompactClip::data
  float start = 0.0f;         // time of key 0, or of frame 0 of a sparse track
  float rate = 0.0f;          // keys (frames) per second; 0 for one key, or keys at float times
  static constexpr std::uint32_t kEvenKeys = 0xFFFFFFFFu;
  // Where the keys fall. kEvenKeys: key k at start + k / rate. Otherwise bytes into
  // CompactClip::data of the keys' times: with rate 0, floats (keys off any grid); with
  // rate > 0, 16-bit frame numbers f, key at start + f / rate (a sparse track: the keys
  // the load-time optimizer kept on the clip's frame grid, when much fewer than its frames).
  std::uint32_t times = kEvenKeys;
  float min[3] = {0, 0, 0};   // value = min + quantized * scale, per stored component
  float scale[3] = {0, 0, 0};
};

struct CompactClip {
  float duration = 0.0f;
  // The animated rotations in 8 or 16 bits, then the animated translations and scales in
  // 8 or 16 bits (each run decoded four tracks at a time, whatever their widths; evenly
  // keyed tracks first in each), then the other animated tracks (floats, 64-bit rotations),
  // then the constants (one key, stored as floats, copied); by joint within each.
  std::vector<CompactTrack> tracks;
  std::uint32_t rotations = 0, vectors = 0, constants = 0;  // the lengths of those runs
  std::vector<std::uint8_t> data;    // the keys, track after track

  [[nodiscard]] bool empty() const noexcept { return tracks.empty(); }
  [[nodiscard]] std::size_t bytes() const noexcept {
    return tracks.size() * sizeof(CompactTrack) + data.size();
  }
};

struct CompactClipStats {
  bool compacted = false;
  std::string reason;            // why not, when not
  std::size_t floatBytes = 0;    // the float clip's keys: times and values of its joint tracks
  std::size_t compactBytes = 0;  // CompactClip::bytes()
  int tracks8 = 0, tracks16 = 0, tracks32 = 0, tracks64 = 0;  // 64: smallest-three rotations
  int tracksResampled = 0;       // tracks whose keys were put on their frame grid
  int tracksTimed = 0;           // tracks whose keys keep their (uneven) times
  int tracksSparse = 0;          // tracks whose keys stay few, with their frame numbers
  int keysDropped = 0;           // keys the key reduction removed
  bool keyReductionUndone = false;  // it broke the budget: compacted again without
  float maxError = 0.0f;         // metres, largest virtual-vertex distance found at the keys
  int checks = 0;                // encode-and-measure rounds the bit choice took
};

// Compacts `clip` (bound to `skeleton`). Empty, with the reason in the stats, when the
// clip cannot be (cubic tracks, keys not evenly spaced, nothing to compact).
[[nodiscard]] CompactClip compactClip(const Clip& clip, const Skeleton& skeleton, const CompactClipOptions& options = {},
                                      CompactClipStats* stats = nullptr);

// As sampleClip / sampleClipTracks (sampling.hpp), from the compact keys: joints without
// a track get `rest` (sampleCompactClip) or are left untouched (sampleCompactClipTracks).
// Per-frame code: no allocation, never NaN, the span contract of pose.hpp.
// `hints` (optional, one per track of the clip): the key each track with sparse or
// timed keys was last found at, tried before a binary search and updated, as a
// SamplingCursor does for float clips. The result does not depend on them.
void sampleCompactClip(const CompactClip& clip, float time, std::span<const Transform> rest, std::span<Transform> out,
                       std::uint32_t* hints = nullptr) noexcept;
void sampleCompactClipTracks(const CompactClip& clip, float time, std::span<Transform> out,
                             std::uint32_t* hints = nullptr) noexcept;
// The two halves of sampleCompactClipTracks, for a caller that samples over one pose
// many times (AnimationClip::pose): the constant tracks written into `pose` once, and
// the animated tracks written each frame. Together, the bits of sampleCompactClipTracks.
void applyCompactClipConstants(const CompactClip& clip, std::span<Transform> pose) noexcept;
void sampleCompactClipAnimated(const CompactClip& clip, float time, std::span<Transform> out,
                               std::uint32_t* hints = nullptr) noexcept;
// Track after track, without the four-wide decoding: the definition, for tests (the same bits).
void sampleCompactClipTracksScalar(const CompactClip& clip, float time, std::span<Transform> out) noexcept;

}  // namespace marionette
