#include "marionette_ar/render/occlusion_mask_texture.hpp"

#include <epoxy/gl.h>

namespace marionette::ar {

void setOcclusionUniforms(const ShaderProgram& program, const OcclusionDraw* occlusion, int unit) {
  const bool on = occlusion && occlusion->texture;
  program.set("uOcclusionOn", on ? 1 : 0);
  program.set("uOcclusionMask", unit);
  if (!on) return;
  program.set("uOcclusionScreenToImage", occlusion->screenToImage);
  glUniform2f(program.location("uOcclusionImageToMask"), occlusion->imageToMask.x, occlusion->imageToMask.y);
  glUniform2f(program.location("uOcclusionViewport"), occlusion->viewport.x, occlusion->viewport.y);
  program.set("uOcclusionHeight", occlusion->heightLimit);
  glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(unit));
  glBindTexture(GL_TEXTURE_2D, occlusion->texture);
  glActiveTexture(GL_TEXTURE0);
}

OcclusionMaskTexture::~OcclusionMaskTexture() {
  if (texture_) glDeleteTextures(1, &texture_);
}

void OcclusionMaskTexture::upload(int width, int height, const std::uint8_t* pixels, std::ptrdiff_t stride) {
  if (width <= 0 || height <= 0 || !pixels || stride < width) return;
  if (!texture_) glGenTextures(1, &texture_);
  glBindTexture(GL_TEXTURE_2D, texture_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, static_cast<GLint>(stride));
  if (width != width_ || height != height_) {
    glTexImage2D(GL_TEXTURE_2D, 0, GL_R8, width, height, 0, GL_RED, GL_UNSIGNED_BYTE, pixels);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    width_ = width;
    height_ = height;
  } else {
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, GL_RED, GL_UNSIGNED_BYTE, pixels);
  }
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  glBindTexture(GL_TEXTURE_2D, 0);
}

}  // namespace marionette::ar
