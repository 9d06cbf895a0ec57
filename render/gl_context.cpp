#include "render/gl_context.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string_view>
#include <vector>

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include "core/error.h"

namespace ropecast {

namespace {

bool hasExtension(const char* list, std::string_view name) {
  if (!list) return false;
  std::string_view all(list);
  size_t pos = 0;
  while ((pos = all.find(name, pos)) != std::string_view::npos) {
    const bool startOk = pos == 0 || all[pos - 1] == ' ';
    const bool endOk = pos + name.size() == all.size() || all[pos + name.size()] == ' ';
    if (startOk && endOk) return true;
    pos += name.size();
  }
  return false;
}

std::string eglErrorText() {
  char buf[32];
  std::snprintf(buf, sizeof buf, "EGL error 0x%04x", unsigned(eglGetError()));
  return buf;
}

void GLAPIENTRY debugCallback(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei length,
                              const GLchar* message, const void*) {
  if (severity == GL_DEBUG_SEVERITY_NOTIFICATION) return;
  std::fprintf(stderr, "GL debug [type 0x%x id %u severity 0x%x]: %.*s\n", type, id, severity, int(length),
               message);
}

struct Attempt {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
};

// Initializes `display` and creates a current 4.5 core context on it; on failure returns why and cleans up.
std::string tryDisplay(EGLDisplay display, const GlContextOptions& options, Attempt& out) {
  if (display == EGL_NO_DISPLAY) return "no display (" + eglErrorText() + ")";
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) return "eglInitialize failed (" + eglErrorText() + ")";
  const char* extensions = eglQueryString(display, EGL_EXTENSIONS);
  auto fail = [&](std::string why) {
    eglTerminate(display);
    return why;
  };
  if (!hasExtension(extensions, "EGL_KHR_surfaceless_context"))
    return fail("EGL_KHR_surfaceless_context missing");
  if (!eglBindAPI(EGL_OPENGL_API)) return fail("eglBindAPI(EGL_OPENGL_API) failed (" + eglErrorText() + ")");

  EGLConfig config = nullptr;
  if (!hasExtension(extensions, "EGL_KHR_no_config_context")) {
    const EGLint configAttribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLint count = 0;
    if (!eglChooseConfig(display, configAttribs, &config, 1, &count) || count < 1)
      return fail("no EGL config with EGL_OPENGL_BIT");
  }
  const EGLint contextAttribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                   4,
                                   EGL_CONTEXT_MINOR_VERSION,
                                   5,
                                   EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                   EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                   EGL_CONTEXT_OPENGL_DEBUG,
                                   options.debugOutput ? EGL_TRUE : EGL_FALSE,
                                   EGL_NONE};
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttribs);
  if (context == EGL_NO_CONTEXT) return fail("no OpenGL 4.5 core context (" + eglErrorText() + ")");
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
    eglDestroyContext(display, context);
    return fail("eglMakeCurrent without a surface failed (" + eglErrorText() + ")");
  }
  if (epoxy_gl_version() < 45) {
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display, context);
    return fail("context reports OpenGL " + std::to_string(epoxy_gl_version()) + ", need 4.5 core");
  }
  out = {display, context};
  return {};
}

}  // namespace

GlContext::GlContext(const GlContextOptions& options) {
  const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!clientExtensions)
    throw Error(
        "GlContext: EGL client extensions unavailable (EGL 1.5 or EGL_EXT_client_extensions missing)");
  const bool hasDevice = hasExtension(clientExtensions, "EGL_EXT_platform_device") &&
                         hasExtension(clientExtensions, "EGL_EXT_device_enumeration");
  const bool hasSurfaceless = hasExtension(clientExtensions, "EGL_MESA_platform_surfaceless");
  if (!hasDevice && !hasSurfaceless)
    throw Error(
        "GlContext: neither EGL_EXT_platform_device (+EGL_EXT_device_enumeration) nor "
        "EGL_MESA_platform_surfaceless is available; EGL client extensions: " +
        std::string(clientExtensions));

  std::string failures;
  Attempt attempt;
  auto tryDevices = [&]() {
    if (!hasDevice) return false;
    EGLint count = 0;
    if (!eglQueryDevicesEXT(0, nullptr, &count) || count <= 0) {
      failures += " device platform: no EGL devices;";
      return false;
    }
    std::vector<EGLDeviceEXT> devices(static_cast<size_t>(count));
    eglQueryDevicesEXT(count, devices.data(), &count);
    for (EGLint i = 0; i < count; ++i) {
      EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[size_t(i)], nullptr);
      const std::string why = tryDisplay(d, options, attempt);
      if (why.empty()) return true;
      failures += " device " + std::to_string(i) + ": " + why + ";";
    }
    return false;
  };
  auto trySurfaceless = [&]() {
    if (!hasSurfaceless) return false;
    EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    const std::string why = tryDisplay(d, options, attempt);
    if (why.empty()) return true;
    failures += " surfaceless: " + why + ";";
    return false;
  };
  const char* platformEnv = std::getenv("EGL_PLATFORM");
  const bool surfacelessFirst = platformEnv && std::string_view(platformEnv) == "surfaceless";
  bool ok = false;
  if (surfacelessFirst) {
    if ((ok = trySurfaceless()))
      info_.platform = "surfaceless";
    else if ((ok = tryDevices()))
      info_.platform = "device";
  } else {
    if ((ok = tryDevices()))
      info_.platform = "device";
    else if ((ok = trySurfaceless()))
      info_.platform = "surfaceless";
  }
  if (!ok) throw Error("GlContext: no headless OpenGL 4.5 core context could be created:" + failures);
  display_ = attempt.display;
  context_ = attempt.context;

  info_ = describeCurrentContext(info_.platform);
  if (options.debugOutput) enableDebugOutput();
  while (glGetError() != GL_NO_ERROR) {
  }
}

GlContext::~GlContext() {
  if (display_) {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display_, context_);
    eglTerminate(display_);
    eglReleaseThread();
  }
}

void GlContext::makeCurrent() const {
  if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
    throw Error("GlContext::makeCurrent: eglMakeCurrent failed (" + eglErrorText() + ")");
}

GlContextInfo describeCurrentContext(const std::string& platform) {
  GlContextInfo info;
  info.platform = platform;
  auto str = [](GLenum name) {
    const auto* s = reinterpret_cast<const char*>(glGetString(name));
    return std::string(s ? s : "");
  };
  info.vendor = str(GL_VENDOR);
  info.renderer = str(GL_RENDERER);
  info.version = str(GL_VERSION);
  glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &info.max3DTextureSize);
  glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &info.maxTextureBufferTexels);
  if (epoxy_has_gl_extension("GL_NVX_gpu_memory_info")) {
    GLint kib = 0;
    glGetIntegerv(GL_GPU_MEMORY_INFO_TOTAL_AVAILABLE_MEMORY_NVX, &kib);
    if (kib > 0) info.totalGpuMemoryBytes = uint64_t(kib) * 1024;
  } else if (epoxy_has_gl_extension("GL_ATI_meminfo")) {
    GLint kib[4] = {};
    glGetIntegerv(GL_TEXTURE_FREE_MEMORY_ATI, kib);
    if (kib[0] > 0) info.totalGpuMemoryBytes = uint64_t(kib[0]) * 1024;
  }
  return info;
}

void enableDebugOutput() {
  glEnable(GL_DEBUG_OUTPUT);
  glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
  glDebugMessageCallback(debugCallback, nullptr);
}

void checkGlError(const char* where) {
  const GLenum e = glGetError();
  if (e == GL_NO_ERROR) return;
  while (glGetError() != GL_NO_ERROR) {
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, "GL error 0x%04x", unsigned(e));
  throw Error(std::string(where) + ": " + buf);
}

}  // namespace ropecast
