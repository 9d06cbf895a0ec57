// Bricks' memory: blocks of a size are distinct, aligned and writable; a freed block is the next one handed
// out of its size, without a new chunk; a size's chunks go back when its last block does; small blocks and,
// under AddressSanitizer, all of them come from operator new; threads allocating and freeing at once never
// get one block twice.
#include "loader/brick_memory.h"

#include <algorithm>
#include <barrier>
#include <cstdint>
#include <cstring>
#include <set>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace ropecast {
namespace {

constexpr size_t kBrickBytes = 34 * 34 * 34 * 2;  // a 32^3 brick with its borders, 16 bits a sample

TEST(BrickMemory, BlocksAreDistinctAlignedAndWritable) {
  std::vector<void*> blocks;
  for (int i = 0; i < 600; ++i) {  // more than one chunk's worth
    void* p = brick_memory::allocate(kBrickBytes);
    ASSERT_NE(p, nullptr);
    EXPECT_EQ(reinterpret_cast<uintptr_t>(p) % 64, 0u);
    std::memset(p, i & 0xFF, kBrickBytes);
    blocks.push_back(p);
  }
  std::vector<uintptr_t> starts;
  for (void* p : blocks) starts.push_back(reinterpret_cast<uintptr_t>(p));
  std::sort(starts.begin(), starts.end());
  for (size_t i = 1; i < starts.size(); ++i) EXPECT_GE(starts[i] - starts[i - 1], kBrickBytes);
  for (size_t i = 0; i < blocks.size(); ++i)
    EXPECT_EQ(static_cast<unsigned char*>(blocks[i])[kBrickBytes - 1], i & 0xFF) << "block " << i;
  for (void* p : blocks) brick_memory::deallocate(p, kBrickBytes);
}

TEST(BrickMemory, AFreedBlockIsReusedWithoutANewChunk) {
  void* kept = brick_memory::allocate(kBrickBytes + 64);  // the size stays in use throughout
  void* first = brick_memory::allocate(kBrickBytes + 64);
  brick_memory::deallocate(first, kBrickBytes + 64);
  const size_t chunks = brick_memory::mappedChunks();
  std::vector<void*> again;
  for (int i = 0; i < 100; ++i) {
    again.push_back(brick_memory::allocate(kBrickBytes + 64));
    brick_memory::deallocate(again.back(), kBrickBytes + 64);
  }
  if (brick_memory::kChunked) {
    for (void* p : again) EXPECT_EQ(p, first);  // the freed block, each time
    EXPECT_EQ(brick_memory::mappedChunks(), chunks);
  } else {
    EXPECT_EQ(brick_memory::mappedChunks(), 0u);  // AddressSanitizer: operator new, never a chunk
  }
  brick_memory::deallocate(kept, kBrickBytes + 64);
}

TEST(BrickMemory, ASizeWhoseLastBlockIsFreedGivesItsChunksBack) {
  const size_t before = brick_memory::mappedChunks();
  std::vector<void*> blocks;
  for (int i = 0; i < 600; ++i) blocks.push_back(brick_memory::allocate(kBrickBytes + 128));
  // 600 blocks of 78 KiB take two chunks of 32 MiB.
  EXPECT_EQ(brick_memory::mappedChunks(), before + (brick_memory::kChunked ? 2u : 0u));
  for (size_t i = 0; i + 1 < blocks.size(); ++i) brick_memory::deallocate(blocks[i], kBrickBytes + 128);
  EXPECT_EQ(brick_memory::mappedChunks(), before + (brick_memory::kChunked ? 2u : 0u));  // one still lives
  brick_memory::deallocate(blocks.back(), kBrickBytes + 128);
  EXPECT_EQ(brick_memory::mappedChunks(), before);
  // The size can be used again.
  void* p = brick_memory::allocate(kBrickBytes + 128);
  std::memset(p, 1, kBrickBytes + 128);
  brick_memory::deallocate(p, kBrickBytes + 128);
  EXPECT_EQ(brick_memory::mappedChunks(), before);
}

TEST(BrickMemory, SmallBlocksComeFromOperatorNew) {
  const size_t chunks = brick_memory::mappedChunks();
  std::vector<void*> blocks;
  for (int i = 0; i < 1000; ++i) blocks.push_back(brick_memory::allocate(brick_memory::kMinBlockBytes - 1));
  EXPECT_EQ(brick_memory::mappedChunks(), chunks);
  for (void* p : blocks) brick_memory::deallocate(p, brick_memory::kMinBlockBytes - 1);
}

TEST(BrickMemory, ThreadsAllocatingAndFreeingAtOnceNeverShareABlock) {
  constexpr int kThreads = 4, kRounds = 2000;
  std::vector<std::thread> threads;
  std::vector<std::vector<uintptr_t>> seen(kThreads);
  std::barrier allHolding(kThreads);
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([t, &seen, &allHolding] {
      std::vector<void*> held;
      for (int r = 0; r < kRounds; ++r) {
        void* p = brick_memory::allocate(kBrickBytes);
        std::memset(p, t, 64);
        held.push_back(p);
        if (held.size() > 8) {  // free the oldest: blocks move between threads' hands
          EXPECT_EQ(*static_cast<unsigned char*>(held.front()), t);
          brick_memory::deallocate(held.front(), kBrickBytes);
          held.erase(held.begin());
        }
      }
      for (void* p : held) seen[t].push_back(reinterpret_cast<uintptr_t>(p));
      allHolding.arrive_and_wait();  // no thread frees its last blocks before all have listed theirs
      for (void* p : held) brick_memory::deallocate(p, kBrickBytes);
    });
  }
  for (std::thread& th : threads) th.join();
  // Each thread wrote its number into the blocks it held and found it there before freeing them; the blocks
  // all held at once at the end were distinct.
  std::set<uintptr_t> all;
  for (const auto& s : seen)
    for (uintptr_t p : s) EXPECT_TRUE(all.insert(p).second);
}

}  // namespace
}  // namespace ropecast
