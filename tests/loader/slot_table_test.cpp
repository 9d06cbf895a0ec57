// GPU slot assignment: free slots first, then demoted ones, then least recently used; slots of the cut being
// built never reused.
#include "loader/slot_table.h"

#include <random>
#include <set>

#include <gtest/gtest.h>

#include "core/error.h"

namespace ropecast {
namespace {

NodeKey key(uint32_t i) {
  return {3, {i, 0, 0}};
}

TEST(SlotTable, HandsOutFreeSlotsFirstThenTheLeastRecentlyUsed) {
  SlotTable t(3);
  EXPECT_EQ(t.acquire(key(0)), 0u);
  EXPECT_EQ(t.acquire(key(1)), 1u);
  EXPECT_EQ(t.acquire(key(2)), 2u);
  EXPECT_EQ(t.acquire(key(3)), std::nullopt);  // all pinned by this cut
  EXPECT_EQ(t.availableCount(), 0u);

  t.beginCut();
  EXPECT_EQ(t.availableCount(), 3u);
  EXPECT_EQ(t.occupiedCount(), 3u);
  // Keep key(0) in the new cut; unpin key(1) after using it, so key(2) is now the least recently used.
  t.pin(*t.find(key(0)));
  t.pin(*t.find(key(1)));
  t.unpin(*t.find(key(1)));
  const auto s = t.acquire(key(9));
  ASSERT_TRUE(s);
  EXPECT_EQ(*s, 2u);
  EXPECT_FALSE(t.find(key(2)));  // forgotten
  EXPECT_EQ(t.keyOf(2), key(9));
  EXPECT_EQ(t.find(key(9)), 2u);
  // Only key(1)'s slot is left to reuse; key(0)'s is pinned.
  EXPECT_EQ(t.acquire(key(10)), 1u);
  EXPECT_EQ(t.acquire(key(11)), std::nullopt);
  EXPECT_TRUE(t.find(key(0)));
}

// Random cuts over 41 keys in 16 slots; with marks, random touches before each cut and demotions after its
// start. Whatever the order of reuse, a slot of the cut being built is never handed out again.
void expectNoPinnedSlotReused(uint32_t seed, bool withMarks) {
  std::mt19937 rng(seed);
  SlotTable t(16);
  const auto randomSlot = [&] { return t.find(key(std::uniform_int_distribution<uint32_t>(0, 40)(rng))); };
  for (int frame = 0; frame < 200; ++frame) {
    for (int i = 0; withMarks && i < 3; ++i)
      if (const auto s = randomSlot()) t.touch(*s);
    t.beginCut();
    for (int i = 0; withMarks && i < 3; ++i)
      if (const auto s = randomSlot()) t.demote(*s);
    std::set<uint32_t> cut;
    const int wanted = std::uniform_int_distribution<int>(1, 20)(rng);
    for (int i = 0; i < wanted; ++i) {
      const NodeKey k = key(std::uniform_int_distribution<uint32_t>(0, 40)(rng));
      if (const auto s = t.find(k)) {
        t.pin(*s);
        cut.insert(*s);
        continue;
      }
      const auto s = t.acquire(k);
      if (!s) {
        EXPECT_EQ(t.pinnedCount(), 16u);
        continue;
      }
      EXPECT_FALSE(cut.count(*s)) << "slot " << *s << " reused inside its cut";
      cut.insert(*s);
    }
    EXPECT_EQ(t.pinnedCount(), cut.size());
    EXPECT_LE(t.occupiedCount(), 16u);
    for (uint32_t s : cut) EXPECT_TRUE(t.isPinned(s));
  }
}

TEST(SlotTable, NeverReusesAPinnedSlotUnderRandomUse) {
  expectNoPinnedSlotReused(7, /*withMarks=*/false);
}

TEST(SlotTable, NeverReusesAPinnedSlotWithRandomTouchesAndDemotions) {
  expectNoPinnedSlotReused(5, /*withMarks=*/true);
}

TEST(SlotTable, RejectsAnEmptyPool) {
  EXPECT_THROW(SlotTable(0), Error);
}

TEST(SlotTable, TouchedSlotsAreReusedLastAndTheirEvictionsCounted) {
  SlotTable t(6);
  for (uint32_t i = 0; i < 4; ++i) t.acquire(key(i));
  t.beginCut();  // recency now key(3) (least) .. key(0) (most): the reverse of the order they were pinned
  t.acquire(key(4));
  t.acquire(key(5));  // the two free slots first
  t.beginCut();
  t.pin(*t.find(key(4)));
  t.pin(*t.find(key(5)));
  // The next cut: the rays used key(0) and key(4), unpinned and pinned.
  t.touch(*t.find(key(0)));
  t.touch(*t.find(key(4)));
  t.beginCut();  // least .. most: key(3), key(2), key(1), key(5) (last cut), key(0), key(4) (touched)
  EXPECT_EQ(t.keyOf(*t.acquire(key(10))), key(10));
  EXPECT_FALSE(t.find(key(3)));
  t.acquire(key(11));
  t.acquire(key(12));
  EXPECT_FALSE(t.find(key(2)));
  EXPECT_FALSE(t.find(key(1)));
  t.acquire(key(13));
  EXPECT_FALSE(t.find(key(5)));
  EXPECT_EQ(t.usedEvictions(), 0u);
  t.acquire(key(14));
  EXPECT_FALSE(t.find(key(0)));
  EXPECT_EQ(t.usedEvictions(), 1u);
  t.acquire(key(15));
  EXPECT_FALSE(t.find(key(4)));
  EXPECT_EQ(t.usedEvictions(), 2u);

  // A mark holds for the one cut after the touch.
  t.touch(*t.find(key(15)));
  t.beginCut();
  t.beginCut();
  for (uint32_t i = 20; i < 26; ++i) t.acquire(key(i));
  EXPECT_EQ(t.usedEvictions(), 2u);
}

TEST(SlotTable, ReusesTheLastCutsLowestPrioritySlotsFirst) {
  // A cut pinned by priority: key(0) first, key(3) last. The next refinement keeps key(0) and key(1) and
  // needs a new brick: it takes key(3)'s slot, the one it would reach last, not key(2)'s.
  SlotTable t(4);
  for (uint32_t i = 0; i < 4; ++i) t.acquire(key(i));
  t.beginCut();
  t.pin(*t.find(key(0)));
  t.pin(*t.find(key(1)));
  t.acquire(key(10));
  EXPECT_FALSE(t.find(key(3)));
  EXPECT_TRUE(t.find(key(2)));
}

TEST(SlotTable, DemotedSlotsAreReusedAfterTheFreeOnesBeforeOlderOnes) {
  SlotTable t(6);
  for (uint32_t i = 0; i < 4; ++i) t.acquire(key(i));
  t.beginCut();  // the first tree, all four
  t.pin(*t.find(key(0)));
  t.beginCut();  // key(1..3) left the tree a cut ago: recency key(3) (least), key(2), key(1), then key(0)
  t.demote(*t.find(key(1)));
  EXPECT_EQ(t.acquire(key(10)), 4u);  // free slots still come first
  EXPECT_EQ(t.acquire(key(11)), 5u);
  EXPECT_EQ(t.acquire(key(12)), 1u);  // the demoted brick, before the older key(3) and key(2)
  EXPECT_FALSE(t.find(key(1)));
  EXPECT_TRUE(t.find(key(3)));
  t.acquire(key(13));
  EXPECT_FALSE(t.find(key(3)));  // then least recently used again
  EXPECT_TRUE(t.find(key(2)));
  EXPECT_TRUE(t.find(key(0)));
}

TEST(SlotTable, DemoteLeavesPinnedUsedAndLastTreeSlotsAlone) {
  SlotTable t(4);
  for (uint32_t i = 0; i < 4; ++i) t.acquire(key(i));
  t.beginCut();
  t.pin(*t.find(key(2)));
  t.pin(*t.find(key(3)));
  t.touch(*t.find(key(1)));
  t.beginCut();  // key(0), key(1) left the tree; key(2), key(3) were in it: recency 0, 3, 2, 1 (touched)
  t.pin(*t.find(key(0)));
  t.demote(*t.find(key(0)));  // pinned: in the cut being built
  EXPECT_TRUE(t.isPinned(*t.find(key(0))));
  t.demote(*t.find(key(1)));  // the rays used it: use wins
  t.demote(*t.find(key(2)));  // in the last tree: the refinement may pin it again
  // Reuse order unchanged by the demotions: key(3), key(2), then the touched key(1).
  t.acquire(key(10));
  EXPECT_FALSE(t.find(key(3)));
  t.acquire(key(11));
  EXPECT_FALSE(t.find(key(2)));
  t.acquire(key(12));
  EXPECT_FALSE(t.find(key(1)));
  EXPECT_EQ(t.acquire(key(13)), std::nullopt);
  EXPECT_TRUE(t.find(key(0)));
  EXPECT_EQ(t.usedEvictions(), 1u);

  // Once a whole cut has passed without it in the tree, key(0) can be demoted.
  t.beginCut();
  t.pin(*t.find(key(10)));
  t.pin(*t.find(key(12)));
  t.beginCut();  // recency key(11), key(0), key(12), key(10)
  t.demote(*t.find(key(0)));
  t.acquire(key(14));
  EXPECT_FALSE(t.find(key(0)));
  EXPECT_TRUE(t.find(key(11)));
}

}  // namespace
}  // namespace ropecast
