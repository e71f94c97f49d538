// 8-bit images in memory, read and written through OpenImageIO: textures,
// camera frames, the PNG frames the renderer writes. Row 0 is the top row.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "marionette/core/diagnostic.hpp"

namespace marionette::ar {

struct Image8 {
  int width = 0, height = 0, channels = 0;  // channels 3 (RGB) or 4 (RGBA)
  std::vector<std::uint8_t> pixels;         // width * height * channels, row-major
  [[nodiscard]] bool empty() const noexcept { return pixels.empty(); }
};

// Reads any format OpenImageIO knows, converted to 8-bit RGBA. False with an error in
// `diagnostics` naming the file.
[[nodiscard]] bool readImage(const std::string& path, Image8& out, Diagnostics& diagnostics);
// The same from encoded bytes in memory (textures inside a glTF); `name` is the diagnostics' file.
[[nodiscard]] bool readImage(std::span<const unsigned char> bytes, const std::string& name, Image8& out,
                             Diagnostics& diagnostics);
// Writes PNG (or any format the extension names). False with an error in `diagnostics` naming the file.
[[nodiscard]] bool writeImage(const std::string& path, const Image8& image, Diagnostics& diagnostics);

}  // namespace marionette::ar
