// The byte layout of CompactClip::data, shared by the encoder (compact_clip.cpp) and
// the sampler (compact_clip_sampling.cpp).
#pragma once
#include <cstdint>
#include <cstring>

namespace marionette::compact {

template <class T>
T readAt(const std::uint8_t* p) noexcept {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

// Smallest three in 64 bits: 2 bits say which component is the largest (rebuilt), the
// other three are 20 bits each over [-1/sqrt2, 1/sqrt2].
constexpr float kS3Half = 0.70710678f;
constexpr float kS3Levels = 1048575.0f;  // 2^20 - 1

// Where the three kept components of a rotation go (x, y, z, w = 0..3), by the one dropped.
constexpr int kKept[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};


// Bytes of padding after the last track: the decoder may read this far past a key.
constexpr std::uint32_t kReadPastKey = 4;

}  // namespace marionette::compact
