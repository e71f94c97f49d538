#include "marionette/animation/pose.hpp"

#include <algorithm>

#include "simd4.hpp"
#include "simd_dispatch.hpp"

namespace marionette {

namespace {

#if MARIONETTE_SIMD4
// Local matrices are composed four joints at a time (structure of arrays), then each
// joint is multiplied by its parent's model matrix, which is already written (parents
// come first). The product takes each local element broadcast from memory: on SSE2 a
// load and a shuffle, with AVX a single broadcast load. With a palette,
// model * inverseBind follows while the model matrix is in registers, its factors read
// ready-broadcast from the PaletteBasis when there is one.
//
// Built three times from the same source (simd_dispatch.hpp): SSE2, AVX (its broadcasts
// are single loads; the same bits) and AVX2 + FMA (each column's multiply-adds fused:
// 12 % faster here, last-place differences), chosen by what the CPU has and setSimdPath
// (tests/animation/simd_pose_test.cpp holds the first two to the scalar bits).
inline __m128 productColumn(const simd4::Mat4& a, const float* b) noexcept {  // a * (b[0], b[4], b[8]) broadcast
  return _mm_add_ps(_mm_add_ps(_mm_mul_ps(a.c0, _mm_load1_ps(b)), _mm_mul_ps(a.c1, _mm_load1_ps(b + 4))),
                    _mm_mul_ps(a.c2, _mm_load1_ps(b + 8)));
}

inline __m128 splatColumn(const simd4::Mat4& a, const float* b) noexcept {  // b: three splatted factors
  return _mm_add_ps(_mm_add_ps(_mm_mul_ps(a.c0, _mm_loadu_ps(b)), _mm_mul_ps(a.c1, _mm_loadu_ps(b + 4))),
                    _mm_mul_ps(a.c2, _mm_loadu_ps(b + 8)));
}

// What one call of localToModel4 works on.
struct LocalToModelArgs {
  const Skeleton& skeleton;
  std::span<const Transform> local;
  std::span<glm::mat4> model;
  std::span<const glm::mat4> inverseBind;
  const PaletteBasis* basis;
  std::span<glm::mat4> palette;
};

[[gnu::always_inline]] inline void localToModel4Body(const LocalToModelArgs& args) noexcept {
  const auto& [skeleton, local, model, inverseBind, basis, palette] = args;
  const std::size_t n = std::min({skeleton.jointCount(), local.size(), model.size()});
  const std::size_t withPalette = std::min({n, inverseBind.size(), palette.size()});
  const bool splat = basis && basis->joints() >= withPalette && withPalette > 0;
  const int* parents = skeleton.parents.data();
  const simd4::Mat4 root = simd4::loadMat(skeleton.rootTransform);
  simd4::Mat4 previous = root;
  alignas(16) float elements[12][4];  // [element][joint of the group]: columns 0..3, rows 0..2
  for (std::size_t j0 = 0; j0 < n; j0 += 4) {
    const std::size_t count = std::min<std::size_t>(4, n - j0);
    if (count == 4) {
      simd4::composeElements4(simd4::load4(&local[j0]), elements);
    } else {  // the last joints, padded with identities
      Transform tail[4];
      std::copy_n(&local[j0], count, tail);
      simd4::composeElements4(simd4::load4(tail), elements);
    }
    for (std::size_t k = 0; k < count; ++k) {
      const std::size_t j = j0 + k;
      const int p = parents[j];
      // A chain's next joint takes its parent from registers, not back through the store.
      const simd4::Mat4& a =
          p < 0 ? root : (static_cast<std::size_t>(p) + 1 == j ? previous : simd4::loadMat(model[static_cast<std::size_t>(p)]));
      const float* e = &elements[0][k];
      const simd4::Mat4 m{productColumn(a, e), productColumn(a, e + 12), productColumn(a, e + 24),
                          _mm_add_ps(productColumn(a, e + 36), a.c3)};
      previous = m;
      simd4::storeMat(m, model[j]);
      if (j >= withPalette) continue;
      if (splat) {
        const float* b = basis->splat.data() + j * 48;
        simd4::storeMat({splatColumn(m, b), splatColumn(m, b + 12), splatColumn(m, b + 24),
                         _mm_add_ps(splatColumn(m, b + 36), m.c3)},
                        palette[j]);
      } else {
        simd4::storeMat(simd4::affineMultiply(m, simd4::loadMat(inverseBind[j])), palette[j]);
      }
    }
  }
}

MARIONETTE_SIMD_KERNEL(localToModel4, LocalToModelArgs, localToModel4Body)

// The palette half of localToModel4Body on stored model matrices: the same operations on the
// same values (a model matrix is stored from the register it was made in), so the same bits.
struct PaletteFromModelArgs {
  std::span<const glm::mat4> model;
  std::span<const glm::mat4> inverseBind;
  const PaletteBasis* basis;
  std::size_t first;
  std::span<glm::mat4> out;
};

[[gnu::always_inline]] inline void paletteFromModel4Body(const PaletteFromModelArgs& args) noexcept {
  const auto& [model, inverseBind, basis, first, out] = args;
  const bool splat = basis && basis->joints() >= first + out.size();
  for (std::size_t k = 0; k < out.size(); ++k) {
    const std::size_t j = first + k;
    const simd4::Mat4 m = simd4::loadMat(model[j]);
    if (splat) {
      const float* b = basis->splat.data() + j * 48;
      simd4::storeMat({splatColumn(m, b), splatColumn(m, b + 12), splatColumn(m, b + 24),
                       _mm_add_ps(splatColumn(m, b + 36), m.c3)},
                      out[k]);
    } else {
      simd4::storeMat(simd4::affineMultiply(m, simd4::loadMat(inverseBind[j])), out[k]);
    }
  }
}

MARIONETTE_SIMD_KERNEL(paletteFromModel4, PaletteFromModelArgs, paletteFromModel4Body)
#endif

}  // namespace

void localToModel(const Skeleton& skeleton, std::span<const Transform> local, std::span<glm::mat4> model) noexcept {
#if MARIONETTE_SIMD4
  localToModel4({skeleton, local, model, {}, nullptr, {}});
#else
  localToModelScalar(skeleton, local, model);
#endif
}

void localToModelScalar(const Skeleton& skeleton, std::span<const Transform> local, std::span<glm::mat4> model) noexcept {
  const std::size_t n = std::min({skeleton.jointCount(), local.size(), model.size()});
  const int* parents = skeleton.parents.data();
  for (std::size_t i = 0; i < n; ++i) {
    const glm::mat4 m = local[i].matrix();
    const int p = parents[i];
    model[i] = affineMultiply(p < 0 ? skeleton.rootTransform : model[p], m);
  }
}

PaletteBasis PaletteBasis::of(std::span<const glm::mat4> inverseBind) {
  PaletteBasis b;
  b.splat.resize(inverseBind.size() * 48);
  for (std::size_t j = 0; j < inverseBind.size(); ++j)
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 3; ++r)
        for (int lane = 0; lane < 4; ++lane) b.splat[j * 48 + static_cast<std::size_t>((c * 3 + r) * 4 + lane)] = inverseBind[j][c][r];
  return b;
}

void localToModelAndPalette(const Skeleton& skeleton, std::span<const Transform> local, std::span<glm::mat4> model,
                            std::span<glm::mat4> palette, const PaletteBasis* basis) noexcept {
#if MARIONETTE_SIMD4
  localToModel4({skeleton, local, model, skeleton.inverseBind, basis, palette});
#else
  (void)basis;
  localToModelScalar(skeleton, local, model);
  skinningPalette(model.first(std::min({skeleton.jointCount(), local.size(), model.size()})), skeleton.inverseBind, palette);
#endif
}

void paletteFromModel(std::span<const glm::mat4> model, std::span<const glm::mat4> inverseBind,
                      const PaletteBasis* basis, std::size_t first, std::span<glm::mat4> out) noexcept {
  if (first > model.size() || first > inverseBind.size()) return;
  out = out.first(std::min({out.size(), model.size() - first, inverseBind.size() - first}));
#if MARIONETTE_SIMD4
  paletteFromModel4({model, inverseBind, basis, first, out});
#else
  (void)basis;
  for (std::size_t k = 0; k < out.size(); ++k) out[k] = affineMultiply(model[first + k], inverseBind[first + k]);
#endif
}

glm::mat4 modelMatrixOf(const Skeleton& skeleton, std::span<const Transform> local, int joint) noexcept {
  if (joint < 0 || static_cast<std::size_t>(joint) >= std::min(skeleton.jointCount(), local.size()))
    return skeleton.rootTransform;
  // Parents come before children, so the chain up is at most `joint` long; compose from the top.
  glm::mat4 m(1.0f);
  for (int j = joint; j >= 0; j = skeleton.parents[static_cast<std::size_t>(j)])
    m = affineMultiply(local[static_cast<std::size_t>(j)].matrix(), m);
  return affineMultiply(skeleton.rootTransform, m);
}

glm::quat modelRotationOf(const Skeleton& skeleton, std::span<const Transform> local, int joint) noexcept {
  glm::mat3 root(skeleton.rootTransform);
  for (int c = 0; c < 3; ++c) root[c] = glm::length(root[c]) > 0.0f ? glm::normalize(root[c]) : root[c];
  int chain[256];
  int n = 0;
  const std::size_t joints = std::min(skeleton.jointCount(), local.size());
  for (int p = joint; p >= 0 && static_cast<std::size_t>(p) < joints && n < 256; p = skeleton.parents[static_cast<std::size_t>(p)])
    chain[n++] = p;
  glm::quat q = glm::quat_cast(root);
  for (int i = n - 1; i >= 0; --i) q = q * local[static_cast<std::size_t>(chain[i])].rotation;
  return q;
}

void skinningPalette(std::span<const glm::mat4> model, std::span<const glm::mat4> inverseBind,
                     std::span<glm::mat4> palette) noexcept {
  const std::size_t n = std::min({model.size(), inverseBind.size(), palette.size()});
#if MARIONETTE_SIMD4
  for (std::size_t i = 0; i < n; ++i)
    simd4::storeMat(simd4::affineMultiply(simd4::loadMat(model[i]), simd4::loadMat(inverseBind[i])), palette[i]);
#else
  for (std::size_t i = 0; i < n; ++i) palette[i] = affineMultiply(model[i], inverseBind[i]);
#endif
}

}  // namespace marionette
