#include "render/visibility_from_rays.h"

namespace ropecast {

void markVisibilityFromRays(std::span<const NodeKey> dataLeaves, const RayFeedback& rays,
                            const CollapseGuard& collapses, uint64_t frame, VisibilityTracker& visibility) {
  for (const NodeKey& leaf : dataLeaves) {
    const NodeHint hint = rays.hint(leaf, frame);
    if (hint == NodeHint::Unused) {
      visibility.markUnseen(leaf, frame);
      continue;
    }
    if (collapses.collapsed(leaf)) continue;
    if (hint == NodeHint::Used || hint == NodeHint::Requested) visibility.markSeen(leaf);
    if (rays.hitByRays(leaf, frame)) visibility.markHit(leaf, rays.answeredFrame());
  }
}

}  // namespace ropecast
