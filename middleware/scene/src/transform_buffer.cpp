#include "marionette/scene/transform_buffer.hpp"

#include <algorithm>
#include <cstring>

namespace marionette {

void TransformBuffer::resize(std::size_t joints, std::size_t morphs) {
  skinning_.assign(skinningStored_ ? joints : 0, glm::mat4(1.0f));
  model_.assign(joints, glm::mat4(1.0f));
  morphs_.assign(morphs, 0.0f);
  packed_.assign(packedEnabled_ ? joints * 12 : 0, 0.0f);
}

void TransformBuffer::setPacked3x4(bool enabled) {
  packedEnabled_ = enabled;
  packed_.assign(enabled ? model_.size() * 12 : 0, 0.0f);
}

void TransformBuffer::setSkinningStored(bool stored, std::span<const glm::mat4> inverseBind, const PaletteBasis* basis) {
  if (!stored && inverseBind.size() < model_.size()) return;  // nothing to make them from: they stay stored
  skinningStored_ = stored;
  inverseBind_ = stored ? std::span<const glm::mat4>() : inverseBind;
  basis_ = stored ? nullptr : basis;
  if (stored)
    skinning_.assign(model_.size(), glm::mat4(1.0f));
  else
    RuntimeVector<glm::mat4>().swap(skinning_);  // the memory goes, not only the size
}

bool TransformBuffer::skinningMatrices(std::size_t first, std::span<glm::mat4> out) const noexcept {
  if (first > model_.size() || out.size() > model_.size() - first) return false;
  if (skinningStored_) {
    std::copy_n(skinning_.begin() + static_cast<std::ptrdiff_t>(first), out.size(), out.begin());
    return true;
  }
  if (inverseBind_.size() < model_.size()) return false;  // not made for this skeleton (resized since)
  paletteFromModel(model_, inverseBind_, basis_, first, out);
  return true;
}

void TransformBuffer::finishFrame() noexcept {
  if (packedEnabled_) {
    float* out = packed_.data();
    for (std::size_t j = 0; j < model_.size(); ++j) {
      glm::mat4 made;
      const glm::mat4& m = skinningStored_ ? skinning_[j] : (skinningMatrices(j, {&made, 1}), made);
      for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 4; ++col) *out++ = m[col][row];
    }
  }
  ++frame_;
}

namespace {
std::uint64_t fnv(std::uint64_t h, const void* data, std::size_t bytes) noexcept {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < bytes; ++i) {
    h ^= p[i];
    h *= 1099511628211ull;
  }
  return h;
}
}  // namespace

std::uint64_t TransformBuffer::hash() const noexcept {
  std::uint64_t h = 1469598103934665603ull;
  h = fnv(h, skinning_.data(), skinning_.size() * sizeof(glm::mat4));
  h = fnv(h, model_.data(), model_.size() * sizeof(glm::mat4));
  h = fnv(h, morphs_.data(), morphs_.size() * sizeof(float));
  h = fnv(h, &world_, sizeof(world_));
  return h;
}

}  // namespace marionette
