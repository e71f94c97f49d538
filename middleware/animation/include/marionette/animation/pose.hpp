// From a local pose to model-space matrices and the skinning palette.
// Matrices are glm::mat4, column-major, 16 contiguous floats each.
//
// Span contract (all of animation/: pose, sampling, blending): the per-frame functions
// clamp, they do not validate. Spans should have the skeleton's joint count. When they
// differ, the output is written for the joints its required inputs also have (the
// shortest of them) and left untouched past that; an optional input that is shorter (a
// blend layer's pose, a joint mask) contributes nothing to the joints it lacks (a
// non-empty mask counts as weight 0 there; an empty one as 1 everywhere). Nothing reads or
// writes past a span, fails or allocates: per-frame code has no error channel, and a
// caller that wants a check compares the sizes once when it binds, as Character does.
// tests/animation/span_contract_test.cpp holds each function to this.
#pragma once
#include <span>
#include <vector>

#include "marionette/skeleton/skeleton.hpp"

namespace marionette {

// model[i] = model[parent(i)] * local[i]; roots use skeleton.rootTransform.
// Joints 0 .. min(joints, local, model) - 1 (the span contract above).
// On x86-64 the local matrices are built four joints at a time with SSE2 (the baseline
// of every x86-64 CPU); the result is bit-identical to localToModelScalar, which is the
// definition and what other targets run, except on the FMA build (SimdPath, below).
void localToModel(const Skeleton& skeleton, std::span<const Transform> local, std::span<glm::mat4> model) noexcept;
void localToModelScalar(const Skeleton& skeleton, std::span<const Transform> local, std::span<glm::mat4> model) noexcept;

// localToModel, then palette[i] = model[i] * skeleton.inverseBind[i] in the same pass
// while the model matrix is in registers: what a character does every frame. The same
// bits as the two calls (but for the FMA build); the palette is written for i below the shortest of the model
// joints, inverseBind and palette.
//
// With a PaletteBasis of the skeleton's inverse binds (a Rig keeps one), the palette
// product reads its factors ready-broadcast instead of shuffling them out of the
// matrices, which is most of its cost on SSE2; the bits are the same either way.
// The 4-wide code is built for SSE2 (the x86-64 baseline), AVX and AVX2 + FMA; each
// process runs the fastest its CPU has (SimdPath::Auto). What is promised:
// - Baseline (SSE2) and Portable (AVX where the CPU has it, else SSE2) give the same
//   bits as the scalar definitions on every x86-64 CPU: for lockstep simulations.
// - Auto on an AVX2 + FMA CPU fuses multiply-adds (one rounding instead of two): the
//   results differ from Portable's in the last places (within 2e-6 of them, relative,
//   in tests/animation/simd_pose_test.cpp) and are the same run after run on one machine.
enum class SimdPath { Auto, Baseline, Portable };
void setSimdPath(SimdPath path) noexcept;  // for the whole process; Auto by default
// "avx2+fma", "avx", "sse2" or "scalar" (no SSE2: other CPUs)
[[nodiscard]] const char* activeSimdPath() noexcept;

struct PaletteBasis {
  // Per joint, the 12 elements of the inverse bind's first three rows (column-major),
  // each repeated 4 times: 192 bytes a joint, shared by every character of a rig.
  std::vector<float> splat;
  [[nodiscard]] static PaletteBasis of(std::span<const glm::mat4> inverseBind);
  [[nodiscard]] std::size_t joints() const noexcept { return splat.size() / 48; }
};
void localToModelAndPalette(const Skeleton& skeleton, std::span<const Transform> local, std::span<glm::mat4> model,
                            std::span<glm::mat4> palette, const PaletteBasis* basis = nullptr) noexcept;
// The palette of joints [first, first + out.size()) from model matrices that
// localToModelAndPalette stored: bit for bit the palette it would have stored with the same
// inverse binds and basis (for buffers that keep no palette and make it as it is copied).
void paletteFromModel(std::span<const glm::mat4> model, std::span<const glm::mat4> inverseBind,
                      const PaletteBasis* basis, std::size_t first, std::span<glm::mat4> out) noexcept;

// Model-space matrix of one joint, walking up its ancestors (no allocation): for
// controllers that need a few joints mid-frame, before the full localToModel.
[[nodiscard]] glm::mat4 modelMatrixOf(const Skeleton& skeleton, std::span<const Transform> local, int joint) noexcept;

// Model-space rotation of one joint: the root transform's rotation (its scale removed)
// times the local rotations down the chain. Scale along the chain is ignored, which is
// what aiming controllers (gaze, saccades) want. A joint < 0 gives the root's rotation.
[[nodiscard]] glm::quat modelRotationOf(const Skeleton& skeleton, std::span<const Transform> local, int joint) noexcept;

// palette[i] = model[i] * inverseBind[i], for i below the shortest span's length.
void skinningPalette(std::span<const glm::mat4> model, std::span<const glm::mat4> inverseBind,
                     std::span<glm::mat4> palette) noexcept;

// Affine product of two matrices whose last row is (0,0,0,1): 36 multiplies
// instead of 64, in 4-wide column operations the compiler vectorizes. Exact for
// the matrices the runtime makes. Inline: it runs twice per joint per frame.
[[nodiscard]] inline glm::mat4 affineMultiply(const glm::mat4& a, const glm::mat4& b) noexcept {
  glm::mat4 r;
  for (int c = 0; c < 3; ++c) r[c] = a[0] * b[c][0] + a[1] * b[c][1] + a[2] * b[c][2];
  r[3] = a[0] * b[3][0] + a[1] * b[3][1] + a[2] * b[3][2] + a[3];
  // a's columns 0..2 end in 0 and column 3 in 1, so the last row is (0,0,0,1) already.
  return r;
}

}  // namespace marionette
