// GlContext: a headless OpenGL 4.5 core context through EGL, with no window system and no surface
// (EGL_KHR_surfaceless_context). Platforms tried: the EGL device platform (EGL_EXT_platform_device, NVIDIA;
// the first device that gives a 4.5 core context) and Mesa's surfaceless platform
// (EGL_MESA_platform_surfaceless, llvmpipe on machines without a GPU). With EGL_PLATFORM=surfaceless in the
// environment the surfaceless platform is tried first. GL entry points come from libepoxy.
//
// Owned by the render thread: the constructor makes the context current on the calling thread, and every GL
// call of render/ must be made from that thread. Not copyable or movable (GL objects refer to the current
// context). One GlContext per process at a time: EGL displays are shared per platform, and the destructor
// terminates it.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace ropecast {

struct GlContextInfo {
  std::string platform;  // "device" or "surfaceless" (EGL), "glfw" (a window)
  std::string vendor, renderer, version;
  std::optional<uint64_t>
      totalGpuMemoryBytes;  // NVX_gpu_memory_info (total) or ATI_meminfo (free texture memory)
  int max3DTextureSize = 0;
  int maxTextureBufferTexels = 0;
};

struct GlContextOptions {
  // Debug output (KHR_debug) printed to stderr. Defaults to on in builds without NDEBUG.
  bool debugOutput =
#ifdef NDEBUG
      false;
#else
      true;
#endif
};

class GlContext {
 public:
  // Throws ropecast::Error naming what is missing (EGL, a platform extension, surfaceless contexts, GL 4.5
  // core).
  explicit GlContext(const GlContextOptions& options = {});
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  const GlContextInfo& info() const { return info_; }
  // Makes the context current on the calling thread again (after another context was made current).
  void makeCurrent() const;

 private:
  void* display_ = nullptr;  // EGLDisplay
  void* context_ = nullptr;  // EGLContext
  GlContextInfo info_;
};

// What the context current on the calling thread is: vendor, renderer, version, limits, memory; `platform`
// names how it was made. Shared by GlContext and the viewer's window context (render/window_context.h).
GlContextInfo describeCurrentContext(const std::string& platform);
// Prints the current context's debug output (KHR_debug) to stderr, notifications left out.
void enableDebugOutput();

// Throws ropecast::Error("<where>: GL error 0x...") if glGetError reports one; for checks at pass boundaries.
void checkGlError(const char* where);

}  // namespace ropecast
