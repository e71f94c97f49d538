#include "exr_header_check.hpp"

#include <cstdint>
#include <filesystem>
#include <fstream>
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
      unsigned char size[4];
      if (t == Text::End || !in.read(reinterpret_cast<char*>(size), 4)) return "";
      const std::int32_t bytes = static_cast<std::int32_t>(std::uint32_t(size[0]) | std::uint32_t(size[1]) << 8 |
                                                           std::uint32_t(size[2]) << 16 | std::uint32_t(size[3]) << 24);
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
        unsigned char wh[8];
        if (!in.read(reinterpret_cast<char*>(wh), 8)) return "";
        auto u32 = [&](int k) { return std::uint64_t(wh[k]) | std::uint64_t(wh[k + 1]) << 8 | std::uint64_t(wh[k + 2]) << 16 | std::uint64_t(wh[k + 3]) << 24; };
        content = static_cast<std::int64_t>(8 + u32(0) * u32(4) * 4);
      }
      if (!in || content != bytes)
        return damaged + "declares " + std::to_string(bytes) + " bytes but holds " +
               (in ? std::to_string(content) : std::string("more than the file has"));
      in.seekg(at + bytes);
    }
    if (!multiPart || in.peek() == 0 || in.peek() == EOF) return "";
  }
}

}  // namespace marionette::prt
