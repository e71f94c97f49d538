// Measuring joint rotations in the behavior tests: a joint's model-frame
// rotation from the transform buffer, and the angle between two rotations,
// accurate near zero (2 acos of a float dot is not: its smallest step is 7e-4 rad).
#pragma once
#include <cmath>

#include "marionette/scene/character.hpp"

namespace marionette::test {

inline glm::quat modelRotation(const Character& c, int joint) {
  glm::mat3 r(c.transformBuffer().modelMatrices()[static_cast<std::size_t>(joint)]);
  for (int i = 0; i < 3; ++i) r[i] = glm::normalize(r[i]);  // the root space may scale
  return glm::normalize(glm::quat_cast(r));
}

inline float preciseAngleBetween(const glm::quat& a, const glm::quat& b) {
  const glm::quat d = glm::inverse(a) * b;
  return 2.0f * std::atan2(glm::length(glm::vec3(d.x, d.y, d.z)), std::fabs(d.w));
}

}  // namespace marionette::test
