// PaletteBinding: copies a character's TransformBuffer into an engine's bone
// palette. The mapping from engine bones to skeleton joints is resolved once,
// by name, at bind time; each frame copies only the mapped joints (the writer
// idea of ACL: write straight into the caller's layout, no intermediate copy).
#pragma once
#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "marionette/scene/transform_buffer.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette::bridge {

enum class PaletteLayout {
  Mat4ColumnMajor,  // 16 floats per bone (OpenGL / glm)
  Mat3x4RowMajor,   // 12 floats per bone: rows (r0 r1 r2 t), as Filament and many GPU skinning shaders take it
};

class PaletteBinding {
 public:
  // engineBones[i] names the joint that goes to engine palette slot i. Names the
  // skeleton lacks stay unmapped (identity in the palette); `unmapped()` lists them.
  PaletteBinding(const Skeleton& skeleton, std::span<const std::string> engineBones);
  // Identity mapping: palette slot i = joint i.
  explicit PaletteBinding(const Skeleton& skeleton);

  [[nodiscard]] std::size_t slotCount() const noexcept { return slotToJoint_.size(); }
  [[nodiscard]] const std::vector<std::string>& unmapped() const noexcept { return unmapped_; }
  [[nodiscard]] std::size_t floatsPerSlot(PaletteLayout layout) const noexcept {
    return layout == PaletteLayout::Mat4ColumnMajor ? 16 : 12;
  }

  // Writes slotCount() matrices into `out` (slotCount() * floatsPerSlot floats).
  // Returns false, writing nothing, when `out` is too small or the buffer's joint
  // count differs from the bound skeleton. No allocation, no exceptions.
  bool copy(const TransformBuffer& buffer, std::span<float> out, PaletteLayout layout) const noexcept;
  // Fills unmapped slots with identity once (copy() leaves them untouched).
  void clearUnmapped(std::span<float> out, PaletteLayout layout) const noexcept;

 private:
  std::vector<int> slotToJoint_;  // -1 = unmapped
  std::vector<std::string> unmapped_;
  std::size_t jointCount_ = 0;
};

}  // namespace marionette::bridge
