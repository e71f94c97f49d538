// Contact shadows on the tracked floor (the world's y = 0 plane): what the light is and where
// a character touches the floor, computed on the CPU from the same SH light that shades the
// character (docs/ar-renderer.md, "Contact shadows"). The GL passes that draw them are
// marionette_ar/render/contact_shadow_renderer.hpp.
//
// The light model: the environment seen by the floor is a distant directional light (from
// the band-1 direction of the irradiance's luminance) plus a uniform ambient, fitted to bands
// 0 and 1 exactly. The directional part casts the character's shadow (a shadow map, softened
// by `softnessDegrees`); the ambient part is darkened by soft discs under the contact points.
#pragma once
#include <array>
#include <cstddef>
#include <span>

#include <glm/glm.hpp>

namespace marionette::ar {

struct ShadowLight {
  glm::vec3 towardLight{0.0f, 1.0f, 0.0f};  // unit, world: where the directional part comes from
  float directFraction = 0.0f;   // share of the floor's irradiance (normal +Y) from the directional part
  float ambientFraction = 0.0f;  // the rest (0 when the floor gets no light at all)
  float directionality = 0.0f;   // the directional part's share of the light's total power, 0..1
};

// The directional + ambient fit of 9 irradiance coefficients (E(n) = sum c_i Y_i(n), RGB, the
// renderer's convention), on their luminance. A light from below the floor, or no light, gives
// directFraction 0. Pure, no allocation.
[[nodiscard]] ShadowLight dominantLight(const std::array<glm::vec3, 9>& irradianceSH) noexcept;

inline constexpr std::size_t kMaxContactPoints = 8;

// Where one character stands, from its joints' world positions this frame.
struct ShadowCaster {
  bool valid = false;             // false: no finite joint, or a character entirely below the floor
  glm::vec3 centre{0.0f};         // of the bounding sphere (the joints' box, grown by the margin)
  float radius = 0.0f;
  float height = 0.0f;            // the joints' extent along +Y (the character's size)
  // Floor points under the joints nearest the floor (x, z, disc radius, weight 0..1 that falls
  // to 0 as the joint rises to kContactHeight of the character's height).
  std::array<glm::vec4, kMaxContactPoints> contacts{};
  std::size_t contactCount = 0;
  // The rectangle on the floor that the catcher covers: centre (x, z), its long axis (unit, x, z:
  // where the shadow falls, or +X), half its length along that axis and half its width across.
  glm::vec2 catcherCentre{0.0f};
  glm::vec2 catcherAxis{1.0f, 0.0f};
  float catcherHalfLength = 0.0f, catcherHalfWidth = 0.0f;
};

inline constexpr float kContactHeight = 0.08f;     // of the character's height: a joint this low touches
inline constexpr float kContactDiscRadius = 0.07f;  // of the character's height
inline constexpr float kBoundsMargin = 0.15f;       // the mesh beyond its joints, of the largest extent

// The caster of one character. `jointWorld` are the joints' world positions; `towardLight` the
// light's direction (the catcher is grown to hold the cast shadow, up to 3 bounding radii for a
// low light). No allocation.
[[nodiscard]] ShadowCaster shadowCaster(std::span<const glm::vec3> jointWorld, const glm::vec3& towardLight) noexcept;

// The orthographic view-projection that sees the caster's bounding sphere from the light
// (depth 0..1 from the sphere's near side to its far side).
[[nodiscard]] glm::mat4 lightViewProjection(const ShadowCaster& caster, const glm::vec3& towardLight) noexcept;

}  // namespace marionette::ar
