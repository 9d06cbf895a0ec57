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

  // The rays used the slot's brick in the latest answered frame. Call before beginCut(), for the cut about to
  // be built: the slot is marked, and beginCut() makes it more recent than every unmarked one. Reusing a
  // marked slot in that cut counts as a used eviction.
  void touch(uint32_t slot);
  // Starts a new cut: the last cut's slots are unpinned and become the most recently used ones, in reverse
  // order of pinning, and the slots touch() marked become more recent still (those of the last cut again in
  // reverse order of pinning). The refinement pins by priority, so what it reuses first is what it would give
  // up first: a slot the new refinement will reach later still holds a brick it needs, and reusing it would
  // cost an upload and then another slot, and so on down the tree.
  void beginCut();
  // The slot's node stays occluded (the latest answered occlusion queries): an unpinned slot becomes the
  // next one reused, after the free slots. Left alone: a pinned slot (it is in the cut being built), a slot
  // touch() marked in this cut (the rays used it: use wins), and a slot of the previous cut's tree (the
  // refinement, which pins the tree again from the root down, would likely ask for it after reusing it; it
  // is demoted in the next cut if it left this one). Call after beginCut(), before the cut's acquires.
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
    uint64_t usedInCut = 0;               // the cut touch() marked it for
    uint64_t pinnedInCut = 0;             // the last cut that pinned it
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
  uint32_t pinnedCount_ = 0;
  uint64_t cut_ = 1;                    // the cut being built, counted by beginCut()
  std::vector<uint32_t> touchedSlots_;  // marked by touch() for the next cut
  uint64_t usedEvictions_ = 0;
};

}  // namespace ropecast
