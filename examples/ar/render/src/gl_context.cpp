#include "marionette_ar/render/gl_context.hpp"

#include <epoxy/gl.h>
#include <GLFW/glfw3.h>

namespace marionette::ar {
namespace {

std::string& lastGlfwError() {
  static std::string message;  // GLFW reports through a process-wide callback
  return message;
}

void onGlfwError(int code, const char* description) {
  lastGlfwError() = "GLFW error " + std::to_string(code) + ": " + (description ? description : "");
}

}  // namespace

std::unique_ptr<GlContext> GlContext::create(const GlContextOptions& options, Diagnostics& diagnostics) {
  glfwSetErrorCallback(onGlfwError);
  if (!glfwInit()) {
    diagnostics.error("", "cannot initialise GLFW (" + lastGlfwError() +
                              "); headless rendering still needs an X display: run under xvfb-run (docs/ar-renderer.md)");
    return nullptr;
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_VISIBLE, options.visible ? GLFW_TRUE : GLFW_FALSE);
  glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
  GLFWwindow* window = glfwCreateWindow(options.width, options.height, options.title.c_str(), nullptr, nullptr);
  if (!window) {
    diagnostics.error("", "cannot create an OpenGL 3.3 core context (" + lastGlfwError() + ")");
    glfwTerminate();
    return nullptr;
  }
  glfwMakeContextCurrent(window);
  glfwSwapInterval(options.visible ? 1 : 0);
  std::unique_ptr<GlContext> context(new GlContext());
  context->window_ = window;
  return context;
}

GlContext::~GlContext() {
  if (window_) glfwDestroyWindow(window_);
  glfwTerminate();
}

bool GlContext::shouldClose() const { return glfwWindowShouldClose(window_) != 0; }

void GlContext::swapAndPoll() {
  glfwSwapBuffers(window_);
  glfwPollEvents();
}

void GlContext::framebufferSize(int& width, int& height) const { glfwGetFramebufferSize(window_, &width, &height); }

std::string GlContext::rendererName() const {
  const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  return std::string(renderer ? renderer : "?") + ", OpenGL " + (version ? version : "?");
}

}  // namespace marionette::ar
