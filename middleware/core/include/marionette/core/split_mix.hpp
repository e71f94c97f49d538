// SplitMix64 (Steele, Lea and Flood 2014): a tiny, fast random stream that gives the same
// sequence on every platform, for the places that need reproducible randomness (PRT's ray
// directions, the tracker's RANSAC samples).
#pragma once
#include <cstdint>

namespace marionette {

struct SplitMix64 {
  std::uint64_t state;
  constexpr std::uint64_t next() noexcept {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // [0, 1) with 24 bits.
  constexpr float uniform() noexcept { return static_cast<float>(next() >> 40) * (1.0f / 16777216.0f); }
};

}  // namespace marionette
