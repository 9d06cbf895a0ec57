// BrickCache: the CPU-side level-2 cache of decompressed bricks, keyed by node, evicted least recently used
// first so that it never holds more than its bytes budget. Bricks are shared, immutable buffers: a brick
// handed to the renderer for upload stays alive after eviction until the renderer drops it.
//
// Owned by the WorkingSet. Not thread-safe: only the thread that drives the WorkingSet (the render thread)
// calls it; I/O workers hand their bricks over through the IoQueue, never into the cache directly.
#pragma once

#include <cstddef>
#include <cstdint>
#include <list>
#include <memory>
#include <unordered_map>
#include <utility>
#include <vector>

#include "loader/brick_memory.h"
#include "store/octree_layout.h"

namespace ropecast {

// Bricks' memory (loader/brick_memory.h), whose bytes a vector sized with it leaves uninitialized: a brick is
// written whole by whoever makes it (a reader decompresses into it), and clearing it first would touch every
// page twice.
template <class T>
struct BrickAllocator {
  using value_type = T;
  BrickAllocator() = default;
  template <class U>
  BrickAllocator(const BrickAllocator<U>&) noexcept {}
  T* allocate(size_t n) { return static_cast<T*>(brick_memory::allocate(n * sizeof(T))); }
  void deallocate(T* p, size_t n) noexcept { brick_memory::deallocate(p, n * sizeof(T)); }
  template <class U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;  // default-initialized: no value written
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
  template <class U>
  bool operator==(const BrickAllocator<U>&) const noexcept {
    return true;
  }
};

using BrickBytes = std::vector<std::byte, BrickAllocator<std::byte>>;
using SharedBrick = std::shared_ptr<const BrickBytes>;

class BrickCache {
 public:
  // Throws ropecast::Error when budgetBytes cannot hold even one brick of brickBytes.
  BrickCache(uint64_t budgetBytes, uint64_t brickBytes);

  // The brick if cached (and marks it most recently used), else nullptr.
  SharedBrick get(const NodeKey& key);
  bool contains(const NodeKey& key) const { return entries_.count(key) != 0; }
  // Adds or replaces the brick as most recently used, evicting least recently used bricks to stay in budget.
  // A brick larger than the whole budget is not kept.
  void put(const NodeKey& key, SharedBrick brick);
  void erase(const NodeKey& key);

  uint64_t bytes() const { return bytes_; }
  uint64_t budgetBytes() const { return budgetBytes_; }
  size_t size() const { return entries_.size(); }
  uint64_t evictions() const { return evictions_; }
  // Keys from most to least recently used (for tests and debugging).
  std::vector<NodeKey> keysByRecency() const;

 private:
  struct Entry {
    SharedBrick brick;
    std::list<NodeKey>::iterator position;  // in recency_, front = most recent
  };
  void evictToFit(uint64_t incomingBytes);

  uint64_t budgetBytes_;
  uint64_t bytes_ = 0;
  uint64_t evictions_ = 0;
  std::list<NodeKey> recency_;
  std::unordered_map<NodeKey, Entry, NodeKeyHash> entries_;
};

}  // namespace ropecast
