// RIFF/WAVE chunks and sample formats (wav_format.hpp). Every read is bounded by the bytes
// given: a size field that points past them is an error naming the chunk, never a read.
#include "wav_format.hpp"

#include <cmath>
#include <cstring>

namespace marionette::speech::detail {
namespace {

constexpr std::uint16_t kFormatPcm = 1, kFormatFloat = 3, kFormatExtensible = 0xFFFE;

std::uint16_t le16(const unsigned char* p) { return static_cast<std::uint16_t>(p[0] | (p[1] << 8)); }
std::uint32_t le32(const unsigned char* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

// A chunk id as it may be shown in a message: printable ASCII, else '?'.
std::string chunkName(const unsigned char* id) {
  std::string out = "'";
  for (int i = 0; i < 4; ++i) out += (id[i] >= 0x20 && id[i] < 0x7f) ? static_cast<char>(id[i]) : '?';
  return out + "'";
}

std::string parseFmt(const unsigned char* p, std::uint32_t size, WavFormat& f) {
  if (size < 16) return "fmt chunk is " + std::to_string(size) + " bytes, expected at least 16";
  f.tag = le16(p);
  f.channels = le16(p + 2);
  f.sampleRate = le32(p + 4);
  f.blockAlign = le16(p + 12);
  f.bits = le16(p + 14);
  if (f.tag == kFormatExtensible) {
    if (size < 40) return "WAVE_FORMAT_EXTENSIBLE fmt chunk is " + std::to_string(size) + " bytes, expected 40";
    // The sub-format GUID's first two bytes are the real format tag; the rest is fixed.
    static const unsigned char kGuidTail[14] = {0x00, 0x00, 0x00, 0x00, 0x10, 0x00, 0x80,
                                               0x00, 0x00, 0xAA, 0x00, 0x38, 0x9B, 0x71};
    if (std::memcmp(p + 26, kGuidTail, sizeof kGuidTail) != 0) return "unknown WAVE_FORMAT_EXTENSIBLE sub-format";
    f.tag = le16(p + 24);
  }
  if (f.tag != kFormatPcm && f.tag != kFormatFloat)
    return "format tag " + std::to_string(f.tag) + " is not supported (expected PCM or IEEE float)";
  if (f.channels == 0 || f.channels > 64) return std::to_string(f.channels) + " channels (expected 1 to 64)";
  if (f.sampleRate == 0 || f.sampleRate > 1'000'000)
    return "sample rate " + std::to_string(f.sampleRate) + " Hz (expected 1 to 1000000)";
  const bool pcmBits = f.tag == kFormatPcm && (f.bits == 8 || f.bits == 16 || f.bits == 24 || f.bits == 32);
  const bool floatBits = f.tag == kFormatFloat && (f.bits == 32 || f.bits == 64);
  if (!pcmBits && !floatBits)
    return std::to_string(f.bits) + "-bit " + (f.tag == kFormatPcm ? "PCM" : "float") +
           " is not supported (expected PCM 8/16/24/32 or float 32/64)";
  if (f.blockAlign != f.channels * (f.bits / 8))
    return "block align " + std::to_string(f.blockAlign) + " does not match " + std::to_string(f.channels) +
           " channels of " + std::to_string(f.bits) + " bits";
  return {};
}

}  // namespace

std::string parseWavLayout(std::span<const unsigned char> bytes, WavLayout& out) {
  out = {};
  if (bytes.size() < 12 || std::memcmp(bytes.data(), "RIFF", 4) != 0 || std::memcmp(bytes.data() + 8, "WAVE", 4) != 0)
    return "not a RIFF/WAVE file";
  // Writers disagree on the RIFF size; the file's real length bounds the chunks.
  const std::size_t end = bytes.size();
  std::size_t pos = 12;
  bool haveFormat = false;
  std::size_t dataSize = 0;
  while (pos + 8 <= end) {
    const unsigned char* header = bytes.data() + pos;
    const std::uint32_t size = le32(header + 4);
    const std::size_t body = pos + 8;
    const std::size_t available = end - body;
    const bool isData = std::memcmp(header, "data", 4) == 0;
    if (isData) {
      // Streaming writers leave 0xFFFFFFFF; any other size must fit the file.
      if (size == 0xFFFFFFFFu) dataSize = available;
      else if (size > available)
        return "truncated: the data chunk declares " + std::to_string(size) + " bytes, the file holds " +
               std::to_string(available);
      else dataSize = size;
      out.data = bytes.data() + body;
      if (haveFormat) break;
    } else {
      if (size > available)
        return "truncated: chunk " + chunkName(header) + " at byte " + std::to_string(pos) + " declares " +
               std::to_string(size) + " bytes, " + std::to_string(available) + " remain";
      if (std::memcmp(header, "fmt ", 4) == 0) {
        if (haveFormat) return "two fmt chunks";
        if (std::string why = parseFmt(header + 8, size, out.format); !why.empty()) return why;
        haveFormat = true;
        if (out.data) break;
      }
    }
    const std::size_t next = body + static_cast<std::size_t>(isData ? dataSize : size);
    pos = next + (next & 1u);  // chunks are padded to an even size
  }
  if (!haveFormat) return "no fmt chunk";
  if (!out.data) return "no data chunk";
  out.frames = dataSize / out.format.blockAlign;
  return {};
}

double wavSample(const unsigned char* p, const WavFormat& f) noexcept {
  if (f.tag == kFormatFloat) {
    double v = 0.0;
    if (f.bits == 32) {
      float x;
      std::memcpy(&x, p, 4);  // little-endian host (x86-64, ARM64)
      v = x;
    } else {
      std::memcpy(&v, p, 8);
    }
    return std::isfinite(v) ? v : 0.0;
  }
  // Powers of two: the scaling is exact, so 16-bit PCM read back as 16-bit is bit-exact.
  switch (f.bits) {
    case 8: return (static_cast<int>(p[0]) - 128) / 128.0;
    case 16: return static_cast<std::int16_t>(le16(p)) / 32768.0;
    case 24: {
      std::int32_t v = static_cast<std::int32_t>(p[0] | (p[1] << 8) | (p[2] << 16));
      if (v & 0x800000) v -= 0x1000000;
      return v / 8388608.0;
    }
    default: return static_cast<std::int32_t>(le32(p)) / 2147483648.0;
  }
}

}  // namespace marionette::speech::detail
