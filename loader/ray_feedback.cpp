#include "loader/ray_feedback.h"

#include <algorithm>

namespace ropecast {

void RayFeedback::rememberCut(uint64_t frame, std::vector<NodeKey> leaves, std::vector<uint8_t> dataLeaf) {
  cuts_.push_back({frame, std::move(leaves), std::move(dataLeaf)});
}

bool RayFeedback::answer(uint64_t frame, std::span<const uint32_t> usedLeaves,
                         std::span<const uint32_t> requestedLeaves, std::span<const uint32_t> hitLeaves) {
  while (!cuts_.empty() && cuts_.front().frame < frame) cuts_.pop_front();
  if (cuts_.empty() || cuts_.front().frame != frame) return false;
  const RememberedCut cut = std::move(cuts_.front());
  cuts_.pop_front();

  // Every data leaf of that cut is answered for: unused unless a ray said otherwise.
  std::vector<NodeHint> hints(cut.leaves.size(), NodeHint::Unused);
  usedNodes_.clear();
  for (uint32_t i : usedLeaves) {
    if (i >= cut.leaves.size()) continue;
    hints[i] = NodeHint::Used;
    usedNodes_.push_back(cut.leaves[i]);
  }
  for (uint32_t i : requestedLeaves)
    if (i < cut.leaves.size()) hints[i] = NodeHint::Requested;
  std::vector<bool> hit(cut.leaves.size(), false);
  for (uint32_t i : hitLeaves)
    if (i < cut.leaves.size()) hit[i] = true;
  // Inner nodes above the data leaves: unused when no data leaf below them was used.
  std::unordered_map<NodeKey, bool, NodeKeyHash> innerUsed;
  for (size_t i = 0; i < cut.leaves.size(); ++i) {
    if (!cut.dataLeaf[i]) continue;
    setAnswer(cut.leaves[i], {frame, hints[i], hit[i]});
    const bool used = hints[i] != NodeHint::Unused;
    for (NodeKey k = cut.leaves[i]; k.depth > 0;) {
      k = k.parent();
      const auto [it, inserted] = innerUsed.try_emplace(k, used);
      if (!inserted && (it->second || !used)) break;  // the nodes above already know as much
      it->second = it->second || used;
    }
  }
  for (const auto& [key, used] : innerUsed) setAnswer(key, {frame, used ? NodeHint::Used : NodeHint::Unused});

  // Bounded memory: answers past their lifetime say nothing.
  std::erase_if(answers_, [&](const auto& entry) { return !live(entry.second, frame); });
  answered_ = true;
  answeredFrame_ = frame;
  return true;
}

NodeHint RayFeedback::hint(const NodeKey& key, uint64_t frame, bool innerNodeNow) const {
  const auto it = answers_.find(key);
  const NodeHint answered =
      it == answers_.end() || !live(it->second, frame) ? NodeHint::None : it->second.hint;
  if (answered != NodeHint::Unused && innerNodeNow) return NodeHint::Used;
  return answered;
}

bool RayFeedback::hitByRays(const NodeKey& key, uint64_t frame) const {
  const auto it = answers_.find(key);
  return it != answers_.end() && live(it->second, frame) && it->second.hit;
}

void RayFeedback::setAnswer(const NodeKey& key, NodeAnswer answer) {
  const auto [it, inserted] = answers_.try_emplace(key, answer);
  if (!inserted && it->second.frame <= answer.frame) it->second = answer;  // a renewed answer is newer
}

void RayFeedback::renew(uint64_t frame) {
  for (auto& [key, answer] : answers_)
    if (live(answer, frame)) answer.frame = std::max(answer.frame, frame);
}

void RayFeedback::reset() {
  cuts_.clear();
  answers_.clear();
  usedNodes_.clear();
  answered_ = false;
}

}  // namespace ropecast
