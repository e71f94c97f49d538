// A sound to hand to an engine: a WAV file decoded to float samples, every channel kept
// (AsapRealizer's <bmlt:audiofile>; SceneListener::onAudio). Read at command time, once;
// the samples are shared, never copied per frame.
#pragma once
#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "marionette/core/file_reader.hpp"

namespace marionette::speech {

struct AudioClip {
  // Interleaved: frame after frame, each `channels` samples. PCM files give [-1, 1);
  // float files their values as stored (NaN and infinity read as 0).
  std::vector<float> samples;
  int channels = 0;
  int sampleRate = 0;  // frames per second
  int sourceBits = 0;  // what the file held: 8, 16, 24, 32 (PCM) or 32, 64 (float)
  bool sourceFloat = false;

  [[nodiscard]] std::size_t frames() const noexcept {
    return channels > 0 ? samples.size() / static_cast<std::size_t>(channels) : 0;
  }
  [[nodiscard]] double duration() const noexcept {
    return sampleRate > 0 ? static_cast<double>(frames()) / sampleRate : 0.0;
  }
};

// The largest WAV read as a clip (about 23 minutes of 48 kHz stereo 16-bit).
inline constexpr std::uintmax_t kMaxAudioClipBytes = 256u << 20;

// Decodes a RIFF/WAVE file's bytes (PCM 8/16/24/32-bit, float 32/64-bit, any channel
// count up to 64 and rate up to 1 MHz, WAVE_FORMAT_EXTENSIBLE; unknown chunks skipped).
// Returns "" with `out` set, or "SOURCE: problem" (a truncated chunk, a zero rate, a
// format it does not read, no samples at all).
[[nodiscard]] std::string parseAudioClip(std::span<const unsigned char> bytes, std::string_view source, AudioClip& out);
// Reads `file` through `files` (core/file_reader.hpp; empty: the disk), then parses it.
[[nodiscard]] std::string readAudioClip(const FileReader& files, const std::filesystem::path& file, AudioClip& out);

}  // namespace marionette::speech
