// What is drawn behind the characters: the camera's image (a photo, an image
// sequence or a video frame, fitted to cover the viewport without stretching),
// the HDR environment seen through the camera, or a flat colour.
#pragma once
#include <glm/glm.hpp>

#include "marionette_ar/render/image.hpp"
#include "marionette_ar/render/shader_program.hpp"

namespace marionette::ar {

// How a camera image covers a viewport without stretching (the longer side cropped): viewport
// coordinates s in [0, 1]^2 (origin bottom-left) see the image at uv = s * rect.xy + rect.zw
// (origin bottom-left too). Shared by the background's drawing and the light estimate.
[[nodiscard]] inline glm::vec4 coverRect(float imageAspect, float viewportAspect) noexcept {
  glm::vec4 rect(1.0f, 1.0f, 0.0f, 0.0f);
  if (viewportAspect > imageAspect) rect.y = imageAspect / viewportAspect;
  else rect.x = viewportAspect / imageAspect;
  rect.z = 0.5f * (1.0f - rect.x);
  rect.w = 0.5f * (1.0f - rect.y);
  return rect;
}

class BackgroundRenderer {
 public:
  BackgroundRenderer() = default;
  ~BackgroundRenderer();
  BackgroundRenderer(const BackgroundRenderer&) = delete;
  BackgroundRenderer& operator=(const BackgroundRenderer&) = delete;

  // Builds its shaders; false with the error in `diagnostics` (ShaderProgram::build).
  bool create(Diagnostics& diagnostics);
  // A new camera frame (RGB or RGBA, row 0 at the top); re-allocates only when the size changes.
  void setImage(const Image8& image);
  // The environment as linear RGB floats, lat-long, row 0 at +Y.
  void setEnvironment(int width, int height, const float* rgb);

  void drawImage(float viewportAspect) const;
  void drawEnvironment(const glm::mat4& inverseViewProjection, float exposure, float rotationRadians) const;
  void drawFlat(const glm::vec3& color) const;

 private:
  void draw() const;
  ShaderProgram program_;
  unsigned vao_ = 0, image_ = 0, environment_ = 0;
  int imageWidth_ = 0, imageHeight_ = 0;
};

}  // namespace marionette::ar
