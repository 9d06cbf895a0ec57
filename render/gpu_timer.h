// GpuTimer: GPU time of a span of GL commands through GL_TIME_ELAPSED queries (the frame's raycast_ms).
// begin()/end() bracket the commands; elapsedMs() waits for the result. Spans may not nest (GL allows one
// GL_TIME_ELAPSED query at a time). Owns a GL query object: render thread only, with the GlContext current.
#pragma once

#include <cstdint>

namespace ropecast {

class GpuTimer {
 public:
  GpuTimer();
  ~GpuTimer();
  GpuTimer(const GpuTimer&) = delete;
  GpuTimer& operator=(const GpuTimer&) = delete;

  void begin();
  void end();
  // Milliseconds between begin() and end() on the GPU; blocks until the query result is available. Throws
  // ropecast::Error when no span has been measured.
  double elapsedMs() const;

 private:
  uint32_t query_ = 0;
  bool running_ = false;
  bool measured_ = false;
};

}  // namespace ropecast
