#include "render/gpu_timer.h"

#include <epoxy/gl.h>

#include "loader/error.h"

namespace ropecast {

GpuTimer::GpuTimer() {
  glCreateQueries(GL_TIME_ELAPSED, 1, &query_);
}

GpuTimer::~GpuTimer() {
  if (query_) glDeleteQueries(1, &query_);
}

void GpuTimer::begin() {
  if (running_) throw Error("GpuTimer::begin: a span is already running");
  glBeginQuery(GL_TIME_ELAPSED, query_);
  running_ = true;
}

void GpuTimer::end() {
  if (!running_) throw Error("GpuTimer::end: no span is running");
  glEndQuery(GL_TIME_ELAPSED);
  running_ = false;
  measured_ = true;
}

double GpuTimer::elapsedMs() const {
  if (!measured_ || running_) throw Error("GpuTimer::elapsedMs: no completed span to report");
  GLuint64 ns = 0;
  glGetQueryObjectui64v(query_, GL_QUERY_RESULT, &ns);
  return double(ns) * 1e-6;
}

}  // namespace ropecast
