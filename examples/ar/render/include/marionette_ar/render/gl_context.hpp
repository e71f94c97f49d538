// An OpenGL 3.3 core context in a GLFW window: visible for interactive use,
// hidden for headless rendering (which then needs an X display such as Xvfb;
// see docs/ar-renderer.md). One per process is enough for the renderer.
#pragma once
#include <memory>
#include <string>

#include "marionette/core/diagnostic.hpp"

struct GLFWwindow;

namespace marionette::ar {

struct GlContextOptions {
  int width = 1280;
  int height = 720;
  bool visible = true;
  std::string title = "marionette-ar";
};

class GlContext {
 public:
  // Returns nullptr with an error in `diagnostics` naming what failed (no display, no GL 3.3;
  // no file: its `file` is empty).
  static std::unique_ptr<GlContext> create(const GlContextOptions& options, Diagnostics& diagnostics);
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  [[nodiscard]] GLFWwindow* window() const noexcept { return window_; }
  [[nodiscard]] bool shouldClose() const;
  void swapAndPoll();
  // The window's framebuffer size in pixels (may differ from the requested size on HiDPI).
  void framebufferSize(int& width, int& height) const;
  [[nodiscard]] std::string rendererName() const;  // GL_RENDERER / GL_VERSION

 private:
  GlContext() = default;
  GLFWwindow* window_ = nullptr;
};

}  // namespace marionette::ar
