#include "marionette_ar/render/render_target.hpp"

#include <epoxy/gl.h>

#include <cstring>

namespace marionette::ar {

RenderTarget::~RenderTarget() {
  if (msaaFbo_) glDeleteFramebuffers(1, &msaaFbo_);
  if (resolveFbo_) glDeleteFramebuffers(1, &resolveFbo_);
  if (colorRb_) glDeleteRenderbuffers(1, &colorRb_);
  if (depthRb_) glDeleteRenderbuffers(1, &depthRb_);
  if (resolveColor_) glDeleteRenderbuffers(1, &resolveColor_);
}

bool RenderTarget::create(int width, int height, int samples, Diagnostics& diagnostics) {
  width_ = width;
  height_ = height;
  GLint maxSamples = 1;
  glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
  samples = samples > maxSamples ? maxSamples : samples;
  glGenFramebuffers(1, &msaaFbo_);
  glGenRenderbuffers(1, &colorRb_);
  glGenRenderbuffers(1, &depthRb_);
  glBindRenderbuffer(GL_RENDERBUFFER, colorRb_);
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, width, height);
  glBindRenderbuffer(GL_RENDERBUFFER, depthRb_);
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, width, height);
  glBindFramebuffer(GL_FRAMEBUFFER, msaaFbo_);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colorRb_);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depthRb_);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    diagnostics.error("", "the multisampled framebuffer is incomplete");
    return false;
  }
  glGenFramebuffers(1, &resolveFbo_);
  glGenRenderbuffers(1, &resolveColor_);
  glBindRenderbuffer(GL_RENDERBUFFER, resolveColor_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  glBindFramebuffer(GL_FRAMEBUFFER, resolveFbo_);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, resolveColor_);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    diagnostics.error("", "the resolve framebuffer is incomplete");
    return false;
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return true;
}

void RenderTarget::bind() const {
  glBindFramebuffer(GL_FRAMEBUFFER, msaaFbo_);
  glViewport(0, 0, width_, height_);
}

void RenderTarget::resolve() const {
  glBindFramebuffer(GL_READ_FRAMEBUFFER, msaaFbo_);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolveFbo_);
  glBlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
}

void RenderTarget::read(Image8& out) {
  resolve();
  glBindFramebuffer(GL_READ_FRAMEBUFFER, resolveFbo_);
  out.width = width_;
  out.height = height_;
  out.channels = 3;
  const std::size_t row = static_cast<std::size_t>(width_) * 3;
  out.pixels.resize(row * static_cast<std::size_t>(height_));
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width_, height_, GL_RGB, GL_UNSIGNED_BYTE, out.pixels.data());
  // OpenGL's row 0 is the bottom one.
  for (int y = 0; y < height_ / 2; ++y)
    std::swap_ranges(out.pixels.begin() + static_cast<std::ptrdiff_t>(row * static_cast<std::size_t>(y)),
                     out.pixels.begin() + static_cast<std::ptrdiff_t>(row * static_cast<std::size_t>(y + 1)),
                     out.pixels.begin() + static_cast<std::ptrdiff_t>(row * static_cast<std::size_t>(height_ - 1 - y)));
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void RenderTarget::present(int windowWidth, int windowHeight) const {
  resolve();
  glBindFramebuffer(GL_READ_FRAMEBUFFER, resolveFbo_);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
  glBlitFramebuffer(0, 0, width_, height_, 0, 0, windowWidth, windowHeight, GL_COLOR_BUFFER_BIT, GL_LINEAR);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace marionette::ar
