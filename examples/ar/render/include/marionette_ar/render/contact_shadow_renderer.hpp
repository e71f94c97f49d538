// Contact shadows on the floor (world y = 0): per character, its depth from the dominant light
// into a shadow map of its own (character.vert + shadow_depth.frag), drawn before the frame's
// target is bound (a framebuffer switch in mid-frame costs a software rasterizer a flush and a
// reload of the frame); then a rectangle on the floor (shadow_catcher.*) that multiplies the
// image already drawn (the camera's) by the light the character takes away. What the light is
// and where the character stands are computed on the CPU (marionette_ar/contact_shadow.hpp);
// docs/ar-renderer.md, "Contact shadows".
#pragma once
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "marionette_ar/render/character_renderer.hpp"
#include "marionette_ar/render/occlusion_mask_texture.hpp"
#include "marionette_ar/render/shader_program.hpp"

namespace marionette::ar {

// One character's shadow, in the renderer's terms.
struct ContactShadowDraw {
  glm::mat4 lightViewProjection{1.0f};  // orthographic, from the light onto the character's bounds
  glm::vec2 centre{0.0f};               // the floor rectangle: centre (x, z),
  glm::vec2 axis{1.0f, 0.0f};           // its long axis (unit, x, z),
  glm::vec2 halfSize{0.0f};             // half its length along the axis and across
  std::span<const glm::vec4> contacts;  // x, z, disc radius, weight (at most 8 are used)
  bool hasDirect = false;               // false: the ambient discs alone (no shadow map)
  float tanSoftness = 0.1f;             // tan of the light's angular radius
  float directFraction = 0.0f, ambientFraction = 0.0f;
  float strength = 1.0f;                // settings x the character's opacity
  const OcclusionDraw* occlusion = nullptr;  // what hides the floor is not darkened (none: null)
};

class ContactShadowRenderer {
 public:
  static constexpr int kMapSize = 512;

  ContactShadowRenderer() = default;
  ~ContactShadowRenderer();
  ContactShadowRenderer(const ContactShadowRenderer&) = delete;
  ContactShadowRenderer& operator=(const ContactShadowRenderer&) = delete;

  // Builds the programs and one shadow map per character slot; false with the error in
  // `diagnostics`.
  bool create(std::size_t slots, Diagnostics& diagnostics);
  // Slot `slot`'s shadow map: the character's depth from the light. Call before binding the
  // frame's target; it leaves framebuffer 0 bound and the viewport changed. No allocation.
  void renderMap(std::size_t slot, const CharacterModel& model, const CharacterPose& pose, const glm::mat4& world,
                 const glm::mat4& lightViewProjection);
  // Slot `slot`'s catcher over the framebuffer bound now (its map rendered this frame when
  // shadow.hasDirect). No allocation.
  void drawCatcher(std::size_t slot, const glm::mat4& viewProjection, const ContactShadowDraw& shadow) const;

 private:
  ShaderProgram depthProgram_, catcherProgram_;
  unsigned fbo_ = 0, vao_ = 0;
  std::vector<unsigned> maps_;
};

}  // namespace marionette::ar
