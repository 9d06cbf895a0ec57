// UploadPacer: turns the per-frame upload time budget (`--upload-time-budget MS`) into a byte budget the
// loader can plan with. The loader decides every upload before the renderer makes one (a frame's cut refers
// to the slots it fills, so an upload cannot be cut short halfway), so the time budget is enforced ahead of
// time: from the upload throughput measured in earlier frames, allowanceBytes() is how many bytes fit in the
// budget. The estimate is deliberately pessimistic: it follows a slower frame at once and a faster one only
// slowly, and before any measurement it allows one brick.
//
// Plain state, no I/O, no clock: the renderer measures and records. Owned by the render thread.
#pragma once

#include <cstdint>

namespace ropecast {

class UploadPacer {
 public:
  // timeBudgetMs <= 0: no time budget (allowanceBytes() is unlimited). brickBytes: the smallest useful
  // allowance (refinement must always be able to make progress).
  UploadPacer(double timeBudgetMs, uint64_t brickBytes);

  bool enabled() const { return timeBudgetMs_ > 0.0; }
  double timeBudgetMs() const { return timeBudgetMs_; }
  // Bytes this frame's uploads may take: the budget times the estimated throughput, at least one brick.
  uint64_t allowanceBytes() const;
  // One frame's uploads: `bytes` took `ms` (ignored when nothing was uploaded).
  void record(uint64_t bytes, double ms);
  // The current estimate, bytes per millisecond (0 before any measurement).
  double bytesPerMs() const { return bytesPerMs_; }

 private:
  double timeBudgetMs_;
  uint64_t brickBytes_;
  double bytesPerMs_ = 0.0;
};

}  // namespace ropecast
