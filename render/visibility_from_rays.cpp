#include "render/visibility_from_rays.h"

namespace ropecast {

void markVisibilityFromRays(std::span<const NodeKey> dataLeaves, const RayFeedback& rays,
                            const CollapseGuard& collapses, uint64_t frame, VisibilityTracker& visibility) {
  for (const NodeKey& leaf : dataLeaves) {
    if (rays.hint(leaf, frame) == NodeHint::Unused)
      visibility.markUnseen(leaf, frame);
    else if (rays.hitByRays(leaf, frame) && !collapses.collapsed(leaf))
      visibility.markHit(leaf, rays.answeredFrame());
  }
}

}  // namespace ropecast
