// The coarse value histogram (store/value_histogram.h): it counts exactly the root brick's samples inside the
// data, each once, in the bins of their data values.
#include <numeric>

#include <gtest/gtest.h>

#include "store/procedural_bricks.h"
#include "store/value_histogram.h"

namespace ropecast {
namespace {

uint64_t total(const ValueHistogram& h) {
  return std::accumulate(h.counts.begin(), h.counts.end(), uint64_t(0));
}

TEST(ValueHistogram, CountsTheRootLevelSamplesInsideTheData) {
  // 40^3 in bricks of 16: a root cube of 64, maxDepth 2; level 2 has ceil(40 / 4) = 10 samples per axis.
  const auto bricks = openProceduralBricks("procedural:sphere:40", 16);
  const ValueHistogram h = coarseHistogram(*bricks, 32, 0.0, 255.0);
  EXPECT_EQ(h.level, 2u);
  ASSERT_EQ(h.counts.size(), 32u);
  EXPECT_EQ(total(h), 1000u);
}

TEST(ValueHistogram, ValuesOutsideTheRangeLandInTheEndBins) {
  const auto bricks = openProceduralBricks("procedural:sphere:32", 16);
  const ValueHistogram h = coarseHistogram(*bricks, 4, 1000.0, 2000.0);  // every value lies below
  EXPECT_EQ(total(h), 16u * 16u * 16u);
  EXPECT_EQ(h.counts[0], total(h));
}

}  // namespace
}  // namespace ropecast
