#include "marionette/animation/pose.hpp"

#include <algorithm>

#include "simd4.hpp"

namespace marionette {

namespace {

#if MARIONETTE_SIMD4
// Local matrices are composed four joints at a time (structure of arrays), then each
// joint is multiplied by its parent's model matrix, which is already written (parents
// come first). With a palette, model * inverseBind follows while the model matrix is
// still in registers.
void localToModel4(const Skeleton& skeleton, std::span<const Transform> local, std::span<glm::mat4> model,
                   std::span<const glm::mat4> inverseBind, std::span<glm::mat4> palette) noexcept {
  const std::size_t n = std::min({skeleton.jointCount(), local.size(), model.size()});
  const std::size_t withPalette = std::min({n, inverseBind.size(), palette.size()});
  const int* parents = skeleton.parents.data();
  const simd4::Mat4 root = simd4::loadMat(skeleton.rootTransform);
  simd4::Mat4 locals[4], previous = root;
  for (std::size_t j0 = 0; j0 < n; j0 += 4) {
    const std::size_t count = std::min<std::size_t>(4, n - j0);
    if (count == 4) {
      simd4::composeMatrices4(simd4::load4(&local[j0]), locals);
    } else {  // the last joints, padded with identities
      Transform tail[4];
      std::copy_n(&local[j0], count, tail);
      simd4::composeMatrices4(simd4::load4(tail), locals);
    }
    for (std::size_t k = 0; k < count; ++k) {
      const std::size_t j = j0 + k;
      const int p = parents[j];
      // A chain's next joint takes its parent from registers, not back through the store.
      const simd4::Mat4& parent =
          p < 0 ? root : (static_cast<std::size_t>(p) + 1 == j ? previous : simd4::loadMat(model[static_cast<std::size_t>(p)]));
      const simd4::Mat4 m = simd4::affineMultiply(parent, locals[k]);
      previous = m;
      simd4::storeMat(m, model[j]);
      if (j < withPalette) simd4::storeMat(simd4::affineMultiply(m, simd4::loadMat(inverseBind[j])), palette[j]);
    }
  }
}
#endif

}  // namespace

void localToModel(const Skeleton& skeleton, std::span<const Transform> local, std::span<glm::mat4> model) noexcept {
#if MARIONETTE_SIMD4
  localToModel4(skeleton, local, model, {}, {});
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

void localToModelAndPalette(const Skeleton& skeleton, std::span<const Transform> local, std::span<glm::mat4> model,
                            std::span<glm::mat4> palette) noexcept {
#if MARIONETTE_SIMD4
  localToModel4(skeleton, local, model, skeleton.inverseBind, palette);
#else
  localToModelScalar(skeleton, local, model);
  skinningPalette(model.first(std::min({skeleton.jointCount(), local.size(), model.size()})), skeleton.inverseBind, palette);
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
