#include "render/window_context.h"

#include <epoxy/gl.h>
// epoxy's GL header first: GLFW then includes no GL header of its own.
#include <GLFW/glfw3.h>

#include "core/error.h"

namespace ropecast {

namespace {

// GLFW reports errors through a callback; the last one is kept for the exception that follows.
std::string lastGlfwError;

void onGlfwError(int code, const char* description) {
  lastGlfwError = description ? description : "error " + std::to_string(code);
}

std::string takeGlfwError() {
  std::string e = lastGlfwError.empty() ? "no reason given" : lastGlfwError;
  lastGlfwError.clear();
  return e;
}

}  // namespace

WindowContext::WindowContext(const WindowContextOptions& options) {
  glfwSetErrorCallback(onGlfwError);
  if (!glfwInit())
    throw NoDisplayError("WindowContext: no display: GLFW cannot initialize (" + takeGlfwError() + ")");
  glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_API);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, options.debugOutput ? GLFW_TRUE : GLFW_FALSE);
  glfwWindowHint(GLFW_SCALE_TO_MONITOR, GLFW_FALSE);
  window_ =
      glfwCreateWindow(int(options.width), int(options.height), options.title.c_str(), nullptr, nullptr);
  if (!window_) {
    const std::string why = takeGlfwError();
    glfwTerminate();
    throw Error("WindowContext: no window with an OpenGL 4.5 core context (" + why + ")");
  }
  glfwMakeContextCurrent(window_);
  if (epoxy_gl_version() < 45) {
    const int version = epoxy_gl_version();
    glfwDestroyWindow(window_);
    glfwTerminate();
    throw Error("WindowContext: the window's context reports OpenGL " + std::to_string(version) +
                ", need 4.5 core");
  }
  // Frames render as fast as they can while bricks stream in; the display does not pace them.
  glfwSwapInterval(0);
  info_ = describeCurrentContext("glfw");
  if (options.debugOutput) enableDebugOutput();
  while (glGetError() != GL_NO_ERROR) {
  }
}

WindowContext::~WindowContext() {
  glfwDestroyWindow(window_);
  glfwTerminate();
}

void WindowContext::framebufferSize(uint32_t& width, uint32_t& height) const {
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_, &w, &h);
  width = uint32_t(w > 0 ? w : 0);
  height = uint32_t(h > 0 ? h : 0);
}

bool WindowContext::shouldClose() const {
  return glfwWindowShouldClose(window_);
}

void WindowContext::swapBuffers() const {
  glfwSwapBuffers(window_);
}

}  // namespace ropecast
