// Images stored inside a character's source file: the "embedded:N" base-colour
// textures of a glTF / GLB / VRM (io/asset.hpp). A renderer decodes them, a
// writer copies them; both need the encoded bytes, which the importer does not
// keep (a headless runtime never needs pixels).
#pragma once
#include <string>
#include <string_view>
#include <vector>

namespace marionette {

class EmbeddedImages {
 public:
  explicit EmbeddedImages(std::string sourcePath);
  ~EmbeddedImages();
  EmbeddedImages(const EmbeddedImages&) = delete;
  EmbeddedImages& operator=(const EmbeddedImages&) = delete;

  // The image index of an "embedded:N" reference, or -1 for anything else.
  [[nodiscard]] static int indexOf(std::string_view textureReference) noexcept;
  // The encoded bytes (PNG, JPEG, ...) of image `index`, or nullptr when the file
  // has no such image or is not a glTF / GLB / VRM. Reads the file once, on first use.
  [[nodiscard]] const std::vector<unsigned char>* find(int index);

 private:
  struct Loaded;
  std::string source_;
  bool tried_ = false;
  std::vector<std::vector<unsigned char>> images_;
};

}  // namespace marionette
