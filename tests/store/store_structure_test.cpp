// The octree a conversion produces, checked node by node against a direct computation: bricks with borders,
// inner-node filtering, min/max over descendants, kinds, and the embedding of non-cubic volumes.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>

#include "store/converter.h"
#include "store/store.h"
#include "store/verify.h"
#include "tests/store/store_test_util.h"

namespace ropecast {
namespace {

using testing::TempDir;

struct Expected {
  std::vector<uint16_t> brick;
  uint16_t min = 0, max = 0;  // over the brick and all descendants
};

// Compares every inside node with the direct computation; returns the number of nodes of each kind.
std::array<uint64_t, 4> expectNodesMatchDirectComputation(const Store& store,
                                                          const std::vector<uint16_t>& level0,
                                                          std::optional<double> discardBelow) {
  const OctreeLayout& layout = store.info().layout;
  const auto levels = testing::levelPyramid(level0, layout);
  std::function<Expected(const NodeKey&)> expected = [&](const NodeKey& key) {
    Expected e;
    e.brick = testing::expectedBrick(levels, layout, key);
    const auto [mn, mx] = std::minmax_element(e.brick.begin(), e.brick.end());
    e.min = *mn;
    e.max = *mx;
    if (key.depth < layout.maxDepth)
      for (uint32_t o = 0; o < 8; ++o)
        if (layout.isInside(key.child(o))) {
          const Expected c = expected(key.child(o));
          e.min = std::min(e.min, c.min);
          e.max = std::max(e.max, c.max);
        }
    return e;
  };
  std::array<uint64_t, 4> kinds{};
  std::vector<std::byte> bytes(store.brickBytes());
  for (uint64_t i = 0; i < layout.insideNodeCount(); ++i) {
    const NodeKey key = layout.nodeAt(i);
    const Expected e = expected(key);
    const NodeInfo node = store.node(key);
    const std::string name = Store::describeNode(key);
    EXPECT_EQ(node.minValue, e.min) << name;
    EXPECT_EQ(node.maxValue, e.max) << name;
    ++kinds[size_t(node.kind)];
    EXPECT_EQ(store.compressedBytes(key), store.entries()[layout.nodeIndex(key)].payloadBytes) << name;
    if (discardBelow && store.info().mapping.toData(e.max) < *discardBelow) {
      EXPECT_EQ(node.kind, NodeKind::Empty) << name;
      // Its samples are not kept: it reads as its brick's minimum, a value of the data (not stored 0, which
      // a signed type's offset would turn into the type's lowest value).
      store.readBrick(key, bytes);
      const std::vector<uint16_t> got = testing::widen(bytes, store.info().storedType);
      const uint16_t brickMin = *std::min_element(e.brick.begin(), e.brick.end());
      EXPECT_EQ(got, std::vector<uint16_t>(got.size(), brickMin)) << name;
      continue;
    }
    EXPECT_EQ(node.kind, e.min == e.max ? NodeKind::Constant : NodeKind::Data) << name;
    store.readBrick(key, bytes);
    const std::vector<uint16_t> got = testing::widen(bytes, store.info().storedType);
    EXPECT_EQ(got, e.brick) << name << ": brick differs from the direct computation";
    if (got != e.brick) break;
  }
  return kinds;
}

template <typename T>
std::unique_ptr<Store> convert(const TempDir& dir, const std::vector<T>& samples, glm::u32vec3 dims,
                               SampleType type, uint32_t brick, std::optional<double> discardBelow = {}) {
  ArraySource source = ArraySource::fromSamples<T>(testing::volumeInfo(dims, type), samples);
  ConvertOptions options;
  options.brickSize = brick;
  options.discardBelow = discardBelow;
  convertVolume(source, dir / "s.store", options);
  return Store::open(dir / "s.store");
}

TEST(StoreStructure, BricksBordersFilteringAndRangesMatchDirectComputation) {
  TempDir dir;
  const glm::u32vec3 dims{45, 37, 29};
  const auto samples = testing::toType<uint16_t>(testing::ballField(dims, 1), 10, 50000);
  const auto store = convert(dir, samples, dims, SampleType::UInt16, 8);
  const auto kinds = expectNodesMatchDirectComputation(*store, testing::storedValues(samples), {});
  EXPECT_GT(kinds[size_t(NodeKind::Data)], 0u);
  EXPECT_GT(kinds[size_t(NodeKind::Constant)], 0u) << "the zero corners should give constant nodes";
  EXPECT_TRUE(verifyStore(*store).ok());
}

TEST(StoreStructure, NonCubicVolumeIsEmbeddedInACubeOfBricks) {
  TempDir dir;
  const glm::u32vec3 dims{70, 20, 9};
  const auto samples = testing::toType<uint8_t>(testing::ballField(dims, 2), 0, 255);
  const auto store = convert(dir, samples, dims, SampleType::UInt8, 8);
  const OctreeLayout& layout = store->info().layout;
  EXPECT_EQ(layout.maxDepth, 4u);  // 70 / 8 -> 9 bricks -> a cube of 16 = 2^4
  EXPECT_GE(layout.cubeSamples(), 70u);
  EXPECT_EQ(store->entries().size(), layout.insideNodeCount());
  EXPECT_EQ(layout.insideNodes(4), glm::u32vec3(9, 3, 2));
  EXPECT_EQ(layout.insideNodes(0), glm::u32vec3(1, 1, 1));
  // Nodes of the cube outside the data are reported Outside and read as zeros.
  EXPECT_EQ(store->node({4, {9, 0, 0}}).kind, NodeKind::Outside);
  EXPECT_EQ(store->node({4, {0, 3, 0}}).kind, NodeKind::Outside);
  EXPECT_EQ(store->node({1, {1, 1, 1}}).kind, NodeKind::Outside);
  std::vector<std::byte> bytes(store->brickBytes(), std::byte{7});
  ASSERT_EQ(store->node({1, {0, 1, 0}}).kind, NodeKind::Outside);
  store->readBrick({1, {0, 1, 0}}, bytes);
  EXPECT_TRUE(std::all_of(bytes.begin(), bytes.end(), [](std::byte b) { return b == std::byte{0}; }));
  expectNodesMatchDirectComputation(*store, testing::storedValues(samples), {});
  EXPECT_TRUE(verifyStore(*store).ok());
}

TEST(StoreStructure, DiscardBelowMarksNodesWhoseMaxIsBelowEmpty) {
  TempDir dir;
  const glm::u32vec3 dims{45, 37, 29};
  const auto samples = testing::toType<int16_t>(testing::ballField(dims, 4), -1000, 1000);
  const double threshold = -600.0;  // data units (int16), the ball's rim lies below it
  const auto store = convert(dir, samples, dims, SampleType::Int16, 8, threshold);
  const auto kinds = expectNodesMatchDirectComputation(*store, testing::storedValues(samples), threshold);
  EXPECT_GT(kinds[size_t(NodeKind::Empty)], 0u);
  EXPECT_GT(kinds[size_t(NodeKind::Data)], 0u);
  for (const StoreNodeEntry& e : store->entries())
    if (e.kind == uint8_t(NodeKind::Empty)) {
      EXPECT_EQ(e.payloadBytes, 0u);
    }
  EXPECT_TRUE(verifyStore(*store).ok());
}

TEST(StoreStructure, UniformVolumeIsOneConstantNodePerBrickWithoutPayloads) {
  TempDir dir;
  const glm::u32vec3 dims{17, 9, 12};
  const std::vector<uint16_t> samples(size_t(dims.x) * dims.y * dims.z, 1234);
  const auto store = convert(dir, samples, dims, SampleType::UInt16, 4);
  for (const StoreNodeEntry& e : store->entries()) {
    EXPECT_EQ(e.kind, uint8_t(NodeKind::Constant));
    EXPECT_EQ(e.payloadBytes, 0u);
    EXPECT_EQ(e.minValue, 1234);
  }
  expectNodesMatchDirectComputation(*store, samples, {});
}

TEST(StoreStructure, SingleSampleVolume) {
  TempDir dir;
  const std::vector<uint8_t> samples{42};
  const auto store = convert(dir, samples, {1, 1, 1}, SampleType::UInt8, 4);
  EXPECT_EQ(store->info().layout.maxDepth, 0u);
  EXPECT_EQ(store->node({0, {0, 0, 0}}).kind, NodeKind::Constant);
  expectNodesMatchDirectComputation(*store, testing::storedValues(samples), {});
}

}  // namespace
}  // namespace ropecast
