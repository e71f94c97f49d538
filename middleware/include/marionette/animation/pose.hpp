// From a local pose to model-space matrices and the skinning palette.
// Matrices are glm::mat4, column-major, 16 contiguous floats each.
#pragma once
#include <span>

#include "marionette/skeleton/skeleton.hpp"

namespace marionette {

// model[i] = model[parent(i)] * local[i]; roots use skeleton.rootTransform.
// All spans have the skeleton's joint count.
void localToModel(const Skeleton& skeleton, std::span<const Transform> local, std::span<glm::mat4> model) noexcept;

// palette[i] = model[i] * inverseBind[i].
void skinningPalette(std::span<const glm::mat4> model, std::span<const glm::mat4> inverseBind,
                     std::span<glm::mat4> palette) noexcept;

// Affine product of two matrices whose last row is (0,0,0,1): 36 multiplies
// instead of 64. Exact for the matrices the runtime makes.
[[nodiscard]] glm::mat4 affineMultiply(const glm::mat4& a, const glm::mat4& b) noexcept;

}  // namespace marionette
