// verifyStore must pass on converted stores and name the node when a store is wrong although its checksums
// hold (the stores here are rewritten with a deliberate error through StoreWriter).
#include <gtest/gtest.h>
#include <zstd.h>

#include <filesystem>
#include <fstream>
#include <functional>

#include "store/converter.h"
#include "store/store.h"
#include "store/store_writer.h"
#include "store/verify.h"
#include "tests/store/store_test_util.h"

namespace ropecast {
namespace {

using testing::TempDir;
using Edit = std::function<void(const NodeKey&, std::vector<uint16_t>& brick, StoreNodeEntry& entry)>;

// Copies `in` to `out`, letting `edit` change each node's brick and entry (bricks of uint16 stores).
void rewriteStore(const Store& in, const std::filesystem::path& out, const Edit& edit) {
  const OctreeLayout& layout = in.info().layout;
  StoreWriter writer(out);
  std::vector<StoreNodeEntry> entries(in.entries().begin(), in.entries().end());
  std::vector<std::byte> bytes(in.brickBytes());
  for (uint64_t i = 0; i < entries.size(); ++i) {
    const NodeKey key = layout.nodeAt(i);
    in.readBrick(key, bytes);
    std::vector<uint16_t> brick = testing::widen(bytes, SampleType::UInt16);
    edit(key, brick, entries[i]);
    if (entries[i].payloadBytes == 0) continue;
    ASSERT_EQ(in.metadata().payloadEncoding, PayloadEncoding::ZstdBytePlanes);
    std::vector<std::byte> planes(bytes.size()), compressed(ZSTD_compressBound(bytes.size()));
    splitBytePlanes(brick.data(), brick.size(), planes.data());
    const size_t n = ZSTD_compress(compressed.data(), compressed.size(), planes.data(), planes.size(), 1);
    ASSERT_FALSE(ZSTD_isError(n));
    compressed.resize(n);
    entries[i].payloadBytes = uint32_t(n);
    entries[i].payloadCrc = storeCrc32(compressed);
    entries[i].payloadOffset = writer.appendPayload(compressed);
  }
  writer.finish(in.metadata(), entries);
}

class StoreVerify : public ::testing::Test {
 protected:
  void SetUp() override {
    const glm::u32vec3 dims{40, 33, 27};
    const auto samples = testing::toType<uint16_t>(testing::ballField(dims, 9), 100, 9000);
    ArraySource source =
        ArraySource::fromSamples<uint16_t>(testing::volumeInfo(dims, SampleType::UInt16), samples);
    ConvertOptions options;
    options.brickSize = 8;
    convertVolume(source, dir / "good.store", options);
    good = Store::open(dir / "good.store");
  }

  // The first Data node with a payload at `depth` whose +x neighbor also has one.
  NodeKey dataNodeWithDataNeighbor(uint32_t depth) const {
    const OctreeLayout& layout = good->info().layout;
    for (uint64_t i = 0; i < layout.insideNodeCount(); ++i) {
      const NodeKey k = layout.nodeAt(i), n{k.depth, k.coord + glm::u32vec3(1, 0, 0)};
      if (k.depth == depth && layout.isInside(n) && good->entries()[i].payloadBytes > 0 &&
          good->entries()[layout.nodeIndex(n)].payloadBytes > 0)
        return k;
    }
    ADD_FAILURE() << "no suitable node at depth " << depth;
    return {};
  }

  VerifyReport verifyRewritten(const Edit& edit) {
    rewriteStore(*good, dir / "bad.store", edit);
    return verifyStore(*Store::open(dir / "bad.store"));
  }

  TempDir dir;
  std::unique_ptr<Store> good;
};

TEST_F(StoreVerify, PassesOnAConvertedStoreAndItsUneditedCopy) {
  const VerifyReport report = verifyStore(*good);
  EXPECT_TRUE(report.ok());
  EXPECT_EQ(report.nodesChecked, good->info().layout.insideNodeCount());
  EXPECT_TRUE(verifyRewritten([](const NodeKey&, std::vector<uint16_t>&, StoreNodeEntry&) {}).ok());
}

TEST_F(StoreVerify, NamesANodeWhoseBorderDiffersFromItsNeighbor) {
  const uint32_t leaves = good->info().layout.maxDepth;
  const NodeKey target = dataNodeWithDataNeighbor(leaves);
  const uint32_t edge = good->info().layout.storedBrickEdge();
  const VerifyReport report =
      verifyRewritten([&](const NodeKey& k, std::vector<uint16_t>& brick, StoreNodeEntry& e) {
        if (!(k == target)) return;
        // The +x border sample in the middle of the brick; keep it inside the node's range so only the border
        // check sees it.
        uint16_t& v = brick[(size_t(edge / 2) * edge + edge / 2) * edge + edge - 1];
        v = v == e.minValue ? e.maxValue : e.minValue;
      });
  ASSERT_FALSE(report.ok());
  EXPECT_NE(report.problems.front().find(Store::describeNode(target)), std::string::npos)
      << report.problems.front();
  EXPECT_NE(report.problems.front().find("border"), std::string::npos) << report.problems.front();
}

TEST_F(StoreVerify, NamesAnInnerNodeThatIsNotTheMeanOfItsChildren) {
  const NodeKey target = dataNodeWithDataNeighbor(good->info().layout.maxDepth - 1);
  const uint32_t edge = good->info().layout.storedBrickEdge();
  const VerifyReport report =
      verifyRewritten([&](const NodeKey& k, std::vector<uint16_t>& brick, StoreNodeEntry& e) {
        if (!(k == target)) return;
        uint16_t& v = brick[(size_t(kBrickBorder + 1) * edge + kBrickBorder + 1) * edge + kBrickBorder + 1];
        v = v == e.minValue ? e.maxValue : e.minValue;
      });
  ASSERT_FALSE(report.ok());
  bool named = false;
  for (const auto& p : report.problems) named |= p.find(Store::describeNode(target)) != std::string::npos;
  EXPECT_TRUE(named) << report.problems.front();
}

TEST_F(StoreVerify, NamesANodeWhoseRangeDoesNotHoldItsChildren) {
  const NodeKey target{0, {0, 0, 0}};
  const VerifyReport report =
      verifyRewritten([&](const NodeKey& k, std::vector<uint16_t>&, StoreNodeEntry& e) {
        if (k == target) e.maxValue = uint16_t(e.maxValue - 1);
      });
  ASSERT_FALSE(report.ok());
  EXPECT_NE(report.problems.front().find("node depth 0 (0, 0, 0)"), std::string::npos)
      << report.problems.front();
}

// A brick whose payload no longer matches its checksum is one problem, however many checks (its own, its
// neighbors' borders, its parent's filtering) would read it.
TEST_F(StoreVerify, ReportsADamagedBrickOnce) {
  const NodeKey target = dataNodeWithDataNeighbor(good->info().layout.maxDepth);
  const StoreNodeEntry& entry = good->entries()[good->info().layout.nodeIndex(target)];
  std::filesystem::copy_file(dir / "good.store", dir / "damaged.store");
  {
    std::fstream file(dir / "damaged.store", std::ios::in | std::ios::out | std::ios::binary);
    file.seekg(std::streamoff(entry.payloadOffset + entry.payloadBytes / 2));
    const char byte = char(file.get() ^ 0x5A);
    file.seekp(std::streamoff(entry.payloadOffset + entry.payloadBytes / 2));
    file.put(byte);
  }
  const VerifyReport report = verifyStore(*Store::open(dir / "damaged.store"));
  ASSERT_EQ(report.problemCount, 1u);
  ASSERT_EQ(report.problems.size(), 1u);
  EXPECT_NE(report.problems.front().find("checksum mismatch"), std::string::npos) << report.problems.front();
  EXPECT_NE(report.problems.front().find(Store::describeNode(target)), std::string::npos)
      << report.problems.front();
}

// The reader takes such a file (every part checks out); the layout ends with the node table.
TEST_F(StoreVerify, ReportsBytesAfterTheNodeTable) {
  std::filesystem::copy_file(dir / "good.store", dir / "appended.store");
  std::ofstream(dir / "appended.store", std::ios::binary | std::ios::app) << "appended";
  const VerifyReport report = verifyStore(*Store::open(dir / "appended.store"));
  ASSERT_EQ(report.problemCount, 1u);
  EXPECT_EQ(report.problems.front(),
            "8 bytes after the node table, which ends a store: the file was appended to or damaged");
}

TEST_F(StoreVerify, NamesAConstantNodeWithARange) {
  const VerifyReport report =
      verifyRewritten([&](const NodeKey& k, std::vector<uint16_t>&, StoreNodeEntry& e) {
        if (k.depth == 0) e.kind = uint8_t(NodeKind::Constant), e.payloadBytes = 0;
      });
  ASSERT_FALSE(report.ok());
  EXPECT_NE(report.problems.front().find("Constant"), std::string::npos) << report.problems.front();
}

}  // namespace
}  // namespace ropecast
