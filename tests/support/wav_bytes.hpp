// WAV files assembled byte by byte for the readers' tests: any format tag, channel count,
// rate and bit depth, chunks before fmt, and sizes that lie.
#pragma once
#include <cstdint>
#include <string>

namespace marionette::test::wav {

// `bytes` little-endian bytes of v.
inline void put(std::string& s, std::uint32_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) s += static_cast<char>((v >> (8 * i)) & 0xff);
}

// A WAV file: optional chunks before fmt, the fmt chunk body, data.
inline std::string makeWav(const std::string& fmtBody, const std::string& data, const std::string& before = "") {
  std::string chunks = before;
  chunks += "fmt ";
  put(chunks, static_cast<std::uint32_t>(fmtBody.size()), 4);
  chunks += fmtBody;
  chunks += "data";
  put(chunks, static_cast<std::uint32_t>(data.size()), 4);
  chunks += data;
  std::string wav = "RIFF";
  put(wav, static_cast<std::uint32_t>(4 + chunks.size()), 4);
  return wav + "WAVE" + chunks;
}

// A plain 16-byte fmt body (tag 1 PCM, 3 float, 0xFFFE extensible: see extensibleFmt).
inline std::string fmtBody(std::uint16_t tag, std::uint16_t channels, std::uint32_t rate, std::uint16_t bits) {
  std::string f;
  put(f, tag, 2);
  put(f, channels, 2);
  put(f, rate, 4);
  put(f, rate * channels * bits / 8, 4);
  put(f, channels * bits / 8, 2);
  put(f, bits, 2);
  return f;
}

// A 40-byte WAVE_FORMAT_EXTENSIBLE fmt body whose sub-format is `subFormat` (1 PCM, 3 float).
inline std::string extensibleFmt(std::uint16_t subFormat, std::uint16_t channels, std::uint32_t rate, std::uint16_t bits) {
  std::string ext = fmtBody(0xFFFE, channels, rate, bits);
  put(ext, 22, 2);    // cbSize
  put(ext, bits, 2);  // valid bits
  put(ext, channels == 2 ? 3u : 4u, 4);  // channel mask: front left+right, or front centre
  put(ext, subFormat, 2);
  ext += std::string("\x00\x00\x00\x00\x10\x00\x80\x00\x00\xAA\x00\x38\x9B\x71", 14);
  return ext;
}

}  // namespace marionette::test::wav
