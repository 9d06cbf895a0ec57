// CollapseGuard: which of the hints that would collapse a refined node (NodeHint::Occluded, ::Unused) the
// refiner hears on a still view. A refined node whose leaves are all hidden or unused goes back to a leaf
// (Gobbetti et al. 2008, Sect. 6; Crassin et al. 2009, Sect. 5), but on a still view that can cycle: a node
// refined because it showed hides another's leaves, that one collapses, its coarse data no longer hides the
// first, ...; and a node the rays asked to refine, whose finer data turns out unseen there (filtered data
// shows where the finer data is empty or hidden), would collapse, be asked for again and refine again. So, on
// one view: a node collapses at most once, and the rays' "unused" never collapses a node they requested;
// such a node is ranked NodeHint::Used, as the tree the rays use is, so that a full GPU pool does not give it
// up to requests either. A node the occlusion marks hide collapses once though the rays requested it: its
// own query, drawn part by part, answers for its finer data, and a request for its coarse data does not
// refine it while that answer says hidden (render/visibility_from_rays.h). reset() when the view or the
// emptiness (mode, isovalue, transfer function) changes.
//
// Plain CPU state, owned by the frame renderer: render thread only.
#pragma once

#include <unordered_set>

#include "loader/refiner.h"

namespace ropecast {

class CollapseGuard {
 public:
  // The hint the refiner gets for `key`, given what the answers say (`hint`) and whether `key` is an inner
  // node of the tree on the GPU now (collapsing concerns those only).
  NodeHint filter(const NodeKey& key, NodeHint hint, bool refinedNow);
  // Whether the node collapsed on this view (it is then queried part by part: render/frame_renderer.h).
  bool collapsed(const NodeKey& key) const { return collapsed_.contains(key); }
  void reset();

 private:
  std::unordered_set<NodeKey, NodeKeyHash> collapsed_;
  std::unordered_set<NodeKey, NodeKeyHash> requested_;
};

}  // namespace ropecast
