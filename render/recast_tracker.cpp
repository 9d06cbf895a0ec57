#include "render/recast_tracker.h"

#include <algorithm>

namespace ropecast {

void RecastTracker::drew(uint64_t frame, const std::vector<PlannedLeaf>& leaves, bool redraw) {
  holdsImage_ = true;
  frame_ = frame;
  leaves_.clear();
  keys_.clear();
  keys_.reserve(leaves.size());
  for (const PlannedLeaf& leaf : leaves) {
    leaves_[leaf.key] = drawnSlotOf(leaf);
    keys_.push_back(leaf.key);
  }
  // The answer about this frame is still to come, but for a frame that draws the converged image again: the
  // answer about the frame before is what its rays would say.
  if (!redraw) answer_.valid = false;
}

void RecastTracker::addCarried(FeedbackReadback& readback) {
  while (!carried_.empty() && carried_.front().frame < readback.frame) carried_.pop_front();
  if (carried_.empty() || carried_.front().frame != readback.frame) return;
  const Carried& carried = carried_.front();
  const auto add = [](std::vector<uint32_t>& to, const std::vector<uint32_t>& from) {
    to.insert(to.end(), from.begin(), from.end());
    std::sort(to.begin(), to.end());  // a leaf both the cast rays and the carried answer list, once
    to.erase(std::unique(to.begin(), to.end()), to.end());
  };
  add(readback.usedLeaves, carried.used);
  add(readback.requestedLeaves, carried.requested);
  add(readback.hitLeaves, carried.hit);
  carried_.pop_front();
}

void RecastTracker::heard(const FeedbackReadback& readback) {
  if (!holdsImage_ || readback.frame != frame_) return;
  answer_ = {};
  answer_.valid = readback.usedDropped + readback.requestedDropped + readback.hitDropped == 0;
  if (!answer_.valid) return;
  const auto add = [this](const std::vector<uint32_t>& leaves, std::unordered_set<NodeKey, NodeKeyHash>& to) {
    for (const uint32_t i : leaves)
      if (i < keys_.size()) {
        to.insert(keys_[i]);
        answer_.any.insert(keys_[i]);
      }
  };
  add(readback.usedLeaves, answer_.used);
  add(readback.requestedLeaves, answer_.requested);
  add(readback.hitLeaves, answer_.hit);
}

std::optional<RecastPlan> RecastTracker::plan(RecastInput view, const std::vector<PlannedLeaf>& leaves,
                                              uint64_t frame, bool castFeedback) {
  if (!holdsImage_) return std::nullopt;
  // The rays not cast answer as they did about the held frame: that answer must be at hand, and whole.
  if (castFeedback && !answer_.valid) return std::nullopt;
  view.drawn = &leaves_;
  view.leaves = &leaves;
  view.answered = castFeedback ? &answer_.any : nullptr;
  RecastPlan recast = planRecast(view);
  if (recast.whole) return std::nullopt;
  if (castFeedback) {
    Carried& carried = carried_.emplace_back();
    carried.frame = frame;
    for (const uint32_t i : recast.keptIn) {
      if (answer_.used.contains(leaves[i].key)) carried.used.push_back(i);
      if (answer_.requested.contains(leaves[i].key)) carried.requested.push_back(i);
    }
    for (const uint32_t i : recast.keptWhole)
      if (answer_.hit.contains(leaves[i].key)) carried.hit.push_back(i);
  }
  return recast;
}

}  // namespace ropecast
