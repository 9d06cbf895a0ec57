// UploadPacer: the time budget as bytes from measured throughput; pessimistic, at least one brick.
#include "render/upload_pacer.h"

#include <limits>

#include <gtest/gtest.h>

namespace ropecast {
namespace {

constexpr uint64_t kBrick = 46656;

TEST(UploadPacer, WithoutATimeBudgetAllowsEverything) {
  UploadPacer pacer(0.0, kBrick);
  EXPECT_FALSE(pacer.enabled());
  EXPECT_EQ(pacer.allowanceBytes(), std::numeric_limits<uint64_t>::max());
  pacer.record(10 * kBrick, 100.0);
  EXPECT_EQ(pacer.allowanceBytes(), std::numeric_limits<uint64_t>::max());
}

TEST(UploadPacer, OneBrickBeforeAnyMeasurementThenTheBudgetTimesTheThroughput) {
  UploadPacer pacer(2.0, kBrick);
  EXPECT_TRUE(pacer.enabled());
  EXPECT_EQ(pacer.allowanceBytes(), kBrick);
  pacer.record(0, 5.0);  // a frame without uploads measures nothing
  EXPECT_EQ(pacer.allowanceBytes(), kBrick);
  pacer.record(10 * kBrick, 1.0);  // 10 bricks per ms
  EXPECT_DOUBLE_EQ(pacer.bytesPerMs(), 10.0 * kBrick);
  EXPECT_EQ(pacer.allowanceBytes(), 20 * kBrick);
}

TEST(UploadPacer, FollowsASlowerFrameAtOnceAndAFasterOneSlowly) {
  UploadPacer pacer(1.0, kBrick);
  pacer.record(10 * kBrick, 1.0);
  pacer.record(10 * kBrick, 4.0);  // 2.5 bricks per ms
  EXPECT_EQ(pacer.allowanceBytes(), uint64_t(2.5 * kBrick));
  pacer.record(100 * kBrick, 1.0);  // much faster: a quarter of the way
  const double expected = 2.5 * kBrick + 0.25 * (100.0 - 2.5) * kBrick;
  EXPECT_NEAR(pacer.bytesPerMs(), expected, 1e-6);
  EXPECT_LT(pacer.allowanceBytes(), 100 * kBrick);
  EXPECT_GT(pacer.allowanceBytes(), 2.5 * kBrick);
}

TEST(UploadPacer, NeverLessThanOneBrick) {
  UploadPacer pacer(0.5, kBrick);
  pacer.record(kBrick, 1000.0);  // very slow uploads
  EXPECT_EQ(pacer.allowanceBytes(), kBrick);
  pacer.record(kBrick, 0.0);  // too short to time: counted at the clock's resolution, no division by zero
  EXPECT_GT(pacer.allowanceBytes(), kBrick);
}

}  // namespace
}  // namespace ropecast
