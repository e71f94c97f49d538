#include "marionette/animation/clip_error.hpp"

#include <algorithm>
#include <cmath>

namespace marionette {

namespace {
glm::vec3 axis(const glm::mat4& m, int c) {
  const glm::vec3 v(m[c]);
  const float len = glm::length(v);
  return len > 0.0f ? v / len : v;
}
}  // namespace

float virtualVertexError(std::span<const glm::mat4> a, std::span<const glm::mat4> b, float distance,
                         std::span<float> perJoint) noexcept {
  const std::size_t n = std::min(a.size(), b.size());
  float worst = 0.0f;
  for (std::size_t j = 0; j < n; ++j) {
    const glm::vec3 ta(a[j][3]), tb(b[j][3]);
    float e = glm::length(ta - tb);
    for (int c = 0; c < 3; ++c) {
      const glm::vec3 d = (axis(a[j], c) - axis(b[j], c)) * distance;
      e = std::max({e, glm::length(ta - tb + d), glm::length(ta - tb - d)});
    }
    if (!(e == e)) e = INFINITY;  // a NaN pose is as wrong as it gets
    if (j < perJoint.size()) perJoint[j] = e;
    worst = std::max(worst, e);
  }
  return worst;
}

}  // namespace marionette
