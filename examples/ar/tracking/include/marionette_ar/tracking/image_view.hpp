// A frame handed to a tracker: 8-bit pixels the caller owns, viewed without a copy.
// Grey (1 channel), RGB (3, the background sources' frames) or RGBA (4); rows top to
// bottom, `stride` bytes apart (0: width * channels).
#pragma once
#include <cstddef>
#include <cstdint>

namespace marionette::ar {

struct ImageView {
  const std::uint8_t* pixels = nullptr;
  int width = 0;
  int height = 0;
  int channels = 1;
  std::ptrdiff_t stride = 0;

  [[nodiscard]] std::ptrdiff_t rowBytes() const noexcept {
    return stride != 0 ? stride : static_cast<std::ptrdiff_t>(width) * channels;
  }
  // False for a null buffer, a size below 1x1, a channel count other than 1, 3, 4, or a
  // stride shorter than a row.
  [[nodiscard]] bool valid() const noexcept {
    return pixels != nullptr && width > 0 && height > 0 && (channels == 1 || channels == 3 || channels == 4) &&
           rowBytes() >= static_cast<std::ptrdiff_t>(width) * channels;
  }
};

}  // namespace marionette::ar
