#include "render/gpu_timer.h"

#include <cstring>

#include <epoxy/gl.h>

#include "core/error.h"

namespace ropecast {

GpuTimer::GpuTimer() {
  glCreateQueries(GL_TIMESTAMP, 2, queries_);
  // llvmpipe (and softpipe) run a draw when its scene is flushed, on several threads, and their timestamps
  // then bound a piece of the work, not the span (a small fraction of a long ray cast): time them by the wall
  // clock, from a drained pipeline to glFinish.
  const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  softwareRenderer_ = renderer && (std::strstr(renderer, "llvmpipe") || std::strstr(renderer, "softpipe"));
}

GpuTimer::~GpuTimer() {
  if (queries_[0]) glDeleteQueries(2, queries_);
}

void GpuTimer::begin() {
  if (running_) throw Error("GpuTimer::begin: a span is already running");
  if (softwareRenderer_) glFinish();  // earlier commands are not this span's
  wallBegin_ = std::chrono::steady_clock::now();
  glQueryCounter(queries_[0], GL_TIMESTAMP);
  running_ = true;
  resolved_ = false;
}

void GpuTimer::end() {
  if (!running_) throw Error("GpuTimer::end: no span is running");
  glQueryCounter(queries_[1], GL_TIMESTAMP);
  if (softwareRenderer_) {
    glFinish();
    wallEnd_ = std::chrono::steady_clock::now();
  }
  running_ = false;
  measured_ = true;
}

double GpuTimer::elapsedMs() {
  if (!measured_ || running_) throw Error("GpuTimer::elapsedMs: no completed span to report");
  if (resolved_) return resolvedMs_;
  glFinish();
  const auto wallEnd = softwareRenderer_ ? wallEnd_ : std::chrono::steady_clock::now();
  const double wallMs = std::chrono::duration<double, std::milli>(wallEnd - wallBegin_).count();
  GLuint64 stamps[2] = {0, 0};
  glGetQueryObjectui64v(queries_[0], GL_QUERY_RESULT, &stamps[0]);
  glGetQueryObjectui64v(queries_[1], GL_QUERY_RESULT, &stamps[1]);
  const double gpuMs = stamps[1] >= stamps[0] ? double(stamps[1] - stamps[0]) * 1e-6 : -1.0;
  usedWallClock_ = softwareRenderer_ || !(gpuMs >= 0.0 && gpuMs <= wallMs);
  resolvedMs_ = usedWallClock_ ? wallMs : gpuMs;
  resolved_ = true;
  return resolvedMs_;
}

}  // namespace ropecast
