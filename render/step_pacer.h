// StepPacer: `ropecast render --target-frame-ms MS`, the adaptive sample distance of an interactive volume
// renderer (VTK's AutoAdjustSampleDistances does the same): when a frame took longer than the target, the
// next frames sample at a larger step; when there is time to spare, the step returns toward the requested
// --step. The ray cast's cost is close to proportional to its number of samples, 1 / step, so the scale that
// meets the target is (ray-cast ms at scale 1) / (target - the rest of the frame). That cost is predicted for
// the next frame from the last two (a camera closing in makes it rise frame after frame, and a look back only
// would be one frame late), by extrapolating rises, never falls. The scale follows a slower frame at once and
// a faster one gradually, so a view that alternates does not make the step oscillate. The working set, and so
// the loader, does not depend on it.
//
// Plain state, no clock: the renderer measures and records. Owned by the render thread.
#pragma once

namespace ropecast {

class StepPacer {
 public:
  static constexpr double kMaxScale = 4.0;       // the step grows to 4x --step at most
  static constexpr double kRecoveryRate = 0.25;  // share of the way back toward a smaller scale per frame

  // targetFrameMs <= 0: off (scale() stays 1).
  explicit StepPacer(double targetFrameMs);

  bool enabled() const { return targetFrameMs_ > 0.0; }
  // The factor for the next frame's --step, in [1, kMaxScale].
  double scale() const { return scale_; }
  // A frame rendered at scale(): its whole time and its ray cast's share.
  void record(double frameMs, double raycastMs);

 private:
  double targetFrameMs_;
  double scale_ = 1.0;
  double lastCostAtScale1_ = 0.0;  // ray-cast ms of the last frame, at scale 1; 0 before any
};

}  // namespace ropecast
