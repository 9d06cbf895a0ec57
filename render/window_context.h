// WindowContext: an OpenGL 4.5 core context with a window, through GLFW on X11 (any GL 4.5 driver: a GPU, or
// Mesa's llvmpipe), for `ropecast view`. The headless commands keep GlContext (EGL); FrameRenderer takes the
// GlContextInfo of either. GL entry points come from libepoxy, as in GlContext.
//
// Owned by the main thread: GLFW must be initialized, polled and torn down there, and the constructor makes
// the context current on it; every GL call of render/ is made from that thread. One WindowContext per process
// at a time (it initializes and terminates GLFW). Not copyable or movable.
#pragma once

#include <cstdint>
#include <string>

#include "core/error.h"
#include "render/gl_context.h"

struct GLFWwindow;

namespace ropecast {

struct WindowContextOptions {
  std::string title = "ropecast";
  uint32_t width = 512, height = 512;  // window size in screen coordinates
  bool debugOutput = GlContextOptions{}.debugOutput;
};

// No display to open a window on (GLFW cannot initialize), as opposed to a display without OpenGL 4.5 core:
// callers point at different remedies.
class NoDisplayError : public Error {
 public:
  using Error::Error;
};

class WindowContext {
 public:
  // Throws NoDisplayError when there is no display, ropecast::Error naming what else failed: no window, no
  // 4.5 core context.
  explicit WindowContext(const WindowContextOptions& options);
  ~WindowContext();
  WindowContext(const WindowContext&) = delete;
  WindowContext& operator=(const WindowContext&) = delete;

  const GlContextInfo& info() const { return info_; }
  GLFWwindow* window() const { return window_; }
  // The default framebuffer's size in pixels (may differ from the window size on scaled displays).
  void framebufferSize(uint32_t& width, uint32_t& height) const;
  bool shouldClose() const;
  void swapBuffers() const;

 private:
  GLFWwindow* window_ = nullptr;
  GlContextInfo info_;
};

}  // namespace ropecast
