// Occlusion over the target, on the GPU side (docs/ar-renderer.md, "Occlusion over the target"):
// the mask of the camera frame's pixels that something real hides (the markerless tracker's
// occlusionMask(), or a mask made elsewhere) as a texture, and what the shaders' occludedShare()
// (occlusion.glsl) needs to find a fragment's value in it. The character shader fades what lies
// over the mask, the shadow catcher does not darken it.
#pragma once
#include <cstdint>

#include <glm/glm.hpp>

#include "marionette_ar/render/shader_program.hpp"

namespace marionette::ar {

// One frame's occlusion, for drawCharacter (Lighting::occlusion) and the shadow catcher.
struct OcclusionDraw {
  unsigned texture = 0;                        // R8, row 0 at the top of the frame
  glm::vec4 screenToImage{1.0f, 1.0f, 0.0f, 0.0f};  // coverRect(frame aspect, viewport aspect)
  glm::vec2 imageToMask{1.0f, 1.0f};           // frame size / (mask size x its scale): its last pixels may pass the edge
  glm::vec2 viewport{1.0f, 1.0f};              // pixels
  float heightLimit = -1.0f;                   // metres above the floor; < 0: everything over the mask
};

// Sets occlusion.glsl's uniforms on `program` (in use), the mask on texture `unit`; null turns it off.
void setOcclusionUniforms(const ShaderProgram& program, const OcclusionDraw* occlusion, int unit);

class OcclusionMaskTexture {
 public:
  OcclusionMaskTexture() = default;
  ~OcclusionMaskTexture();
  OcclusionMaskTexture(const OcclusionMaskTexture&) = delete;
  OcclusionMaskTexture& operator=(const OcclusionMaskTexture&) = delete;

  // A mask of width x height bytes (rows top to bottom, `stride` bytes apart): 255 hidden, 0 shown.
  // Re-allocates only when the size changes; linear filtering gives the edge between mask pixels.
  void upload(int width, int height, const std::uint8_t* pixels, std::ptrdiff_t stride);
  [[nodiscard]] unsigned texture() const noexcept { return texture_; }
  [[nodiscard]] int width() const noexcept { return width_; }
  [[nodiscard]] int height() const noexcept { return height_; }

 private:
  unsigned texture_ = 0;
  int width_ = 0, height_ = 0;
};

}  // namespace marionette::ar
