#include "marionette/core/transform.hpp"

#include <algorithm>
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

namespace {
// The exact formula: extrapolation only (t outside [0, 1]).
glm::quat slerpExact(const glm::quat& a, const glm::quat& b, float d, float t) noexcept {
  if (d > 0.9995f) return nlerpShortest(a, b, t);  // sin(theta) ~ 0: nlerp is exact to first order
  const float theta = std::acos(d);
  const float s = std::sin(theta);
  const float wa = std::sin((1.0f - t) * theta) / s;
  const float wb = std::sin(t * theta) / s;
  return safeNormalize(glm::quat(wa * a.w + wb * b.w, wa * a.x + wb * b.x, wa * a.y + wb * b.y, wa * a.z + wb * b.z));
}
}  // namespace

glm::quat slerpShortest(const glm::quat& a, const glm::quat& b, float t) noexcept {
  float d = a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
  const float sign = d < 0.0f ? -1.0f : 1.0f;
  d = d * sign;
  const glm::quat bb(b.w * sign, b.x * sign, b.y * sign, b.z * sign);
  if (!(t >= 0.0f && t <= 1.0f)) {
    if (!std::isfinite(t)) return a;
    return slerpExact(a, bb, std::min(d, 1.0f), t);
  }
  // Within 90 degrees of rotation (cos of the arc at least cos 45 degrees), where the
  // series converges fast, it is used as it is. Beyond, the arc is halved at its exact
  // midpoint m (|a + b| = 2 cos(theta / 2) for unit inputs) and the half holding t taken.
  float c = std::min(d, 1.0f), u = t;
  glm::quat p = a, q = bb;
  if (c < slerp_series::kHalveBelow) {
    c = std::sqrt((1.0f + c) * 0.5f);
    const float h = 0.5f / c;
    const glm::quat m((a.w + bb.w) * h, (a.x + bb.x) * h, (a.y + bb.y) * h, (a.z + bb.z) * h);
    const bool low = t < 0.5f;
    p = low ? a : m;
    q = low ? m : bb;
    u = low ? t * 2.0f : t * 2.0f - 1.0f;
  }
  const float v = 1.0f - u;
  const float y = c - 1.0f, u2 = u * u, v2 = v * v;
  float ru = 1.0f, rv = 1.0f;
  for (int i = slerp_series::kTerms; i >= 1; --i) {
    ru = 1.0f + (u2 * slerp_series::kScale[i] - slerp_series::kOffset[i]) * y * ru;
    rv = 1.0f + (v2 * slerp_series::kScale[i] - slerp_series::kOffset[i]) * y * rv;
  }
  const float wp = v * rv, wq = u * ru;
  return safeNormalize(glm::quat(wp * p.w + wq * q.w, wp * p.x + wq * q.x, wp * p.y + wq * q.y, wp * p.z + wq * q.z));
}

}  // namespace marionette
