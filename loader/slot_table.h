// SlotTable: which brick each slot of the GPU brick pool holds, and which slot to give the next brick. The
// pool itself (one 3D texture of slots) belongs to render/; this table only decides. Slots whose brick is in
// the tree being built (the cut and the inner nodes above it) are pinned and never reused; the others are
// reused least recently used first, free slots before any of them. A brick that left the cut keeps its slot
// until it is reused, so it comes back without an upload. Recency is by use when the rays' feedback is known
// (touch): bricks the rays used are reused last (Crassin et al. 2009). Bricks of nodes that stay occluded
// are reused first, right after the free slots (demote; Gobbetti et al. 2008, Sect. 6).
//
// Owned by the WorkingSet. Not thread-safe: the render thread only.
#pragma once

#include <cstdint>
#include <optional>
#include <unordered_map>
#include <vector>

#include "store/octree_layout.h"

namespace ropecast {

class SlotTable {
 public:
  explicit SlotTable(uint32_t slotCount);

  // Starts a new cut: every slot is unpinned (the previous cut's bricks become the most recently used ones)
  // and the marks of touch() are cleared.
  void beginCut();
  // The rays used the slot's brick in the latest answered frame: an unpinned slot becomes the most recently
  // used; a pinned one is marked too (it becomes the most recent when unpinned). Reusing a marked slot in
  // this cut counts as a used eviction. Call after beginCut(), before the cut's acquires.
  void touch(uint32_t slot);
  // The slot's node stays occluded (the latest answered occlusion queries): an unpinned slot becomes the
  // next one reused, after the free slots. Left alone: a pinned slot (it is in the cut being built), a slot
  // touch() marked in this cut (the rays used it: use wins), and a slot of the previous cut's tree (the
  // refinement, which pins the tree again from the root down, would likely ask for it after reusing it; it
  // is demoted in the next cut if it left this one). Call after beginCut() and touch(), before the cut's
  // acquires.
  void demote(uint32_t slot);

  std::optional<uint32_t> find(const NodeKey& key) const;
  // Pins a slot holding a brick of the cut being built (idempotent).
  void pin(uint32_t slot);
  // The node left the cut being built (it was refined): its slot may be reused, most recently used.
  void unpin(uint32_t slot);
  bool isPinned(uint32_t slot) const { return slots_[slot].pinned; }

  // A slot for `key`: a free one, else the least recently used unpinned one (its brick is forgotten).
  // The slot comes back pinned. nullopt when every slot is pinned. `key` must not already hold a slot.
  std::optional<uint32_t> acquire(const NodeKey& key);

  uint32_t slotCount() const { return uint32_t(slots_.size()); }
  uint32_t pinnedCount() const { return pinnedCount_; }
  // Slots acquire() could still hand out in this cut.
  uint32_t availableCount() const { return slotCount() - pinnedCount_; }
  // Slots holding a brick (pinned or kept for reuse).
  uint32_t occupiedCount() const { return uint32_t(bySlotKey_.size()); }
  std::optional<NodeKey> keyOf(uint32_t slot) const;
  // Bricks marked by touch() that acquire() gave away, since construction.
  uint64_t usedEvictions() const { return usedEvictions_; }

 private:
  static constexpr uint32_t kNone = UINT32_MAX;
  struct Slot {
    NodeKey key;
    bool occupied = false;
    bool pinned = false;
    bool used = false;                    // touched in this cut
    bool inLastTree = false;              // pinned in the previous cut
    uint32_t prev = kNone, next = kNone;  // in the reuse list while unpinned
  };
  void linkAtMostRecent(uint32_t slot);
  void linkAfterFree(uint32_t slot);
  void unlink(uint32_t slot);

  std::vector<Slot> slots_;
  std::unordered_map<NodeKey, uint32_t, NodeKeyHash> bySlotKey_;
  // Unpinned slots: free ones sit at the least recent end so they are taken first, demoted ones next.
  uint32_t leastRecent_ = kNone, mostRecent_ = kNone;
  std::vector<uint32_t> pinnedSlots_;
  std::vector<uint32_t> lastTreeSlots_;  // pinned in the previous cut
  uint32_t pinnedCount_ = 0;
  std::vector<uint32_t> usedSlots_;  // marked by touch() in this cut
  uint64_t usedEvictions_ = 0;
};

}  // namespace ropecast
