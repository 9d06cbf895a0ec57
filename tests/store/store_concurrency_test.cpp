// Several threads reading random nodes of one Store at once get exactly what one thread reads.
#include <gtest/gtest.h>

#include <random>
#include <thread>

#include "store/converter.h"
#include "store/store.h"
#include "tests/store/store_test_util.h"

namespace ropecast {
namespace {

TEST(StoreConcurrency, RandomReadsFromSeveralThreadsMatchSerialReads) {
  testing::TempDir dir;
  const glm::u32vec3 dims{64, 48, 40};
  const auto samples = testing::toType<uint16_t>(testing::ballField(dims, 8), 0, 65535);
  ArraySource source =
      ArraySource::fromSamples<uint16_t>(testing::volumeInfo(dims, SampleType::UInt16), samples);
  ConvertOptions options;
  options.brickSize = 8;
  convertVolume(source, dir / "c.store", options);
  const auto store = Store::open(dir / "c.store");
  const OctreeLayout& layout = store->info().layout;

  std::vector<std::vector<std::byte>> serial(layout.insideNodeCount(),
                                             std::vector<std::byte>(store->brickBytes()));
  for (uint64_t i = 0; i < serial.size(); ++i) store->readBrick(layout.nodeAt(i), serial[i]);

  constexpr int kThreads = 6, kReadsPerThread = 1500;
  std::vector<int> mismatches(kThreads, 0), failures(kThreads, 0);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&, t] {
      std::mt19937_64 rng(t + 1);
      std::vector<std::byte> out(store->brickBytes());
      for (int r = 0; r < kReadsPerThread; ++r) {
        const uint64_t i = rng() % serial.size();
        try {
          store->readBrick(layout.nodeAt(i), out);
          mismatches[t] += out != serial[i];
        } catch (...) {
          ++failures[t];
        }
      }
    });
  for (auto& t : threads) t.join();
  for (int t = 0; t < kThreads; ++t) {
    EXPECT_EQ(mismatches[t], 0) << "thread " << t;
    EXPECT_EQ(failures[t], 0) << "thread " << t;
  }
}

}  // namespace
}  // namespace ropecast
