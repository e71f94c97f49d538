#include "marionette/bridge/palette_binding.hpp"

#include <cstring>

namespace marionette::bridge {

PaletteBinding::PaletteBinding(const Skeleton& skeleton, std::span<const std::string> engineBones)
    : jointCount_(skeleton.jointCount()) {
  slotToJoint_.reserve(engineBones.size());
  for (const std::string& name : engineBones) {
    const int j = skeleton.findJoint(name);
    slotToJoint_.push_back(j);
    if (j < 0) unmapped_.push_back(name);
  }
}

PaletteBinding::PaletteBinding(const Skeleton& skeleton) : jointCount_(skeleton.jointCount()) {
  slotToJoint_.resize(skeleton.jointCount());
  for (std::size_t i = 0; i < slotToJoint_.size(); ++i) slotToJoint_[i] = static_cast<int>(i);
}

bool PaletteBinding::copy(const TransformBuffer& buffer, std::span<float> out, PaletteLayout layout) const noexcept {
  const std::size_t per = floatsPerSlot(layout);
  if (out.size() < slotToJoint_.size() * per || buffer.jointCount() != jointCount_) return false;
  const std::span<const glm::mat4> palette = buffer.skinningMatrices();
  float* dst = out.data();
  for (std::size_t slot = 0; slot < slotToJoint_.size(); ++slot, dst += per) {
    const int j = slotToJoint_[slot];
    if (j < 0) continue;
    const glm::mat4& m = palette[j];
    if (layout == PaletteLayout::Mat4ColumnMajor) {
      std::memcpy(dst, &m[0][0], 16 * sizeof(float));
    } else {
      for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 4; ++col) dst[row * 4 + col] = m[col][row];
    }
  }
  return true;
}

void PaletteBinding::clearUnmapped(std::span<float> out, PaletteLayout layout) const noexcept {
  const std::size_t per = floatsPerSlot(layout);
  if (out.size() < slotToJoint_.size() * per) return;
  for (std::size_t slot = 0; slot < slotToJoint_.size(); ++slot) {
    if (slotToJoint_[slot] >= 0) continue;
    float* dst = out.data() + slot * per;
    std::memset(dst, 0, per * sizeof(float));
    if (layout == PaletteLayout::Mat4ColumnMajor) dst[0] = dst[5] = dst[10] = dst[15] = 1.0f;
    else dst[0] = dst[5] = dst[10] = 1.0f;
  }
}

}  // namespace marionette::bridge
