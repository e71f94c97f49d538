#include "marionette/scene/transform_buffer.hpp"

#include <cstring>

namespace marionette {

void TransformBuffer::resize(std::size_t joints, std::size_t morphs) {
  skinning_.assign(joints, glm::mat4(1.0f));
  model_.assign(joints, glm::mat4(1.0f));
  morphs_.assign(morphs, 0.0f);
  packed_.assign(packedEnabled_ ? joints * 12 : 0, 0.0f);
}

void TransformBuffer::setPacked3x4(bool enabled) {
  packedEnabled_ = enabled;
  packed_.assign(enabled ? model_.size() * 12 : 0, 0.0f);
}

void TransformBuffer::finishFrame() noexcept {
  if (packedEnabled_) {
    float* out = packed_.data();
    for (const glm::mat4& m : skinning_) {
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
