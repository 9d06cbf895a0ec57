#include "loader/slot_table.h"

#include "core/error.h"

namespace ropecast {

SlotTable::SlotTable(uint32_t slotCount) : slots_(slotCount) {
  if (slotCount == 0) throw Error("SlotTable: the GPU pool must have at least one slot");
  for (uint32_t s = 0; s < slotCount; ++s) linkAtMostRecent(s);
}

void SlotTable::beginCut() {
  ++cut_;
  const auto unpinLastCut = [&](bool marked) {
    for (auto it = pinnedSlots_.rbegin(); it != pinnedSlots_.rend(); ++it)
      if (slots_[*it].pinned && (slots_[*it].usedInCut == cut_) == marked) unpin(*it);
  };
  unpinLastCut(false);
  for (uint32_t s : touchedSlots_) {
    if (slots_[s].pinned || slots_[s].usedInCut != cut_) continue;
    unlink(s);
    linkAtMostRecent(s);
  }
  unpinLastCut(true);
  pinnedSlots_.clear();
  touchedSlots_.clear();
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
  s.pinnedInCut = cut_;
  ++pinnedCount_;
  pinnedSlots_.push_back(slot);
}

void SlotTable::touch(uint32_t slot) {
  Slot& s = slots_.at(slot);
  if (!s.occupied) return;
  s.usedInCut = cut_ + 1;
  touchedSlots_.push_back(slot);
}

void SlotTable::demote(uint32_t slot) {
  const Slot& s = slots_.at(slot);
  if (!s.occupied || s.pinned || s.usedInCut == cut_ || (s.pinnedInCut != 0 && s.pinnedInCut + 1 == cut_))
    return;
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
  if (s.usedInCut == cut_) ++usedEvictions_;
  s.usedInCut = 0;
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
