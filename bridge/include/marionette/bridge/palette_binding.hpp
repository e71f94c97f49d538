// PaletteBinding: copies a character's TransformBuffer into an engine's bone
// palette, in the engine's order and layout. Which joint feeds which engine bone
// is resolved once, at bind time: by exact name, then through joint maps
// (rig/joint_map.hpp) where the two skeletons name joints differently. Each
// frame copies only the bound joints, straight into the caller's array (no
// intermediate copy); runs of consecutive joints going to consecutive slots were
// found at bind time and copy as one block.
#pragma once
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "marionette/rig/joint_map.hpp"
#include "marionette/scene/transform_buffer.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette::bridge {

enum class PaletteLayout {
  Mat4ColumnMajor,  // 16 floats per bone, columns one after the other (OpenGL, glm, Vulkan GLSL mat4)
  Mat4RowMajor,     // 16 floats per bone, rows one after the other (Direct3D row_major, Unreal FMatrix)
  Mat3x4RowMajor,   // 12 floats per bone: rows r0 r1 r2 of the affine part (bottom row 0 0 0 1 dropped),
                    // as Filament and many GPU skinning shaders take it
};

[[nodiscard]] constexpr std::size_t floatsPerBone(PaletteLayout layout) noexcept {
  return layout == PaletteLayout::Mat3x4RowMajor ? 12 : 16;
}

// What an engine's palette holds per bone.
struct PaletteFormat {
  PaletteLayout layout = PaletteLayout::Mat4ColumnMajor;
  // true: skinning matrices (model * inverseBind: what vertex skinning multiplies by);
  // false: model-space joint matrices (attachments, debug drawing, engines that
  // apply their own inverse bind).
  bool inverseBind = true;
};

// The engine's and the character's joint maps, for bones whose names differ. The
// engine map's joint indices are engine bone indices (slots), e.g. a map loaded
// for the engine's skeleton; the character map's are the character's joints.
struct BindMaps {
  const retarget::JointMap& engine;
  const retarget::JointMap& character;
};

// How the names were resolved, for the engine's log. Bones and joints by name.
struct BindReport {
  struct Mapped {
    std::string engineBone, canonical, joint;  // e.g. "mixamorig:Spine1", "spine[1]", "Torso"
  };
  std::vector<std::string> byName;          // engine bones that found a joint of the same name
  std::vector<Mapped> throughMaps;          // engine bones bound through the joint maps
  std::vector<std::string> unmatchedBones;  // engine bones without a joint: their slots get identity
  std::vector<std::string> unusedJoints;    // character joints no engine bone receives

  [[nodiscard]] bool complete() const noexcept { return unmatchedBones.empty(); }
  // One line per problem, naming the bones ("palette: engine bone 'X' has no joint ...");
  // empty when every bone was bound and every joint is used.
  [[nodiscard]] std::string format() const;
};

class PaletteBinding {
 public:
  PaletteBinding() = default;  // binds nothing (slotCount() == 0)
  // engineBones[i] is the engine's bone in palette slot i. Each is bound to the
  // character joint of the same name, else (with `maps`) to the character joint
  // the maps give for the bone's canonical joint: chains (spine, neck, fingers)
  // match joint k to joint k. Bones that find neither are reported and get identity.
  PaletteBinding(const Skeleton& character, std::span<const std::string> engineBones,
                 const BindMaps* maps = nullptr);
  // Identity mapping: palette slot i = joint i (an engine that took the character's skeleton).
  explicit PaletteBinding(const Skeleton& character);

  [[nodiscard]] std::size_t slotCount() const noexcept { return slotToJoint_.size(); }
  [[nodiscard]] std::size_t jointCount() const noexcept { return jointCount_; }
  [[nodiscard]] int jointForSlot(std::size_t slot) const noexcept { return slotToJoint_[slot]; }
  [[nodiscard]] const BindReport& report() const noexcept { return report_; }
  // Floats the engine's array needs for every slot.
  [[nodiscard]] std::size_t floatCount(PaletteLayout layout) const noexcept {
    return slotToJoint_.size() * floatsPerBone(layout);
  }

  // Writes every slot into `out` (at least floatCount(format.layout) floats; more
  // are left untouched): bound slots from the buffer, unmatched ones as identity. A buffer
  // that keeps no skinning matrices (TransformBuffer::setSkinningStored) has them made here,
  // bit for bit as stored ones.
  // Returns false, writing nothing, when `out` is too small or the buffer's joint
  // count is not the bound skeleton's. Per frame: no allocation, no exceptions.
  bool copy(const TransformBuffer& buffer, std::span<float> out, PaletteFormat format = {}) const noexcept;

 private:
  // `count` consecutive joints from `joint` to consecutive slots from `slot`;
  // joint -1: `count` unmatched slots.
  struct Run {
    int joint;
    std::size_t slot, count;
  };
  void buildRuns();
  // `count` matrices from `m` into `dst` in `layout`.
  static void copyRun(const glm::mat4* m, std::size_t count, PaletteLayout layout, float* dst) noexcept;

  std::vector<int> slotToJoint_;  // -1 = unmatched
  std::vector<Run> runs_;
  std::size_t jointCount_ = 0;
  BindReport report_;
};

}  // namespace marionette::bridge
