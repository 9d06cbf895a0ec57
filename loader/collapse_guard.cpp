#include "loader/collapse_guard.h"

namespace ropecast {

NodeHint CollapseGuard::filter(const NodeKey& key, NodeHint hint, bool refinedNow) {
  if (hint == NodeHint::Requested) requested_.insert(key);
  const bool collapses = (hint == NodeHint::Occluded || hint == NodeHint::Unused) && refinedNow;
  if (!collapses) return hint;
  const bool keptForTheRays = hint == NodeHint::Unused && requested_.contains(key);
  if (keptForTheRays || !collapsed_.insert(key).second) return NodeHint::Used;
  return hint;
}

void CollapseGuard::reset() {
  collapsed_.clear();
  requested_.clear();
}

}  // namespace ropecast
