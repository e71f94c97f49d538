#include "marionette_ar/contact_shadow.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

namespace marionette::ar {

namespace {

constexpr float kPi = 3.14159265358979f;
constexpr float kY00 = 0.282095f;     // Y_0
constexpr float kY1 = 0.488603f;      // Y_1m / (x, y, z)
constexpr float kBand0Area = 4.0f * kPi * kY00;  // a constant radiance a projects to L_0 = a 4 pi Y_0

float luminance(const glm::vec3& c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

ShadowLight dominantLight(const std::array<glm::vec3, 9>& irradianceSH) noexcept {
  ShadowLight out;
  // Radiance from irradiance: L_l = c_l / A_l (A_0 = pi, A_1 = 2 pi / 3).
  const float l0 = luminance(irradianceSH[0]) / kPi;
  const glm::vec3 l1 = glm::vec3(luminance(irradianceSH[1]), luminance(irradianceSH[2]), luminance(irradianceSH[3])) /
                       (2.0f * kPi / 3.0f);
  const float length1 = glm::length(l1);
  if (!(l0 > 0.0f) || !std::isfinite(l0) || !std::isfinite(length1)) return out;
  // A delta light of irradiance I from d projects to L_0 = I Y_0, L_1 = I Y_1 d; the ambient
  // takes the rest of band 0. A band 1 too strong for that (ringing) puts all of band 0 in I.
  float direct = length1 / kY1;
  float ambient = (l0 - direct * kY00) / kBand0Area;
  if (ambient < 0.0f) {
    direct = l0 / kY00;
    ambient = 0.0f;
  }
  if (length1 > 0.0f) out.towardLight = l1 / length1;
  out.directionality = std::clamp(direct * kY00 / l0, 0.0f, 1.0f);
  const float floorDirect = direct * std::max(out.towardLight.y, 0.0f);
  const float floorAmbient = kPi * ambient;  // the upper hemisphere's constant radiance on a +Y normal
  const float floorTotal = floorDirect + floorAmbient;
  if (!(floorTotal > 0.0f)) return out;
  out.directFraction = floorDirect / floorTotal;
  out.ambientFraction = floorAmbient / floorTotal;
  return out;
}

ShadowCaster shadowCaster(std::span<const glm::vec3> jointWorld, const glm::vec3& towardLight) noexcept {
  ShadowCaster out;
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(std::numeric_limits<float>::lowest());
  std::size_t count = 0;
  for (const glm::vec3& p : jointWorld) {
    if (!finite(p)) continue;
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
    ++count;
  }
  if (count == 0 || hi.y < 0.0f) return out;
  const glm::vec3 extent = hi - lo;
  const float size = std::max({extent.x, extent.y, extent.z, 1e-3f});
  out.height = extent.y;
  out.centre = 0.5f * (lo + hi);
  out.radius = 0.5f * glm::length(extent) + kBoundsMargin * size;

  // The lowest joints within kContactHeight of the floor, each a disc; the weight fades as it rises.
  const float reach = kContactHeight * size;
  for (const glm::vec3& p : jointWorld) {
    if (!finite(p) || p.y >= reach) continue;
    const glm::vec4 contact(p.x, p.z, kContactDiscRadius * size, 1.0f - std::max(p.y, 0.0f) / reach);
    if (out.contactCount < kMaxContactPoints) {
      out.contacts[out.contactCount++] = contact;
      continue;
    }
    // Full: replace the weakest (the highest joint) if this one is lower.
    auto weakest = std::min_element(out.contacts.begin(), out.contacts.end(),
                                    [](const glm::vec4& a, const glm::vec4& b) { return a.w < b.w; });
    if (weakest->w < contact.w) *weakest = contact;
  }

  // The catcher: the footprint (the bounding sphere's disc), stretched toward where the
  // directional shadow falls (a low light throws it far: at most 3 bounding radii). A rectangle
  // along the throw, so that a long shadow does not pay for a square's area.
  glm::vec2 ground(out.centre.x, out.centre.z);
  float halfLength = out.radius;
  const glm::vec2 across(towardLight.x, towardLight.z);
  const float acrossLength = glm::length(across);
  if (finite(towardLight) && towardLight.y > 0.05f && acrossLength > 1e-4f) {
    const float throwLength = std::min(hi.y * acrossLength / towardLight.y, 3.0f * out.radius);
    out.catcherAxis = -across / acrossLength;
    ground += out.catcherAxis * (0.5f * throwLength);
    halfLength += 0.5f * throwLength;
  }
  out.catcherCentre = ground;
  out.catcherHalfLength = halfLength;
  out.catcherHalfWidth = out.radius;
  out.valid = true;
  return out;
}

glm::mat4 lightViewProjection(const ShadowCaster& caster, const glm::vec3& towardLight) noexcept {
  const float r = std::max(caster.radius, 1e-3f);
  glm::vec3 d = finite(towardLight) && glm::length(towardLight) > 1e-6f ? glm::normalize(towardLight) : glm::vec3(0, 1, 0);
  const glm::vec3 up = std::abs(d.y) > 0.99f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
  const glm::mat4 view = glm::lookAt(caster.centre + d * (2.0f * r), caster.centre, up);
  return glm::ortho(-r, r, -r, r, r, 3.0f * r) * view;
}

}  // namespace marionette::ar
