#include "loader/slot_table.h"

#include "core/error.h"

namespace ropecast {

SlotTable::SlotTable(uint32_t slotCount) : slots_(slotCount) {
  if (slotCount == 0)
    throw Error("SlotTable: the GPU pool must have at least one slot (--gpu-budget too small)");
  for (uint32_t s = 0; s < slotCount; ++s) linkAtMostRecent(s);
}

void SlotTable::beginCut() {
  for (uint32_t s : usedSlots_) slots_[s].used = false;
  usedSlots_.clear();
  for (uint32_t s : lastTreeSlots_) slots_[s].inLastTree = false;
  lastTreeSlots_.clear();
  for (uint32_t s : pinnedSlots_) {
    if (!slots_[s].pinned) continue;
    unpin(s);
    slots_[s].inLastTree = true;
    lastTreeSlots_.push_back(s);
  }
  pinnedSlots_.clear();
}

std::optional<uint32_t> SlotTable::find(const NodeKey& key) const {
  const auto it = bySlotKey_.find(key);
  if (it == bySlotKey_.end()) return std::nullopt;
  return it->second;
}

void SlotTable::pin(uint32_t slot) {
  Slot& s = slots_.at(slot);
  if (s.pinned) return;
  unlink(slot);
  s.pinned = true;
  ++pinnedCount_;
  pinnedSlots_.push_back(slot);
}

void SlotTable::touch(uint32_t slot) {
  Slot& s = slots_.at(slot);
  if (!s.occupied) return;
  if (!s.used) usedSlots_.push_back(slot);
  s.used = true;
  if (s.pinned) return;
  unlink(slot);
  linkAtMostRecent(slot);
}

void SlotTable::demote(uint32_t slot) {
  const Slot& s = slots_.at(slot);
  if (!s.occupied || s.pinned || s.used || s.inLastTree) return;
  unlink(slot);
  linkAfterFree(slot);
}

void SlotTable::unpin(uint32_t slot) {
  Slot& s = slots_.at(slot);
  if (!s.pinned) return;
  s.pinned = false;
  --pinnedCount_;
  linkAtMostRecent(slot);
}

std::optional<uint32_t> SlotTable::acquire(const NodeKey& key) {
  if (leastRecent_ == kNone) return std::nullopt;
  const uint32_t slot = leastRecent_;
  Slot& s = slots_[slot];
  if (s.occupied) bySlotKey_.erase(s.key);
  if (s.used) ++usedEvictions_;
  s.used = false;
  s.inLastTree = false;
  s.key = key;
  s.occupied = true;
  bySlotKey_[key] = slot;
  pin(slot);
  return slot;
}

std::optional<NodeKey> SlotTable::keyOf(uint32_t slot) const {
  const Slot& s = slots_.at(slot);
  if (!s.occupied) return std::nullopt;
  return s.key;
}

void SlotTable::linkAtMostRecent(uint32_t slot) {
  Slot& s = slots_[slot];
  s.prev = mostRecent_;
  s.next = kNone;
  if (mostRecent_ != kNone) slots_[mostRecent_].next = slot;
  mostRecent_ = slot;
  if (leastRecent_ == kNone) leastRecent_ = slot;
}

void SlotTable::linkAfterFree(uint32_t slot) {
  // Free slots are taken in slot order from the least recent end and never come back, so while any is left
  // the last slot is the last free one.
  const uint32_t lastFree = slots_.back().occupied ? kNone : slotCount() - 1;
  Slot& s = slots_[slot];
  s.prev = lastFree;
  s.next = lastFree == kNone ? leastRecent_ : slots_[lastFree].next;
  if (s.next != kNone)
    slots_[s.next].prev = slot;
  else
    mostRecent_ = slot;
  if (lastFree != kNone)
    slots_[lastFree].next = slot;
  else
    leastRecent_ = slot;
}

void SlotTable::unlink(uint32_t slot) {
  Slot& s = slots_[slot];
  if (s.prev != kNone)
    slots_[s.prev].next = s.next;
  else
    leastRecent_ = s.next;
  if (s.next != kNone)
    slots_[s.next].prev = s.prev;
  else
    mostRecent_ = s.prev;
  s.prev = s.next = kNone;
}

}  // namespace ropecast
