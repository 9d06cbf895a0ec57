// The streaming converter: progress reporting, memory bounded independently of nz, determinism across worker
// counts, options.
#include "store/converter.h"

#include <gtest/gtest.h>

#include <string>

#include "store/store.h"
#include "store/verify.h"
#include "tests/common/temp_dir.h"
#include "tests/store/store_test_util.h"

namespace ropecast {
namespace {

using testing::TempDir;

ArraySource ballSource(glm::u32vec3 dims) {
  return ArraySource::fromSamples<uint16_t>(
      testing::volumeInfo(dims, SampleType::UInt16),
      testing::toType<uint16_t>(testing::ballField(dims, 12), 0, 30000));
}

TEST(Converter, ReportsMonotonicProgressUpToTheTotal) {
  TempDir dir;
  ArraySource source = ballSource({50, 40, 90});
  ConvertOptions options;
  options.brickSize = 8;
  std::vector<ConvertProgress> seen;
  options.progress = [&](const ConvertProgress& p) { seen.push_back(p); };
  convertVolume(source, dir / "p.store", options);
  ASSERT_FALSE(seen.empty());
  for (size_t i = 1; i < seen.size(); ++i) EXPECT_GT(seen[i].slicesDone, seen[i - 1].slicesDone);
  EXPECT_EQ(seen.back().slicesDone, 90u);
  EXPECT_EQ(seen.back().slicesTotal, 90u);
  EXPECT_EQ(seen.back().bytesDone, source.bytes().size());
  EXPECT_EQ(seen.back().phase, ConvertProgress::Phase::Bricks);  // uint16: no range pre-pass
}

TEST(Converter, BufferedMemoryDoesNotGrowWithDepth) {
  TempDir dir;
  ConvertOptions options;
  options.brickSize = 8;
  options.workerThreads = 2;
  ArraySource shallow = ballSource({64, 48, 40});
  ArraySource deep = ballSource({64, 48, 400});
  const ConvertStats a = convertVolume(shallow, dir / "a.store", options);
  const ConvertStats b = convertVolume(deep, dir / "b.store", options);
  EXPECT_GT(b.nodes, 5 * a.nodes);
  // Windows of B + 2*border (+1 for the filter) slices per level, whatever nz is (the deeper volume has more,
  // ever smaller, levels: a few percent more).
  EXPECT_LE(b.peakWindowBytes, a.peakWindowBytes * 21 / 20);
  const uint64_t sliceBytes = 64 * 48 * 2;
  EXPECT_LE(b.peakWindowBytes, (8 + 2 * kBrickBorder + 2) * sliceBytes * 4 / 3);
  EXPECT_GE(b.peakWindowBytes, (8 + 2 * kBrickBorder) * sliceBytes);
  EXPECT_LE(b.readBufferBytes, (size_t(16) << 20) + sliceBytes);
  EXPECT_EQ(b.brickQueueBytes, 4 * 2 * 12 * 12 * 12 * 2u);  // 4 bricks per worker
  EXPECT_EQ(b.reorderBytes, a.reorderBytes);                // as many compressed ones, whatever nz is
  EXPECT_LE(b.reorderBytes, b.brickQueueBytes * 11 / 10);
}

// The payloads go into the file in node order whichever worker compresses them first: the same input and
// options give the same bytes, with one worker or several, run after run.
TEST(Converter, SameFileWithOneOrSeveralWorkers) {
  TempDir dir;
  ArraySource source = ballSource({45, 37, 29});
  ConvertOptions options;
  options.brickSize = 8;
  options.workerThreads = 1;
  convertVolume(source, dir / "one.store", options);
  const std::string one = test::readBytes(dir / "one.store");
  for (int run = 0; run < 3; ++run) {
    options.workerThreads = 3 + run;
    convertVolume(source, dir / "several.store", options);
    EXPECT_TRUE(test::readBytes(dir / "several.store") == one) << options.workerThreads << " workers";
  }
  EXPECT_TRUE(verifyStore(*Store::open(dir / "several.store")).ok());
}

TEST(Converter, HigherZstdLevelCompressesAtLeastAsWell) {
  TempDir dir;
  ArraySource source = ballSource({45, 37, 29});
  ConvertOptions options;
  options.brickSize = 8;
  options.zstdLevel = 1;
  const ConvertStats fast = convertVolume(source, dir / "fast.store", options);
  options.zstdLevel = 15;
  const ConvertStats small = convertVolume(source, dir / "small.store", options);
  EXPECT_GT(fast.payloadBytes, 0u);
  EXPECT_LT(small.payloadBytes, fast.payloadBytes);
  EXPECT_EQ(Store::open(dir / "small.store")->metadata().zstdLevel, 15);
}

}  // namespace
}  // namespace ropecast
