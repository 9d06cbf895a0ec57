#include "occlusion/visibility_tracker.h"

#include <algorithm>

namespace ropecast {

VisibilityTracker::VisibilityTracker(const VisibilityConfig& config) : config_(config) {}

bool VisibilityTracker::occludedAt(const NodeKey& key, uint64_t frame) const {
  const auto it = marks_.find(key);
  return it != marks_.end() && occludedBy(key, it->second, frame);
}

bool VisibilityTracker::occludedBy(const NodeKey& key, const Mark& mark, uint64_t frame) const {
  if (!mark.occluded || !live(mark, frame)) return false;
  return !unqueryable_.contains(key);  // nearEye: its projection says nothing, so it is visible
}

void VisibilityTracker::finishRound() {
  lastRoundFrames_ = roundFrames_;
  if (!rounds_.empty()) rounds_.back().finished = true;
  dropAnsweredRounds();
  roundQueried_.clear();
  roundFrames_ = 0;
}

FrameQueryPlan VisibilityTracker::plan(uint64_t frame, uint32_t width, uint32_t height,
                                       std::span<const LeafToQuery> leaves) {
  if (dropAll_) {
    firstValidFrame_ = frame;
    dropAll_ = false;
  }
  lastPlanFrame_ = frame;
  // Bounded memory: an expired mark says the same as no mark.
  std::erase_if(marks_, [&](const auto& entry) { return !live(entry.second, frame); });

  lastLeaves_.clear();
  unqueryable_.clear();
  std::vector<uint32_t> queryable;
  for (uint32_t i = 0; i < leaves.size(); ++i) {
    const LeafToQuery& leaf = leaves[i];
    lastLeaves_.push_back(leaf.key);
    if (leaf.projection.nearEye || leaf.projection.rect.empty()) {
      unqueryable_.insert(leaf.key);
      marks_.erase(leaf.key);
    } else if (!leaf.hitByRays) {
      queryable.push_back(i);
    }
  }

  // The round forgets leaves that left the cut; new leaves of the cut join it unqueried.
  std::unordered_set<NodeKey, NodeKeyHash> stillInCut;
  std::vector<QueryCandidate> candidates;
  for (uint32_t i : queryable) {
    if (roundQueried_.contains(leaves[i].key))
      stillInCut.insert(leaves[i].key);
    else
      candidates.push_back({i, leaves[i].projection.rect});
  }
  roundQueried_.swap(stillInCut);
  if (candidates.empty() && !queryable.empty()) {  // the cut shrank to leaves already queried in this round
    finishRound();
    for (uint32_t i : queryable) candidates.push_back({i, leaves[i].projection.rect});
  }

  const TilePlan tiles = planTiles(width, height, candidates, config_.tiles, frame);
  FrameQueryPlan result;
  result.tiles = tiles.tiles;
  result.queries.reserve(tiles.queried.size());
  for (uint32_t i : tiles.queried) {
    result.queries.push_back(leaves[i].key);
    result.queriedIndices.push_back(i);
    roundQueried_.insert(leaves[i].key);
  }
  nothingToQueryFrame_.reset();
  if (queryable.empty()) nothingToQueryFrame_ = frame;
  if (!queryable.empty()) {
    if (roundFrames_ == 0) rounds_.push_back({frame, frame, 0, 0, false});
    rounds_.back().lastFrame = frame;
    rounds_.back().issued += result.queries.size();
    ++roundFrames_;
    if (roundQueried_.size() == queryable.size()) finishRound();
  }
  return result;
}

void VisibilityTracker::answer(const NodeKey& key, uint64_t issuedFrame, uint64_t samplesPassed) {
  if (dropAll_ || issuedFrame < firstValidFrame_) return;  // asked before reset(), about another image
  countAnswer(issuedFrame);
  setMark(key, issuedFrame, samplesPassed);
}

void VisibilityTracker::renew(uint64_t frame) {
  lastPlanFrame_ = frame;
  for (auto& [key, mark] : marks_)
    if (live(mark, frame)) mark.issuedFrame = std::max(mark.issuedFrame, frame);
}

void VisibilityTracker::markUnseen(const NodeKey& key, uint64_t frame) {
  setMark(key, frame, 0);
}

void VisibilityTracker::markHit(const NodeKey& key, uint64_t frame) {
  setMark(key, frame, config_.thresholdPixels);
}

void VisibilityTracker::setMark(const NodeKey& key, uint64_t issuedFrame, uint64_t samplesPassed) {
  const auto [it, inserted] = marks_.try_emplace(key);
  if (!inserted && issuedFrame < it->second.issuedFrame) return;  // an older answer than the one held
  it->second = {issuedFrame, samplesPassed < config_.thresholdPixels, samplesPassed};
}

void VisibilityTracker::countAnswer(uint64_t issuedFrame) {
  for (RoundAnswers& r : rounds_) {
    if (issuedFrame >= r.firstFrame && issuedFrame <= r.lastFrame) {
      ++r.answered;
      break;
    }
  }
  dropAnsweredRounds();
}

void VisibilityTracker::dropAnsweredRounds() {
  std::erase_if(rounds_, [this](const RoundAnswers& r) {
    if (!r.finished || r.answered < r.issued) return false;
    answeredRoundFrame_ = std::max(answeredRoundFrame_.value_or(0), r.firstFrame);
    return true;
  });
  // Answers that never come (queries the renderer stopped collecting) must not hold memory forever.
  constexpr size_t kMaxRounds = 64;
  if (rounds_.size() > kMaxRounds) rounds_.erase(rounds_.begin(), rounds_.end() - kMaxRounds);
}

bool VisibilityTracker::answeredSince(uint64_t frame) const {
  if (nothingToQueryFrame_ && *nothingToQueryFrame_ >= frame) return true;
  return answeredRoundFrame_ && *answeredRoundFrame_ >= frame;
}

void VisibilityTracker::propagate(std::span<const NodeKey> nonEmptyLeaves) {
  // Per inner node: the visible samples of its leaves (an unanswered leaf counts the threshold: visible) and
  // the oldest answer among them.
  std::unordered_map<NodeKey, Mark, NodeKeyHash> inner;
  for (const NodeKey& leaf : nonEmptyLeaves) {
    Mark m;
    m.issuedFrame = UINT64_MAX;
    m.samples = config_.thresholdPixels;
    if (const auto it = marks_.find(leaf);
        it != marks_.end() && live(it->second, lastPlanFrame_) && !unqueryable_.contains(leaf)) {
      m.issuedFrame = it->second.issuedFrame;
      m.samples = it->second.samples;
    }
    for (NodeKey k = leaf; k.depth > 0;) {
      k = k.parent();
      auto [it, inserted] = inner.try_emplace(k, Mark{UINT64_MAX, false, 0});
      it->second.samples += m.samples;
      it->second.issuedFrame = std::min(it->second.issuedFrame, m.issuedFrame);
    }
  }
  for (auto& [key, mark] : inner) {
    mark.occluded = mark.samples < config_.thresholdPixels;
    if (mark.occluded)
      marks_[key] = mark;
    else
      marks_.erase(key);
  }
}

bool VisibilityTracker::isOccluded(const NodeKey& key, uint64_t frame) const {
  return occludedAt(key, frame);
}

void VisibilityTracker::occludedNodes(uint64_t frame, std::vector<NodeKey>& out) const {
  out.clear();
  for (const auto& [key, mark] : marks_) {
    if (occludedBy(key, mark, frame)) out.push_back(key);
  }
}

VisibilityCounts VisibilityTracker::counts(uint64_t frame) const {
  VisibilityCounts c;
  for (const NodeKey& key : lastLeaves_) ++(occludedAt(key, frame) ? c.occluded : c.visible);
  return c;
}

void VisibilityTracker::reset() {
  marks_.clear();
  roundQueried_.clear();
  roundFrames_ = 0;
  lastRoundFrames_ = 0;
  rounds_.clear();
  answeredRoundFrame_.reset();
  nothingToQueryFrame_.reset();
  dropAll_ = true;
}

}  // namespace ropecast
