// Test helpers for the working-set loader tests: a BrickSource over a hand-made octree whose node kinds and
// min/max come from a function, whose bricks are a pattern derived from the node key, and which counts reads,
// can hold reads behind a gate, and can fail chosen reads. Any thread (reads are thread-safe).
#pragma once

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstring>
#include <functional>
#include <mutex>
#include <set>
#include <tuple>
#include <vector>

#include "core/error.h"
#include "loader/refiner.h"
#include "store/brick_source.h"

namespace ropecast::testing {

inline uint8_t patternByte(const NodeKey& k, size_t i) {
  return uint8_t(NodeKeyHash{}(k) + i * 7u);
}

class FakeBrickSource final : public BrickSource {
 public:
  using NodeFn = std::function<NodeInfo(const NodeKey&)>;

  FakeBrickSource(glm::u32vec3 dims, uint32_t brickSize, NodeFn nodeFn = {},
                  glm::dvec3 spacing = glm::dvec3(1.0))
      : nodeFn_(std::move(nodeFn)) {
    info_.layout = OctreeLayout::forVolume(dims, brickSize);
    info_.volume.dims = dims;
    info_.volume.spacing = spacing;
    info_.volume.type = SampleType::UInt8;
    info_.storedType = SampleType::UInt8;
  }

  const BrickSourceInfo& info() const override { return info_; }

  NodeInfo node(const NodeKey& key) const override {
    if (!info_.layout.isInside(key)) return {};
    if (nodeFn_) return nodeFn_(key);
    return {NodeKind::Data, 0, 255};
  }

  void readBrick(const NodeKey& key, std::span<std::byte> out) const override {
    {
      std::unique_lock lock(mutex_);
      readOrder_.push_back(key);
      gateCv_.wait(lock, [&] { return gateOpen_; });
    }
    ++reads_;
    if (failing_.load() && key == failKey_) throw Error("FakeBrickSource: injected failure");
    const NodeInfo n = node(key);
    for (size_t i = 0; i < out.size(); ++i) {
      out[i] = std::byte(n.kind == NodeKind::Constant ? uint8_t(n.minValue) : patternByte(key, i));
    }
  }

  void setGate(bool open) {
    {
      std::lock_guard lock(mutex_);
      gateOpen_ = open;
    }
    gateCv_.notify_all();
  }
  void failOn(const NodeKey& key) {
    failKey_ = key;
    failing_ = true;
  }
  uint64_t reads() const { return reads_.load(); }
  std::vector<NodeKey> readOrder() const {
    std::lock_guard lock(mutex_);
    return readOrder_;
  }

 private:
  BrickSourceInfo info_;
  NodeFn nodeFn_;
  mutable std::mutex mutex_;
  mutable std::condition_variable gateCv_;
  mutable std::vector<NodeKey> readOrder_;
  bool gateOpen_ = true;
  mutable std::atomic<uint64_t> reads_{0};
  NodeKey failKey_;
  std::atomic<bool> failing_{false};
};

inline auto keyTuple(const NodeKey& k) {
  return std::make_tuple(k.depth, k.coord.x, k.coord.y, k.coord.z);
}

struct KeyLess {
  bool operator()(const NodeKey& a, const NodeKey& b) const { return keyTuple(a) < keyTuple(b); }
};

// True when the leaves tile the root cube exactly: no leaf is an ancestor of another, and their volumes
// (in finest-level cells) add up to the cube.
inline bool isFullTiling(const std::vector<PlannedLeaf>& leaves, uint32_t maxDepth) {
  std::set<NodeKey, KeyLess> keys;
  for (const PlannedLeaf& l : leaves) {
    if (!keys.insert(l.key).second) return false;  // twice
  }
  uint64_t cells = 0;
  for (const PlannedLeaf& l : leaves) {
    if (l.key.depth > maxDepth) return false;
    NodeKey k = l.key;
    while (k.depth > 0) {
      k = k.parent();
      if (keys.count(k)) return false;
    }
    cells += uint64_t(1) << (3 * (maxDepth - l.key.depth));
  }
  return cells == uint64_t(1) << (3 * maxDepth);
}

}  // namespace ropecast::testing
