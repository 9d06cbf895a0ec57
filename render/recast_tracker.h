// RecastTracker: what a frame that casts only what changed (FrameRequest::recastChangesOnly,
// docs/RENDERING.md "Recasting what changed") needs to know of the frame whose image the ray-cast pass's
// targets hold: its leaves, and the rays' answer about it, which stands in for the rays a partial frame does
// not cast. For each frame cast in part with feedback it keeps the answer carried over (RecastPlan::keptIn,
// keptWhole) until that frame's readback arrives, and adds it there.
//
// Plain CPU state, owned by FrameRenderer: render thread only.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <unordered_set>
#include <vector>

#include "loader/refiner.h"
#include "render/feedback_buffer.h"
#include "render/recast_plan.h"

namespace ropecast {

class RecastTracker {
 public:
  // The targets hold no frame's image (the warm-up draw, a multi-pass frame).
  void forget() { holdsImage_ = false; }
  // Frame `frame` was cast, whole or in part, over `leaves`. `redraw`: it drew the converged image again
  // (the same view and cut, cast without feedback), about which the answer about the frame before stands.
  void drew(uint64_t frame, const std::vector<PlannedLeaf>& leaves, bool redraw);

  // A readback arrived: the answer carried over for its frame, if it was cast in part, is added to its lists
  // (each leaf once). Before RayFeedback::answer.
  void addCarried(FeedbackReadback& readback);
  // RayFeedback took `readback`: kept when it is the answer about the frame the targets hold and came back
  // whole (nothing dropped).
  void heard(const FeedbackReadback& readback);

  // The pixels frame `frame`'s `leaves` needs cast over the held image, seen as `view` says (its drawn and
  // leaves fields are filled here); nullopt when all of them (no image held, a changed box holds the eye, or
  // with `castFeedback` no whole answer about the held frame). The caller has checked that `view` is the
  // held frame's view. With `castFeedback`, the answer to carry over is kept for `frame`.
  std::optional<RecastPlan> plan(RecastInput view, const std::vector<PlannedLeaf>& leaves, uint64_t frame,
                                 bool castFeedback);

 private:
  struct Answer {
    bool valid = false;
    std::unordered_set<NodeKey, NodeKeyHash> used, requested, hit, any;
  };
  struct Carried {
    uint64_t frame = 0;
    std::vector<uint32_t> used, requested, hit;  // indices into that frame's cut
  };

  bool holdsImage_ = false;
  uint64_t frame_ = 0;  // the frame the targets hold
  DrawnLeaves leaves_;
  std::vector<NodeKey> keys_;  // its leaves in its cut's order
  Answer answer_;              // about frame_
  std::deque<Carried> carried_;
};

}  // namespace ropecast
