#include "marionette/io/embedded_images.hpp"

#include <tiny_gltf.h>

#include <charconv>
#include <cstring>

#include "file_extension.hpp"

namespace marionette {
namespace {

// Keeps the encoded bytes instead of decoding them (no image library needed here).
bool keepEncodedImage(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                      const unsigned char* bytes, int size, void*) {
  image->image.assign(bytes, bytes + size);
  return true;
}

}  // namespace

EmbeddedImages::EmbeddedImages(std::string sourcePath) : source_(std::move(sourcePath)) {}
EmbeddedImages::EmbeddedImages(const Asset& asset)
    : source_(asset.sourcePath), kept_(asset.embeddedImages.empty() ? nullptr : &asset.embeddedImages) {}
EmbeddedImages::~EmbeddedImages() = default;

int EmbeddedImages::indexOf(std::string_view reference) noexcept { return embeddedImageIndex(reference); }

const std::vector<unsigned char>* EmbeddedImages::find(int index) {
  if (kept_) {
    if (index < 0 || static_cast<std::size_t>(index) >= kept_->size() || (*kept_)[static_cast<std::size_t>(index)].empty())
      return nullptr;
    return &(*kept_)[static_cast<std::size_t>(index)];
  }
  if (!tried_) {
    tried_ = true;
    const std::string ext = detail::lowerExtension(source_);
    if (ext == ".gltf" || ext == ".glb" || ext == ".vrm") {
      tinygltf::TinyGLTF loader;
      loader.SetImageLoader(keepEncodedImage, nullptr);
      tinygltf::Model model;
      std::string err, warn;
      const bool ok = ext == ".gltf" ? loader.LoadASCIIFromFile(&model, &err, &warn, source_)
                                     : loader.LoadBinaryFromFile(&model, &err, &warn, source_);
      if (ok)
        for (tinygltf::Image& image : model.images) images_.push_back(std::move(image.image));
    }
  }
  if (index < 0 || static_cast<std::size_t>(index) >= images_.size() || images_[static_cast<std::size_t>(index)].empty())
    return nullptr;
  return &images_[static_cast<std::size_t>(index)];
}

}  // namespace marionette
