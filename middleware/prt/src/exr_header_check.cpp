#include "exr_header_check.hpp"

#include "marionette/core/limits.hpp"

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <istream>
#include <utility>

namespace marionette::prt {

namespace {

// Bytes of OpenEXR's own fixed-size attribute types (ImfAttribute.h and friends), else -1.
int exrFixedSize(const std::string& type) {
  static const std::pair<const char*, int> kSizes[] = {
      {"box2i", 16},  {"box2f", 16},       {"v2i", 8},        {"v2f", 8},      {"v2d", 16},  {"v3i", 12},
      {"v3f", 12},    {"v3d", 24},         {"m33f", 36},      {"m33d", 72},    {"m44f", 64}, {"m44d", 128},
      {"int", 4},     {"float", 4},        {"double", 8},     {"compression", 1}, {"lineOrder", 1},
      {"envmap", 1},  {"deepImageState", 1}, {"tiledesc", 9}, {"chromaticities", 32}, {"keycode", 28},
      {"timecode", 8}, {"rational", 8}};
  for (const auto& [name, size] : kSizes)
    if (type == name) return size;
  return -1;
}

// Four bytes, little-endian, as OpenEXR stores them.
std::int32_t readLe32(std::istream& in) {
  unsigned char b[4] = {0, 0, 0, 0};
  in.read(reinterpret_cast<char*>(b), 4);
  return static_cast<std::int32_t>(std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 | std::uint32_t(b[2]) << 16 |
                                   std::uint32_t(b[3]) << 24);
}

// Real files use tiles of 32 to 256 pixels; at 8 a side an 8192 x 4096 image has 524288.
constexpr std::int32_t kMinTileSide = 8;

}  // namespace

std::string exrHeaderProblem(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  unsigned char start[8];
  if (!in.read(reinterpret_cast<char*>(start), 8) || start[0] != 0x76 || start[1] != 0x2f || start[2] != 0x31 ||
      start[3] != 0x01)
    return "";
  std::error_code ec;
  const auto fileSize = static_cast<std::int64_t>(std::filesystem::file_size(path, ec));
  if (ec) return "";
  const bool multiPart = (start[5] & 0x10) != 0;                     // version flags bit 12
  const std::size_t maxName = (start[5] & 0x04) != 0 ? 255 : 31;     // bit 10: long names
  enum class Text { Ok, End, TooLong };
  auto text = [&](std::string& out) {  // a NUL-terminated name of at most maxName characters
    out.clear();
    for (int c; (c = in.get()) != EOF;) {
      if (c == 0) return Text::Ok;
      if (out.size() == maxName) return Text::TooLong;
      out.push_back(static_cast<char>(c));
    }
    return Text::End;
  };
  const std::string tooLong = "has a damaged OpenEXR header: an attribute name or type is longer than " +
                              std::to_string(maxName) + " characters";
  for (std::string name, type;;) {  // one header per pass
    for (;;) {  // its attributes
      const Text n = text(name);
      if (n == Text::TooLong) return tooLong;
      if (n == Text::End) return "";  // truncated: OpenEXR says so itself
      if (name.empty()) break;        // the end of this header
      const Text t = text(type);
      if (t == Text::TooLong) return tooLong;
      if (t == Text::End) return "";
      const std::int32_t bytes = readLe32(in);
      if (!in) return "";
      const std::int64_t at = static_cast<std::int64_t>(in.tellg()), remaining = fileSize - at;
      const std::string damaged = "has a damaged OpenEXR header: attribute '" + name + "' (" + type + ") ";
      if (bytes < 0 || bytes > remaining)
        return damaged + "declares " + std::to_string(bytes) + " bytes, " + std::to_string(remaining) +
               " remain in the file";
      // OpenEXR reads its own types by their content, not the declared size: they must agree.
      std::int64_t content = bytes;
      if (const int fixed = exrFixedSize(type); fixed >= 0) {
        content = fixed;
      } else if (type == "chlist") {  // channels: name, 16 bytes each, until an empty name
        std::string channel;
        while (text(channel) == Text::Ok && !channel.empty() && in.seekg(16, std::ios::cur)) {
        }
        content = static_cast<std::int64_t>(in.tellg()) - at;
      } else if (type == "preview") {  // width, height, then RGBA bytes
        const auto width = static_cast<std::uint32_t>(readLe32(in)), height = static_cast<std::uint32_t>(readLe32(in));
        if (!in) return "";
        content = static_cast<std::int64_t>(8 + std::uint64_t(width) * height * 4);
      }
      if (!in || content != bytes)
        return damaged + "declares " + std::to_string(bytes) + " bytes but holds " +
               (in ? std::to_string(content) : std::string("more than the file has"));
      // OpenEXR allocates a chunk table for the data window when it opens the file, before
      // anyone reads the size: a 900-byte file asked for 1.3 GB (fuzz_environment_map).
      if (type == "box2i" && name == "dataWindow") {
        in.seekg(at);
        std::int32_t box[4];
        for (std::int32_t& v : box) v = readLe32(in);
        const long long width = static_cast<long long>(box[2]) - box[0] + 1, height = static_cast<long long>(box[3]) - box[1] + 1;
        if (std::string why = limits::imageSizeProblem(width, height); !why.empty())
          return "has an OpenEXR data window that " + why;
      } else if (type == "tiledesc") {  // tiles this small would make millions of chunks
        in.seekg(at);
        const std::int32_t x = readLe32(in), y = readLe32(in);
        if (x < kMinTileSide || y < kMinTileSide)
          return "has OpenEXR tiles of " + std::to_string(x) + "x" + std::to_string(y) + " pixels, fewer than " +
                 std::to_string(kMinTileSide) + " a side";
      }
      in.seekg(at + bytes);
    }
    if (!multiPart || in.peek() == 0 || in.peek() == EOF) return "";
  }
}

}  // namespace marionette::prt
