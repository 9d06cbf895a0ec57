// GpuTimer: GPU time of a span of GL commands (the frame's raycast_ms, occlusion_draw_ms).
// begin()/end() bracket the commands with GL_TIMESTAMP queries; elapsedMs() waits for the results. Some
// drivers report timestamps that cannot be right (llvmpipe stamps per rasterizer thread, so a span can read
// as hours): a GPU span longer than the wall time from begin() to the result is replaced by that wall time,
// which bounds it from above because elapsedMs() waits for the GPU. On llvmpipe/softpipe the stamps can
// also read far too short (a piece of the work), so there begin() and end() drain the pipeline and the wall
// time between them is always reported (so spans may nest or follow one another, as on a GPU).
// usedWallClock() says which one was reported. Owns two GL query objects: render thread
// only, with the GlContext current.
#pragma once

#include <chrono>
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
  // Milliseconds between begin() and end() on the GPU; blocks until the results are available (the first call
  // after end() also glFinish()es, so the wall-clock bound is tight). Throws ropecast::Error when no span has
  // been measured.
  double elapsedMs();
  bool usedWallClock() const { return usedWallClock_; }

 private:
  uint32_t queries_[2] = {0, 0};
  bool running_ = false;
  bool measured_ = false;
  bool resolved_ = false;
  double resolvedMs_ = 0.0;
  bool usedWallClock_ = false;
  bool softwareRenderer_ = false;  // llvmpipe/softpipe: timestamps are not trustworthy, use the wall clock
  std::chrono::steady_clock::time_point wallBegin_{};
  std::chrono::steady_clock::time_point wallEnd_{};  // software renderers: where end() drained
};

}  // namespace ropecast
