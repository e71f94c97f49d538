// The RIFF/WAVE layout shared by the WAV readers (alignment_io.hpp's mono 16-bit readWav,
// audio_clip.hpp's float clips): chunks walked within the bytes there are, the fmt chunk
// checked, one sample read as a value in [-1, 1).
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

namespace marionette::speech::detail {

struct WavFormat {
  std::uint16_t tag = 0, channels = 0, blockAlign = 0, bits = 0;  // tag: 1 PCM, 3 IEEE float
  std::uint32_t sampleRate = 0;
};

struct WavLayout {
  WavFormat format;
  const unsigned char* data = nullptr;  // the first frame, inside the bytes given
  std::size_t frames = 0;
};

// Finds the fmt and data chunks of a RIFF/WAVE file (PCM 8/16/24/32-bit, float 32/64,
// WAVE_FORMAT_EXTENSIBLE of either; unknown chunks skipped, odd sizes padded). Returns
// what is wrong (without the file's name), or "" with `out` set.
[[nodiscard]] std::string parseWavLayout(std::span<const unsigned char> bytes, WavLayout& out);

// One sample at `p` as a value in [-1, 1) (float files: as stored; NaN and infinity read as 0).
[[nodiscard]] double wavSample(const unsigned char* p, const WavFormat& format) noexcept;

}  // namespace marionette::speech::detail
