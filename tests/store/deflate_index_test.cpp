// Deflated samples read through access points (store/deflate_index.h, store/file_samples.h): ranges in any
// order equal the data, for gzip and zlib streams of any compression level and for concatenated gzip members;
// a reader after the first starts near its range instead of at the stream's start, and does not inflate to
// the trailer again once it was checked; a trailer that does not match is still refused when inflation
// resumed from a point; a file rewritten since gets a fresh index; readers on two threads share one index.
#include "store/deflate_index.h"

#include <atomic>
#include <chrono>
#include <filesystem>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "store/file_samples.h"
#include "tests/store/store_test_util.h"

namespace ropecast {
namespace {

using testing::deflatedOf;
using testing::TempDir;
using testing::writeFile;

constexpr uint64_t kMiB = uint64_t(1) << 20;

// Bytes that deflate packs in blocks of varied sizes: runs and noise in a narrow range, in tiles of 64 KiB
// (farther apart than deflate's window reaches) each shifted by its index.
std::string compressibleBytes(size_t size, uint32_t seed) {
  std::mt19937 random(seed);
  std::string tile(size_t(1) << 16, '\0');
  for (size_t i = 0; i < tile.size(); ++i)
    tile[i] = char((i / 4096) % 200 + (random() % 8 == 0 ? random() % 40 : 0));
  std::string data(size, '\0');
  for (size_t i = 0; i < size; ++i) data[i] = char(tile[i % tile.size()] + char(i / tile.size()));
  return data;
}

// The samples `bytes` long after `skip` decompressed bytes of the stream at `start`.
std::unique_ptr<FileSamples> samplesOf(const std::string& path, uint64_t start, uint64_t bytes,
                                       uint64_t skip = 0) {
  SampleBlock block;
  block.encoding = SampleEncoding::Deflated;
  block.start = start;
  block.skip = skip;
  block.bytes = bytes;
  block.fileKind = "test file";
  return std::make_unique<FileSamples>(std::make_unique<PosixFile>(path), std::move(block));
}

std::string readRange(FileSamples& samples, uint64_t offset, size_t size) {
  std::string out(size, '\0');
  samples.read(offset, std::as_writable_bytes(std::span(out)));
  return out;
}

// Reads `data` whole, front to back, in slabs (as a conversion does), through a fresh reader.
void readAllInOrder(const std::string& path, uint64_t start, const std::string& data) {
  auto samples = samplesOf(path, start, data.size());
  for (uint64_t at = 0; at < data.size(); at += kMiB) {
    const size_t size = size_t(std::min<uint64_t>(kMiB, data.size() - at));
    ASSERT_EQ(readRange(*samples, at, size), data.substr(at, size)) << "at " << at;
  }
}

std::string errorOfRead(FileSamples& samples, uint64_t offset, size_t size) {
  try {
    readRange(samples, offset, size);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

struct Stream {
  int level;
  bool gzip;
};

class DeflateIndexRead : public ::testing::TestWithParam<Stream> {};

TEST_P(DeflateIndexRead, RangesInAnyOrderEqualTheDataAndStartNearTheirPoint) {
  TempDir dir;
  const std::string data = compressibleBytes(4 * kMiB + 12345, 7);
  const std::string header = "a header of some bytes before the stream";
  const std::string path = dir.file("volume.gz");
  writeFile(path, header + deflatedOf(data, GetParam().level, GetParam().gzip));

  readAllInOrder(path, header.size(), data);
  EXPECT_GE(deflateIndexFor(PosixFile(path), header.size())->pointCount(), 3u);

  // A fresh reader (as the next volume's source is) reads the last half MiB: from the point before it, not
  // from the stream's start, and its end does not inflate to the trailer again.
  auto tail = samplesOf(path, header.size(), data.size());
  const uint64_t last = data.size() - kMiB / 2;
  EXPECT_EQ(readRange(*tail, last, kMiB / 2), data.substr(last));
  EXPECT_LE(tail->inflatedBytes(), 2 * kMiB);

  // Ranges in a shuffled order, some across points, some behind the last read.
  std::mt19937 random(11);
  auto samples = samplesOf(path, header.size(), data.size());
  for (int i = 0; i < 12; ++i) {
    const uint64_t offset = random() % data.size();
    const size_t size = size_t(std::min<uint64_t>(1 + random() % (2 * kMiB), data.size() - offset));
    ASSERT_EQ(readRange(*samples, offset, size), data.substr(offset, size)) << offset << " + " << size;
  }
}

INSTANTIATE_TEST_SUITE_P(Streams, DeflateIndexRead,
                         ::testing::Values(Stream{0, true}, Stream{1, true}, Stream{6, true},
                                           Stream{6, false}, Stream{1, false}),
                         [](const auto& info) {
                           return std::string(info.param.gzip ? "Gzip" : "Zlib") + "Level" +
                                  std::to_string(info.param.level);
                         });

TEST(DeflateIndex, ConcatenatedMembersReadOnFromAPointInTheFirst) {
  TempDir dir;
  const std::string first = compressibleBytes(3 * kMiB + 3, 1);
  const std::string second = compressibleBytes(2 * kMiB + 5, 2);
  const std::string data = first + second;
  const std::string path = dir.file("members.gz");
  writeFile(path, deflatedOf(first, 1, true) + deflatedOf(second, 1, true));
  readAllInOrder(path, 0, data);

  // From a point in the first member through its trailer (checked here, by this reader) into the second.
  auto samples = samplesOf(path, 0, data.size());
  const uint64_t offset = first.size() - kMiB / 2;
  EXPECT_EQ(readRange(*samples, offset, kMiB), data.substr(offset, kMiB));
  EXPECT_LE(samples->inflatedBytes(), 3 * kMiB);
  EXPECT_EQ(readRange(*samples, data.size() - 100, 100), data.substr(data.size() - 100));
}

// The volumes of a series: each read whole ends with a check of the stream's trailer, which inflates the
// volumes after it the first time only.
TEST(DeflateIndex, AVolumeBeforeTheStreamsEndInflatesToTheTrailerOnce) {
  TempDir dir;
  const std::string data = compressibleBytes(5 * kMiB, 5);
  const std::string path = dir.file("series.gz");
  writeFile(path, deflatedOf(data, 1, true));
  const uint64_t volume = kMiB / 2;
  auto first = samplesOf(path, 0, volume, volume);
  EXPECT_EQ(readRange(*first, 0, volume), data.substr(volume, volume));
  EXPECT_EQ(first->inflatedBytes(), data.size());
  for (uint64_t t : {7, 2, 8}) {
    auto later = samplesOf(path, 0, volume, t * volume);
    EXPECT_EQ(readRange(*later, 0, volume), data.substr(t * volume, volume)) << t;
    EXPECT_LE(later->inflatedBytes(), 2 * volume + DeflateIndex::kFirstSpacingBytes) << t;
  }
}

TEST(DeflateIndex, ATrailerThatDoesNotMatchIsRefusedAfterAResume) {
  TempDir dir;
  const std::string data = compressibleBytes(4 * kMiB, 3);
  const std::string good = deflatedOf(data, 1, true);
  for (const auto& [name, flippedFromEnd, why] :
       {std::tuple{"crc", 8, "incorrect data check"}, std::tuple{"length", 2, "incorrect length check"}}) {
    SCOPED_TRACE(name);
    std::string bad = good;
    bad[bad.size() - flippedFromEnd] ^= 0x5a;
    const std::string path = dir.file(std::string(name) + ".gz");
    writeFile(path, bad);
    // The first reader reads the whole stream, taking points, and finds the trailer wrong (zlib's check).
    auto whole = samplesOf(path, 0, data.size());
    EXPECT_NE(errorOfRead(*whole, 0, data.size()).find(why), std::string::npos);
    EXPECT_GE(deflateIndexFor(PosixFile(path), 0)->pointCount(), 3u);
    // The next reads the end alone, resuming from a point: the trailer is checked by the stream, not zlib.
    auto tail = samplesOf(path, 0, data.size());
    const std::string message = errorOfRead(*tail, data.size() - 1000, 1000);
    EXPECT_NE(message.find(why), std::string::npos) << message;
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_LE(tail->inflatedBytes(), 2 * kMiB);
  }

  // Cut inside the trailer: refused as truncated, also when resumed.
  const std::string path = dir.file("cut.gz");
  writeFile(path, good.substr(0, good.size() - 3));
  auto whole = samplesOf(path, 0, data.size());
  EXPECT_NE(errorOfRead(*whole, 0, data.size()).find("truncated"), std::string::npos);
  auto tail = samplesOf(path, 0, data.size());
  const std::string message = errorOfRead(*tail, data.size() - 1000, 1000);
  EXPECT_NE(message.find("truncated"), std::string::npos) << message;
}

TEST(DeflateIndex, AFileRewrittenSinceGetsAFreshIndex) {
  TempDir dir;
  const std::string path = dir.file("volume.gz");
  const std::string before = compressibleBytes(4 * kMiB, 4);
  std::string after = before;  // other data of the same length
  std::reverse(after.begin(), after.end());
  // Both streams stored at one size, padded with zeros (which a reader never reaches).
  std::string first = deflatedOf(before, 1, true), second = deflatedOf(after, 1, true);
  first.resize(std::max(first.size(), second.size()), '\0');
  second.resize(first.size(), '\0');
  writeFile(path, first);
  readAllInOrder(path, 0, before);
  const auto firstIndex = deflateIndexFor(PosixFile(path), 0);
  ASSERT_GT(firstIndex->pointCount(), 0u);

  // Rewritten in place at the same size, under a later time.
  writeFile(path, second);
  std::filesystem::last_write_time(path, std::filesystem::last_write_time(path) + std::chrono::seconds(5));
  EXPECT_NE(deflateIndexFor(PosixFile(path), 0), firstIndex);
  auto samples = samplesOf(path, 0, after.size());
  EXPECT_EQ(readRange(*samples, 3 * kMiB, kMiB), after.substr(3 * kMiB, kMiB));
}

// Two readers of one file on two threads at once, as two sources of a series may be: one takes the points as
// it inflates front to back while the other reads ranges, resuming from those already taken. Each reads the
// data.
TEST(DeflateIndexThreads, ReadersOnTwoThreadsShareOneIndex) {
  TempDir dir;
  const std::string data = compressibleBytes(3 * kMiB, 11);
  const std::string path = (dir / "shared.gz").string();
  writeFile(path, deflatedOf(data, 6, true));
  std::string problem;
  std::atomic<bool> done = false;
  std::thread front([&] {
    try {
      readAllInOrder(path, 0, data);
    } catch (const Error& e) {
      problem = e.what();
    }
    done = true;
  });
  std::mt19937 random(5);
  for (int reads = 0; !done || reads < 4; ++reads) {
    auto samples = samplesOf(path, 0, data.size());
    const uint64_t at = random() % (data.size() - 4096);
    EXPECT_EQ(readRange(*samples, at, 4096), data.substr(at, 4096)) << "at " << at;
  }
  front.join();
  EXPECT_EQ(problem, "");
}

TEST(DeflateIndex, PointsAreThinnedPastTheirLimitAndStillSpanTheStream) {
  DeflateIndex index;
  uint64_t output = 0;
  for (size_t i = 0; i < 3 * DeflateIndex::kMaxPoints; ++i) {
    output += DeflateIndex::kFirstSpacingBytes * 2;
    if (!index.wantsPointAt(output)) continue;
    DeflateAccessPoint point;
    point.output = output;
    index.add(point);
  }
  EXPECT_LE(index.pointCount(), DeflateIndex::kMaxPoints);
  EXPECT_GE(index.pointCount(), DeflateIndex::kMaxPoints / 4);
  EXPECT_FALSE(index.pointBefore(DeflateIndex::kFirstSpacingBytes).has_value());
  const auto last = index.pointBefore(output);
  ASSERT_TRUE(last.has_value());
  EXPECT_GT(last->output, output * 3 / 4);  // the latest points are kept, not only the first
  const auto middle = index.pointBefore(output / 2);
  ASSERT_TRUE(middle.has_value());
  EXPECT_GT(middle->output, output / 2 - output / 8);
  EXPECT_LE(middle->output, output / 2);
}

}  // namespace
}  // namespace ropecast
