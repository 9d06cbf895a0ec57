#include "render/step_pacer.h"

#include <algorithm>

namespace ropecast {

StepPacer::StepPacer(double targetFrameMs) : targetFrameMs_(targetFrameMs) {}

void StepPacer::record(double frameMs, double raycastMs) {
  if (!enabled() || !(raycastMs > 0.0)) return;
  // What the rest of the frame leaves to the ray cast; never less than a quarter of the target, so that a
  // frame whose loading alone overruns does not send the step to its maximum.
  const double rest = std::max(frameMs - raycastMs, 0.0);
  const double raycastBudget = std::max(targetFrameMs_ - rest, 0.25 * targetFrameMs_);
  const double cost = raycastMs * scale_;
  const double rise = lastCostAtScale1_ > 0.0 ? std::max(cost - lastCostAtScale1_, 0.0) : 0.0;
  lastCostAtScale1_ = cost;
  const double wanted = std::clamp((cost + rise) / raycastBudget, 1.0, kMaxScale);
  scale_ = wanted >= scale_ ? wanted : scale_ + kRecoveryRate * (wanted - scale_);
}

}  // namespace ropecast
