// slerp by acos and sin in float, as slerpShortest computed it before its series
// (core/transform.cpp): the "before" of the slerp figures in docs/accuracy.md and
// docs/benchmarks.md (Stage/BlendOverAcos).
#pragma once
#include <cmath>

#include "marionette/core/transform.hpp"

namespace marionette::test {

inline glm::quat slerpAcos(const glm::quat& a, const glm::quat& b, float t) {
  float d = a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
  const glm::quat bb = d < 0.0f ? -b : b;
  d = std::abs(d);
  if (d > 0.9995f) return nlerpShortest(a, bb, t);  // sin(theta) ~ 0: nlerp
  const float theta = std::acos(d), s = std::sin(theta);
  const float wa = std::sin((1.0f - t) * theta) / s, wb = std::sin(t * theta) / s;
  return safeNormalize(glm::quat(wa * a.w + wb * bb.w, wa * a.x + wb * bb.x, wa * a.y + wb * bb.y, wa * a.z + wb * bb.z));
}

}  // namespace marionette::test
