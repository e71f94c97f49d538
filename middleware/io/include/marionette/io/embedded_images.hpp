// Images stored inside a character's source file: the "embedded:N" base-colour
// textures (asset/asset.hpp). A writer copies them. An asset imported with meshes keeps
// them (Asset::embeddedImages, what a renderer reads); one imported without (a headless
// runtime never needs pixels) does not, and this reads them from its glTF / GLB / VRM file
// on first use.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "marionette/asset/asset.hpp"

namespace marionette {

class EmbeddedImages {
 public:
  explicit EmbeddedImages(std::string sourcePath);
  // The asset's kept images when it has them (it must outlive this), else its file's.
  explicit EmbeddedImages(const Asset& asset);
  ~EmbeddedImages();
  EmbeddedImages(const EmbeddedImages&) = delete;
  EmbeddedImages& operator=(const EmbeddedImages&) = delete;

  // The image index of an "embedded:N" reference, or -1 for anything else.
  [[nodiscard]] static int indexOf(std::string_view textureReference) noexcept;
  // The encoded bytes (PNG, JPEG, ...) of image `index`, or nullptr when neither the
  // asset nor its file (a glTF / GLB / VRM) has such an image. Reads the file once, on first use.
  [[nodiscard]] const std::vector<unsigned char>* find(int index);

 private:
  struct Loaded;
  std::string source_;
  bool tried_ = false;
  std::vector<std::vector<unsigned char>> images_;
  const std::vector<std::vector<unsigned char>>* kept_ = nullptr;
};

}  // namespace marionette
