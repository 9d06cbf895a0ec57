// The figures the progress lines and summaries print: byte counts in a readable unit, durations.
#include "tools/progress_bar.h"

#include <gtest/gtest.h>

namespace ropecast::tools {
namespace {

TEST(ProgressFormat, BytesInTheLargestUnitWithAWholeNumberInFront) {
  EXPECT_EQ(formatBytes(0), "0 B");
  EXPECT_EQ(formatBytes(900), "900 B");
  EXPECT_EQ(formatBytes(1023), "1023 B");
  EXPECT_EQ(formatBytes(1024), "1.0 KiB");
  EXPECT_EQ(formatBytes(12595), "12.3 KiB");
  EXPECT_EQ(formatBytes(uint64_t(45) << 19), "22.5 MiB");
  EXPECT_EQ(formatBytes(uint64_t(3) << 30), "3.0 GiB");
  EXPECT_EQ(formatBytes(uint64_t(5) << 50), "5120.0 TiB");
}

TEST(ProgressFormat, DurationsAsMinutesAndSeconds) {
  EXPECT_EQ(formatDuration(0.0), "0:00");
  EXPECT_EQ(formatDuration(245.4), "4:05");
  EXPECT_EQ(formatDuration(3723.0), "1:02:03");
  EXPECT_EQ(formatDuration(-3.0), "0:00");
}

}  // namespace
}  // namespace ropecast::tools
