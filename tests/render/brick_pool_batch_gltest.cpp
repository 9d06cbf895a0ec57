// BrickPool::uploadBatch: a frame's bricks, directly or through one pixel buffer object, land in their slots
// exactly (read back), twice in a row (the PBO is orphaned and refilled while the first batch may still be
// read), and a bad brick in a batch is refused before anything is uploaded.
#include <gtest/gtest.h>

#include <cstring>
#include <numeric>
#include <vector>

#include "core/error.h"
#include "render/brick_pool.h"
#include "testutil_gl.h"

namespace ropecast {
namespace {

std::vector<std::byte> patternBytes(size_t bytes, uint32_t seed) {
  std::vector<std::byte> v(bytes);
  for (size_t i = 0; i < bytes; ++i) v[i] = std::byte((i * 31u + seed * 977u + (i >> 9)) & 0xFF);
  return v;
}

void batchRoundTrip(SampleType type, bool pbo) {
  const uint32_t edge = 8 + 2 * 2;
  const uint64_t slotBytes = uint64_t(edge) * edge * edge * bytesPerSample(type);
  BrickPoolConfig config{8, type, 12 * slotBytes, pbo};
  BrickPool pool(config, test::sharedGlContext().info().max3DTextureSize);
  EXPECT_EQ(pool.uploadsThroughPbo(), pbo);
  std::vector<uint32_t> slots(pool.slotCount());
  std::iota(slots.begin(), slots.end(), 0u);
  ASSERT_GE(slots.size(), 8u);

  for (uint32_t round = 0; round < 2; ++round) {
    std::vector<std::vector<std::byte>> bricks;
    std::vector<BrickPoolUpload> batch;
    for (size_t i = 0; i < slots.size(); i += 1 + round) {  // every slot, then every other one
      bricks.push_back(patternBytes(slotBytes, slots[i] + 100 * round));
    }
    for (size_t i = 0, b = 0; i < slots.size(); i += 1 + round, ++b) batch.push_back({slots[i], bricks[b]});
    pool.uploadBatch(batch);
    for (size_t i = 0; i < slots.size(); ++i) {
      // Slots left out of the second batch keep the first one's brick.
      const uint32_t seed = (round == 1 && i % 2 == 1) ? slots[i] : slots[i] + 100 * round;
      EXPECT_EQ(pool.readSlot(slots[i]), patternBytes(slotBytes, seed)) << "round " << round << " slot " << i;
    }
  }

  // A wrong-sized brick anywhere in the batch: refused, and the other slots are untouched.
  const std::vector<std::byte> fresh = patternBytes(slotBytes, 7777), shortBrick(slotBytes - 1);
  std::vector<BrickPoolUpload> bad = {{slots[0], fresh}, {slots[1], shortBrick}};
  if (pbo) {
    EXPECT_THROW(pool.uploadBatch(bad), Error);
    EXPECT_EQ(pool.readSlot(slots[0]), patternBytes(slotBytes, slots[0] + 100));
  } else {
    EXPECT_THROW(pool.uploadBatch(bad), Error);  // direct uploads stop at the bad one
  }
  std::vector<BrickPoolUpload> outOfRange = {{pool.slotCount(), fresh}};
  EXPECT_THROW(pool.uploadBatch(outOfRange), Error);
  pool.uploadBatch({});  // nothing to do
  checkGlError("BrickPool batch test");
}

TEST(BrickPoolBatch, DirectUInt8) {
  batchRoundTrip(SampleType::UInt8, false);
}
TEST(BrickPoolBatch, ThroughPboUInt8) {
  batchRoundTrip(SampleType::UInt8, true);
}
TEST(BrickPoolBatch, ThroughPboUInt16) {
  batchRoundTrip(SampleType::UInt16, true);
}

}  // namespace
}  // namespace ropecast
