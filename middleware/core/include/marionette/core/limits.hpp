// The largest inputs the library accepts (Filament's style: stated, not discovered).
// Each is an error naming the file and the limit when exceeded, checked before
// anything of that size is allocated or read.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

namespace marionette::limits {

// Text files a user names: scene files, character profiles, joint maps, BML files,
// AR scene files. Only regular files are read (not a FIFO, a device, a folder).
inline constexpr std::uintmax_t kMaxTextFileBytes = std::uintmax_t{16} << 20;  // 16 MiB

// Images: environment maps and light probes (decoded to float RGB), backgrounds and
// textures. 8192 x 4096 is an "8k" HDRI; a float RGB copy of it takes 384 MiB.
inline constexpr int kMaxImageSide = 16384;
inline constexpr std::uint64_t kMaxImagePixels = std::uint64_t{8192} * 4096;

// Model files (glTF, GLB, VRM, VRMA, FBX, BVH, ...), read whole before parsing.
inline constexpr std::uintmax_t kMaxModelFileBytes = std::uintmax_t{512} << 20;  // 512 MiB
// Elements of one array of a model file: a mesh's vertices or indices, a clip
// track's keys, a skin's matrices. 2^26 (67 M) is far above any real character;
// a hostile count stops here before it allocates gigabytes.
inline constexpr std::size_t kMaxArrayElements = std::size_t{1} << 26;
// Joints of a skeleton (every node of a glTF; vertex joint indices are 16 bits).
inline constexpr std::size_t kMaxJoints = 65535;

// One spoken line (a <speech> behavior, a SpeechRequest): synthesis takes about
// 0.05 ms a character with espeak-ng at this size (and grows faster beyond it: 100 KB
// took 48 s), so a line is at most 2000 characters (some two minutes of speech) with
// at most 256 word marks. It is said off the frame path (SpeechService::prepare).
// BML's own limits (behaviors, sync points, repetitions per block) are in
// bml/document.hpp and bml/scheduler.hpp.
inline constexpr std::size_t kMaxSpeechCharacters = 2000;
inline constexpr std::size_t kMaxSpeechMarks = 256;

inline constexpr int kMaxImageChannels = 64;

// "" when a width x height image of `channels` channels is within the limits, else
// what is wrong (for an error that also names the file). Check a header with it
// before decoding.
[[nodiscard]] inline std::string imageSizeProblem(long long width, long long height, long long channels = 1) {
  if (width <= 0 || height <= 0)
    return "has no pixels (" + std::to_string(width) + "x" + std::to_string(height) + ")";
  if (width > kMaxImageSide || height > kMaxImageSide || std::uint64_t(width) * std::uint64_t(height) > kMaxImagePixels)
    return "is " + std::to_string(width) + "x" + std::to_string(height) + " pixels, more than the library reads (" +
           std::to_string(kMaxImageSide) + " a side and " + std::to_string(kMaxImagePixels) +
           " pixels in all: limits::kMaxImagePixels)";
  if (channels > kMaxImageChannels)
    return "has " + std::to_string(channels) + " channels, more than " + std::to_string(kMaxImageChannels);
  return "";
}

}  // namespace marionette::limits
