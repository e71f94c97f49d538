#include "marionette/animation/pose.hpp"

#include <algorithm>

namespace marionette {

glm::mat4 affineMultiply(const glm::mat4& a, const glm::mat4& b) noexcept {
  glm::mat4 r;
  for (int c = 0; c < 3; ++c)
    r[c] = glm::vec4(glm::vec3(a[0]) * b[c][0] + glm::vec3(a[1]) * b[c][1] + glm::vec3(a[2]) * b[c][2], 0.0f);
  r[3] = glm::vec4(glm::vec3(a[0]) * b[3][0] + glm::vec3(a[1]) * b[3][1] + glm::vec3(a[2]) * b[3][2] + glm::vec3(a[3]),
                   1.0f);
  return r;
}

void localToModel(const Skeleton& skeleton, std::span<const Transform> local, std::span<glm::mat4> model) noexcept {
  const std::size_t n = std::min({skeleton.jointCount(), local.size(), model.size()});
  const int* parents = skeleton.parents.data();
  for (std::size_t i = 0; i < n; ++i) {
    const glm::mat4 m = local[i].matrix();
    const int p = parents[i];
    model[i] = affineMultiply(p < 0 ? skeleton.rootTransform : model[p], m);
  }
}

void skinningPalette(std::span<const glm::mat4> model, std::span<const glm::mat4> inverseBind,
                     std::span<glm::mat4> palette) noexcept {
  const std::size_t n = std::min({model.size(), inverseBind.size(), palette.size()});
  for (std::size_t i = 0; i < n; ++i) palette[i] = affineMultiply(model[i], inverseBind[i]);
}

}  // namespace marionette
