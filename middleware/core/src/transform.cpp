#include "marionette/core/transform.hpp"

#include <cmath>

namespace marionette {

Transform decompose(const glm::mat4& m) noexcept {
  Transform t;
  t.translation = glm::vec3(m[3]);
  glm::vec3 c0(m[0]), c1(m[1]), c2(m[2]);
  float sx = glm::length(c0), sy = glm::length(c1), sz = glm::length(c2);
  if (glm::determinant(glm::mat3(c0, c1, c2)) < 0.0f) sx = -sx;  // mirrored
  t.scale = {sx, sy, sz};
  glm::mat3 r(sx != 0.0f ? c0 / sx : glm::vec3(1, 0, 0), sy != 0.0f ? c1 / sy : glm::vec3(0, 1, 0),
              sz != 0.0f ? c2 / sz : glm::vec3(0, 0, 1));
  t.rotation = safeNormalize(glm::quat_cast(r));
  return t;
}

glm::quat slerpShortest(const glm::quat& a, const glm::quat& b, float t) noexcept {
  float d = a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
  glm::quat bb = b;
  if (d < 0.0f) {
    d = -d;
    bb = -b;
  }
  // Close inputs: sin(theta) ~ 0 loses precision, nlerp is exact to first order there.
  if (d > 0.9995f) return nlerpShortest(a, bb, t);
  float theta = std::acos(d);
  float s = std::sin(theta);
  float wa = std::sin((1.0f - t) * theta) / s;
  float wb = std::sin(t * theta) / s;
  return safeNormalize(glm::quat(wa * a.w + wb * bb.w, wa * a.x + wb * bb.x, wa * a.y + wb * bb.y,
                                 wa * a.z + wb * bb.z));
}

}  // namespace marionette
