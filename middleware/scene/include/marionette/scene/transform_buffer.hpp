// TransformBuffer: what one character hands the engine each frame.
//
// Layout (all arrays contiguous, joints in the skeleton's order, N = jointCount()):
//   skinning()    N * 16 floats  column-major 4x4 per joint: model * inverseBind (the bone palette)
//   model()       N * 16 floats  column-major 4x4 per joint: model-space joint matrix
//   skinning3x4() N * 12 floats  packed 3x4 per joint, row-major rows of (r0 r1 r2 t): the top
//                                three rows of skinning(); empty unless enabled (setPacked3x4)
//   morphWeights() M floats      in the character's morph-target order (Asset::morphTargets)
//   world()       16 floats      column-major 4x4: world-from-model of the character
//   frame()       counter        Scene::update calls that have written this buffer
// The spans stay valid (same addresses) until the skeleton changes; an engine may
// keep the pointers across frames. Reading needs no copy.
//
// A buffer may keep no skinning matrices (setSkinningStored(false), what the C API's
// characters do: 64 bytes a joint less): skinning() and skinningMatrices() are then empty,
// and skinningMatrices(first, out) makes them from the model matrices, bit for bit what
// would have been stored. PaletteBinding::copy does that as it copies.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "marionette/animation/pose.hpp"
#include "marionette/core/allocator.hpp"

namespace marionette {

class TransformBuffer {
 public:
  void resize(std::size_t joints, std::size_t morphs);
  void setPacked3x4(bool enabled);  // fills skinning3x4() from the next frame on
  // Whether skinning() holds the matrices (true, the default) or they are made on demand from
  // the model matrices, the inverse binds and their basis (kept by the caller: a Character's
  // rig; inverse binds for fewer joints than the buffer has leave them stored). Command time.
  void setSkinningStored(bool stored, std::span<const glm::mat4> inverseBind = {},
                         const PaletteBasis* basis = nullptr);
  [[nodiscard]] bool skinningStored() const noexcept { return skinningStored_; }
  // The skinning matrices of joints [first, first + out.size()), stored or made now. No
  // allocation; false (nothing written) past the joints.
  bool skinningMatrices(std::size_t first, std::span<glm::mat4> out) const noexcept;

  [[nodiscard]] std::span<const float> skinning() const noexcept { return floats(skinning_); }
  [[nodiscard]] std::span<const float> model() const noexcept { return floats(model_); }
  [[nodiscard]] std::span<const float> skinning3x4() const noexcept { return packed_; }
  [[nodiscard]] std::span<const float> morphWeights() const noexcept { return morphs_; }
  [[nodiscard]] const float* world() const noexcept { return &world_[0][0]; }
  [[nodiscard]] std::uint64_t frame() const noexcept { return frame_; }
  [[nodiscard]] std::size_t jointCount() const noexcept { return model_.size(); }
  [[nodiscard]] std::size_t morphCount() const noexcept { return morphs_.size(); }
  [[nodiscard]] bool packed3x4Enabled() const noexcept { return packedEnabled_; }

  // Typed views for C++ callers.
  [[nodiscard]] std::span<const glm::mat4> skinningMatrices() const noexcept { return skinning_; }
  [[nodiscard]] std::span<const glm::mat4> modelMatrices() const noexcept { return model_; }
  [[nodiscard]] const glm::mat4& worldMatrix() const noexcept { return world_; }

  // Writer side (the runtime). Not for engines.
  [[nodiscard]] std::span<glm::mat4> writeSkinning() noexcept { return skinning_; }
  [[nodiscard]] std::span<glm::mat4> writeModel() noexcept { return model_; }
  [[nodiscard]] std::span<float> writeMorphWeights() noexcept { return morphs_; }
  void setWorld(const glm::mat4& world) noexcept { world_ = world; }
  void finishFrame() noexcept;  // packs 3x4 when enabled, bumps the frame counter

  // FNV-1a over every array, for determinism tests.
  [[nodiscard]] std::uint64_t hash() const noexcept;

 private:
  static std::span<const float> floats(const RuntimeVector<glm::mat4>& m) noexcept {
    return {m.empty() ? nullptr : &m[0][0][0], m.size() * 16};
  }
  // Through the runtime allocator (core/allocator.hpp): an engine's heap holds them.
  RuntimeVector<glm::mat4> skinning_, model_;
  RuntimeVector<float> packed_, morphs_;
  glm::mat4 world_{1.0f};
  std::uint64_t frame_ = 0;
  bool packedEnabled_ = false;
  bool skinningStored_ = true;
  std::span<const glm::mat4> inverseBind_;  // when not stored: what skinningMatrices(first, out) multiplies by
  const PaletteBasis* basis_ = nullptr;
};

}  // namespace marionette
