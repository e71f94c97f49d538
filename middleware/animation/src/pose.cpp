#include "marionette/animation/pose.hpp"

#include <algorithm>

namespace marionette {

void localToModel(const Skeleton& skeleton, std::span<const Transform> local, std::span<glm::mat4> model) noexcept {
  const std::size_t n = std::min({skeleton.jointCount(), local.size(), model.size()});
  const int* parents = skeleton.parents.data();
  for (std::size_t i = 0; i < n; ++i) {
    const glm::mat4 m = local[i].matrix();
    const int p = parents[i];
    model[i] = affineMultiply(p < 0 ? skeleton.rootTransform : model[p], m);
  }
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

void skinningPalette(std::span<const glm::mat4> model, std::span<const glm::mat4> inverseBind,
                     std::span<glm::mat4> palette) noexcept {
  const std::size_t n = std::min({model.size(), inverseBind.size(), palette.size()});
  for (std::size_t i = 0; i < n; ++i) palette[i] = affineMultiply(model[i], inverseBind[i]);
}

}  // namespace marionette
