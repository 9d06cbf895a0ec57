// The probe's reader (store/async_voxel_reader.h): answers are the voxels' values; a question whose brick is
// not kept returns at once while the brick is read on the reader's thread, which says when it is known; a
// voxel of the brick kept is answered without a read; a newer question replaces one not yet begun.
#include "store/async_voxel_reader.h"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "store/array_source.h"
#include "store/converter.h"
#include "store/store.h"
#include "tests/store/store_test_util.h"

namespace ropecast {
namespace {

using testing::TempDir;

// A BrickSource whose reads wait until the test opens its gate, and that names the bricks it read.
class GatedSource : public BrickSource {
 public:
  explicit GatedSource(const BrickSource& inner) : inner_(inner) {}
  const BrickSourceInfo& info() const override { return inner_.info(); }
  NodeInfo node(const NodeKey& key) const override { return inner_.node(key); }
  void readBrick(const NodeKey& key, std::span<std::byte> out) const override {
    std::unique_lock lock(mutex_);
    ++waiting_;
    changed_.notify_all();
    changed_.wait(lock, [this] { return open_; });
    --waiting_;
    read_.push_back(key.coord);
    lock.unlock();
    inner_.readBrick(key, out);
  }
  void open() {
    std::lock_guard lock(mutex_);
    open_ = true;
    changed_.notify_all();
  }
  // Blocks until a read waits at the gate.
  void awaitReader() const {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [this] { return waiting_ > 0; });
  }
  std::vector<glm::u32vec3> read() const {
    std::lock_guard lock(mutex_);
    return read_;
  }

 private:
  const BrickSource& inner_;
  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  bool open_ = false;
  mutable int waiting_ = 0;
  mutable std::vector<glm::u32vec3> read_;
};

std::unique_ptr<Store> rampStore(const TempDir& dir) {
  VolumeInfo info = testing::volumeInfo({24, 16, 8}, SampleType::UInt16);
  std::vector<uint16_t> samples(info.sampleCount());
  for (size_t i = 0; i < samples.size(); ++i) samples[i] = uint16_t(i * 3);
  ArraySource source = ArraySource::fromSamples<uint16_t>(info, samples);
  ConvertOptions options;
  options.brickSize = 8;
  convertVolume(source, dir / "ramp.store", options);
  return Store::open(dir / "ramp.store");
}

double rampValue(glm::u32vec3 v) {
  return double(((size_t(v.z) * 16 + v.y) * 24 + v.x) * 3);
}

TEST(AsyncVoxelReader, AQuestionReturnsAtOnceAndItsBrickIsReadOnTheReadersThread) {
  TempDir dir;
  const auto store = rampStore(dir);
  GatedSource gated(*store);
  std::atomic<int> answered = 0;
  {
    AsyncVoxelReader reader(gated, [&] { ++answered; });
    EXPECT_FALSE(reader.ask(0, {3, 4, 5}));  // the gate is shut: no answer, and no wait
    gated.awaitReader();
    EXPECT_FALSE(reader.ask(0, {3, 4, 5}));
    // Newer questions while the first brick is read: the last replaces the others.
    EXPECT_FALSE(reader.ask(0, {12, 4, 5}));
    EXPECT_FALSE(reader.ask(0, {20, 12, 1}));
    gated.open();
    const VoxelAnswer last = reader.wait(0, {20, 12, 1});
    EXPECT_EQ(last.error, "");
    EXPECT_EQ(last.value, rampValue({20, 12, 1}));
    EXPECT_EQ(gated.read(), (std::vector<glm::u32vec3>{{0, 0, 0}, {2, 1, 0}}));  // {12, 4, 5}'s never
    EXPECT_EQ(reader.reads(), 2u);
    // The brick kept answers at once, without a read.
    const std::optional<VoxelAnswer> kept = reader.ask(0, {23, 15, 0});
    ASSERT_TRUE(kept);
    EXPECT_EQ(kept->value, rampValue({23, 15, 0}));
    EXPECT_EQ(reader.reads(), 2u);
    // Another brick, another level: read, then known.
    EXPECT_EQ(reader.wait(0, {3, 4, 5}).value, rampValue({3, 4, 5}));
    EXPECT_EQ(reader.wait(1, {2, 1, 0}).value, voxelValue(*store, 1, {2, 1, 0}));
    EXPECT_EQ(reader.reads(), 4u);
  }
  EXPECT_EQ(answered.load(), 4);
}

TEST(AsyncVoxelReader, AVoxelOutsideTheLevelIsAnAnswerThatSaysSo) {
  TempDir dir;
  const auto store = rampStore(dir);
  AsyncVoxelReader reader(*store);
  const VoxelAnswer outside = reader.wait(0, {24, 0, 0});
  EXPECT_NE(outside.error.find("lies outside level 0"), std::string::npos) << outside.error;
  EXPECT_EQ(reader.wait(0, {0, 0, 0}).value, 0.0);  // and the reader goes on
}

}  // namespace
}  // namespace ropecast
