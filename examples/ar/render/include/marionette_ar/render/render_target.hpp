// The offscreen framebuffer every frame is drawn into (4x multisampled colour
// and depth), resolved for reading back: headless PNG frames, screenshots and
// the window all show the same pixels.
#pragma once
#include "marionette_ar/render/image.hpp"

namespace marionette::ar {

class RenderTarget {
 public:
  RenderTarget() = default;
  ~RenderTarget();
  RenderTarget(const RenderTarget&) = delete;
  RenderTarget& operator=(const RenderTarget&) = delete;

  // False with an error in `diagnostics` (no file: its `file` is empty) when a framebuffer is incomplete.
  bool create(int width, int height, int samples, Diagnostics& diagnostics);
  void bind() const;  // draw into it (sets the viewport)
  // Resolves the samples and reads the frame back as RGB8, row 0 at the top.
  void read(Image8& out);
  // Resolves into the window's default framebuffer of the given size.
  void present(int windowWidth, int windowHeight) const;
  [[nodiscard]] int width() const noexcept { return width_; }
  [[nodiscard]] int height() const noexcept { return height_; }

 private:
  void resolve() const;
  unsigned msaaFbo_ = 0, colorRb_ = 0, depthRb_ = 0;
  unsigned resolveFbo_ = 0, resolveColor_ = 0;
  int width_ = 0, height_ = 0;
};

}  // namespace marionette::ar
