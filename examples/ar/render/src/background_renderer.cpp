#include "marionette_ar/render/background_renderer.hpp"

#include <epoxy/gl.h>

namespace marionette::ar {

BackgroundRenderer::~BackgroundRenderer() {
  if (vao_) glDeleteVertexArrays(1, &vao_);
  if (image_) glDeleteTextures(1, &image_);
  if (environment_) glDeleteTextures(1, &environment_);
}

bool BackgroundRenderer::create(Diagnostics& diagnostics) {
  if (!program_.build("background.vert", "background.frag", diagnostics)) return false;
  glGenVertexArrays(1, &vao_);  // core profile: a draw needs a bound VAO even without attributes
  return true;
}

void BackgroundRenderer::setImage(const Image8& image) {
  if (image.empty()) return;
  const GLenum format = image.channels == 4 ? GL_RGBA : GL_RGB;
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  if (!image_ || image.width != imageWidth_ || image.height != imageHeight_) {
    if (!image_) glGenTextures(1, &image_);
    glBindTexture(GL_TEXTURE_2D, image_);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, image.width, image.height, 0, format, GL_UNSIGNED_BYTE, image.pixels.data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    imageWidth_ = image.width;
    imageHeight_ = image.height;
  } else {
    glBindTexture(GL_TEXTURE_2D, image_);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, image.width, image.height, format, GL_UNSIGNED_BYTE, image.pixels.data());
  }
}

void BackgroundRenderer::setEnvironment(int width, int height, const float* rgb) {
  if (!environment_) glGenTextures(1, &environment_);
  glBindTexture(GL_TEXTURE_2D, environment_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  // RGB16F: filterable on every GL 3.3 and ES 3.0 device, enough range for HDR light.
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB16F, width, height, 0, GL_RGB, GL_FLOAT, rgb);
  glGenerateMipmap(GL_TEXTURE_2D);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

void BackgroundRenderer::drawImage(float viewportAspect) const {
  program_.use();
  program_.set("uMode", image_ ? 0 : 2);
  program_.set("uFlatColor", glm::vec3(0.0f));
  // Cover: scale the image so it fills the viewport, cropping the longer side.
  const float imageAspect = imageHeight_ > 0 ? static_cast<float>(imageWidth_) / static_cast<float>(imageHeight_) : 1.0f;
  program_.set("uImageRect", coverRect(imageAspect, viewportAspect));
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, image_);
  program_.set("uImage", 0);
  draw();
}

void BackgroundRenderer::drawEnvironment(const glm::mat4& inverseViewProjection, float exposure,
                                         float rotationRadians) const {
  program_.use();
  program_.set("uMode", environment_ ? 1 : 2);
  program_.set("uFlatColor", glm::vec3(0.0f));
  program_.set("uInverseViewProjection", inverseViewProjection);
  program_.set("uExposure", exposure);
  program_.set("uEnvironmentRotation", rotationRadians);
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D, environment_);
  program_.set("uEnvironment", 1);
  draw();
}

void BackgroundRenderer::drawFlat(const glm::vec3& color) const {
  program_.use();
  program_.set("uMode", 2);
  program_.set("uFlatColor", color);
  draw();
}

void BackgroundRenderer::draw() const {
  glDisable(GL_DEPTH_TEST);
  glDepthMask(GL_FALSE);
  glBindVertexArray(vao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glDepthMask(GL_TRUE);
  glEnable(GL_DEPTH_TEST);
  glActiveTexture(GL_TEXTURE0);
}

}  // namespace marionette::ar
