#include "loader/brick_cache.h"

#include <string>

#include "core/error.h"

namespace ropecast {

BrickCache::BrickCache(uint64_t budgetBytes, uint64_t brickBytes) : budgetBytes_(budgetBytes) {
  if (budgetBytes < brickBytes) {
    throw Error("BrickCache: --cpu-cache " + std::to_string(budgetBytes) +
                " bytes cannot hold one brick of " + std::to_string(brickBytes) + " bytes");
  }
}

SharedBrick BrickCache::get(const NodeKey& key) {
  const auto it = entries_.find(key);
  if (it == entries_.end()) return nullptr;
  recency_.splice(recency_.begin(), recency_, it->second.position);
  return it->second.brick;
}

void BrickCache::put(const NodeKey& key, SharedBrick brick) {
  erase(key);
  const uint64_t size = brick ? brick->size() : 0;
  if (size > budgetBytes_) return;
  evictToFit(size);
  recency_.push_front(key);
  entries_.emplace(key, Entry{std::move(brick), recency_.begin()});
  bytes_ += size;
}

void BrickCache::erase(const NodeKey& key) {
  const auto it = entries_.find(key);
  if (it == entries_.end()) return;
  bytes_ -= it->second.brick ? it->second.brick->size() : 0;
  recency_.erase(it->second.position);
  entries_.erase(it);
}

void BrickCache::evictToFit(uint64_t incomingBytes) {
  while (!recency_.empty() && bytes_ + incomingBytes > budgetBytes_) {
    erase(recency_.back());
    ++evictions_;
  }
}

std::vector<NodeKey> BrickCache::keysByRecency() const {
  return {recency_.begin(), recency_.end()};
}

}  // namespace ropecast
