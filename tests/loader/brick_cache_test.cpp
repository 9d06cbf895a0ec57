// CPU cache: LRU order, bytes budget never exceeded, bricks in use outlive eviction.
#include "loader/brick_cache.h"

#include <random>

#include <gtest/gtest.h>

#include "core/error.h"

namespace ropecast {
namespace {

NodeKey cacheKey(uint32_t i) {
  return {2, {i, 1, 0}};
}
SharedBrick brick(size_t bytes) {
  return std::make_shared<BrickBytes>(bytes);
}

TEST(BrickCache, EvictsTheLeastRecentlyUsed) {
  BrickCache c(300, 100);
  c.put(cacheKey(0), brick(100));
  c.put(cacheKey(1), brick(100));
  c.put(cacheKey(2), brick(100));
  EXPECT_EQ(c.bytes(), 300u);
  EXPECT_TRUE(c.get(cacheKey(0)));  // cacheKey(1) is now the least recent
  c.put(cacheKey(3), brick(100));
  EXPECT_FALSE(c.contains(cacheKey(1)));
  EXPECT_TRUE(c.contains(cacheKey(0)));
  EXPECT_EQ(c.keysByRecency(), (std::vector<NodeKey>{cacheKey(3), cacheKey(0), cacheKey(2)}));
  EXPECT_EQ(c.evictions(), 1u);
  EXPECT_EQ(c.get(cacheKey(1)), nullptr);
}

TEST(BrickCache, NeverExceedsItsBudget) {
  std::mt19937 rng(3);
  BrickCache c(1000, 64);
  for (int i = 0; i < 2000; ++i) {
    const NodeKey k = cacheKey(std::uniform_int_distribution<uint32_t>(0, 50)(rng));
    if (rng() % 3 == 0) {
      c.get(k);
    } else {
      c.put(k, brick(std::uniform_int_distribution<size_t>(1, 300)(rng)));
    }
    ASSERT_LE(c.bytes(), 1000u);
  }
  uint64_t sum = 0;
  for (const NodeKey& k : c.keysByRecency()) sum += c.get(k)->size();
  EXPECT_EQ(sum, c.bytes());
}

TEST(BrickCache, ABrickInUseOutlivesItsEviction) {
  BrickCache c(100, 100);
  SharedBrick held = brick(100);
  (*std::const_pointer_cast<BrickBytes>(held))[0] = std::byte{42};
  c.put(cacheKey(0), held);
  c.put(cacheKey(1), brick(100));
  EXPECT_FALSE(c.contains(cacheKey(0)));
  EXPECT_EQ((*held)[0], std::byte{42});
  EXPECT_EQ(held.use_count(), 1);
}

TEST(BrickCache, RejectsABudgetSmallerThanABrick) {
  try {
    BrickCache c(10, 100);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("--cpu-cache"), std::string::npos);
  }
}

}  // namespace
}  // namespace ropecast
