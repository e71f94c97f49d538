// The procedural controllers' random draws (saccades, idle life): splitmix64 for uniforms in
// [0, 1) and FNV-1a for seeds from text. Small, fast, the same on every platform: a request's
// motion depends only on its seed and the scene time.
#pragma once
#include <cstdint>
#include <string_view>

namespace marionette::detail {

[[nodiscard]] inline double uniformDraw(std::uint64_t& state) noexcept {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * (1.0 / 9007199254740992.0);
}

[[nodiscard]] inline std::uint64_t textSeed(std::string_view text, std::uint64_t seed = 1469598103934665603ull) noexcept {
  for (char c : text) seed = (seed ^ static_cast<unsigned char>(c)) * 1099511628211ull;
  return seed;
}

}  // namespace marionette::detail
