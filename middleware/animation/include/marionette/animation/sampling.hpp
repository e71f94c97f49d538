// Sampling a clip at a time into a local pose. Per-frame code: no allocation,
// no exceptions, never NaN out (rotations are renormalized).
// Spans: the span contract of pose.hpp (the shortest span decides; nothing past it is touched).
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "marionette/animation/clip.hpp"

namespace marionette {

enum class WrapMode { Loop, Clamp };

// Maps scene-clock time (double, may be huge) to clip-local time in [0, duration].
// Done in double so that a clip sampled at t = 1e7 s has no float jitter.
[[nodiscard]] float wrapClipTime(double time, float duration, WrapMode mode) noexcept;

// Remembers the last key interval of each track so that forward playback finds
// its keys in O(1). Size it once per (clip, player) with reset(); sampling with a
// cursor sized for another clip falls back to binary search, never to UB.
struct SamplingCursor {
  std::vector<std::uint32_t> keys;  // 3 per joint track (T, R, S), then one per morph track
  const Clip* clip = nullptr;
  void reset(const Clip& c);
};

// Writes the pose of `clip` at `time` (clip-local seconds) into `out`. Joints the
// clip has no track for (or whose track is empty) get `rest`. `out` and `rest`
// should have the skeleton's joint count (span contract: joints past the shorter are untouched).
void sampleClip(const Clip& clip, float time, std::span<const Transform> rest, std::span<Transform> out,
                SamplingCursor* cursor = nullptr) noexcept;

// Same, but writes only the joints the clip animates (others untouched).
void sampleClipTracks(const Clip& clip, float time, std::span<Transform> out,
                      SamplingCursor* cursor = nullptr) noexcept;

// Morph weights of `clip` at `time` into `weights` (indexed like Asset::morphTargets);
// targets without a track keep their value.
void sampleMorphWeights(const Clip& clip, float time, std::span<float> weights) noexcept;

// Index i of the key interval [times[i], times[i+1]) holding t, clamped to
// [0, n-2] (0 for n < 2). `hint` is tried first.
[[nodiscard]] std::uint32_t findKeyInterval(std::span<const float> times, float t, std::uint32_t hint) noexcept;

}  // namespace marionette
