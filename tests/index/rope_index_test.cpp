// The rope index against its definition: decode the texels back into a tree (children consecutive, x
// fastest), check every leaf appears once with its kind and slot, and check every rope against an independent
// search over all nodes: the deepest node of depth <= the leaf's depth whose box holds the adjacent cell.
#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "index/cut.h"
#include "index/random_cut.h"
#include "index/rope_index.h"

namespace ropecast {
namespace {

struct DecodedNode {
  uint32_t texel;
  uint32_t depth;
  glm::u32vec3 coord;
};

// Walks the tree from the root; fails the test on malformed pointers.
std::vector<DecodedNode> decode(const RopeIndex& index) {
  std::vector<DecodedNode> nodes{{0, 0, glm::u32vec3(0)}};
  for (size_t i = 0; i < nodes.size(); ++i) {
    const DecodedNode n = nodes[i];
    EXPECT_LT(n.texel, index.nodeCount);
    if (n.texel >= index.nodeCount) break;
    const RopeTexel& t = index.texels[n.texel];
    if (t[kRopeNodeTag] != kRopeTagInner) continue;
    EXPECT_EQ(t[kRopeNodeLeafIndex], n.depth);
    for (uint32_t z = 0; z < 2; ++z)
      for (uint32_t y = 0; y < 2; ++y)
        for (uint32_t x = 0; x < 2; ++x)
          nodes.push_back({t[kRopeNodePointer] + ropeChildOffset(x, y, z), n.depth + 1,
                           n.coord * 2u + glm::u32vec3(x, y, z)});
  }
  return nodes;
}

bool contains(const DecodedNode& node, uint32_t depth, glm::u32vec3 coord) {
  return node.depth <= depth && (coord >> (depth - node.depth)) == node.coord;
}

void checkIndex(const Cut& cut) {
  const RopeIndex index = buildRopeIndex(cut);
  ASSERT_EQ(index.leafCount, cut.leaves.size());
  ASSERT_EQ(index.texels.size(), index.nodeCount + kRopeBlockTexels * index.leafCount);
  const std::vector<DecodedNode> nodes = decode(index);
  ASSERT_EQ(nodes.size(), index.nodeCount) << "every node texel reachable exactly once";
  // (nodes - 1) is a multiple of 8: every inner node has 8 children.
  EXPECT_EQ((index.nodeCount - 1) % 8, 0u);

  std::vector<int> seen(cut.leaves.size(), 0);
  uint32_t maxDepth = 0;
  for (const DecodedNode& node : nodes) {
    const RopeTexel& t = index.texels[node.texel];
    if (t[kRopeNodeTag] == kRopeTagInner) continue;
    const uint32_t leafIndex = t[kRopeNodeLeafIndex];
    ASSERT_LT(leafIndex, cut.leaves.size());
    ++seen[leafIndex];
    const CutLeaf& leaf = cut.leaves[leafIndex];
    EXPECT_EQ(node.depth, leaf.depth);
    EXPECT_EQ(node.coord, leaf.coord);
    EXPECT_EQ(index.leafNodeTexel[leafIndex], node.texel);
    maxDepth = std::max(maxDepth, leaf.depth);
    if (leaf.kind == LeafKind::Data) {
      EXPECT_EQ(t[kRopeNodeTag], kRopeTagDataLeaf);
      EXPECT_EQ(t[kRopeNodeBrickSlot], leaf.brickSlot);
    } else {
      EXPECT_EQ(t[kRopeNodeTag], leaf.kind == LeafKind::Solid ? kRopeTagSolidLeaf : kRopeTagEmptyLeaf);
      EXPECT_EQ(t[kRopeNodeBrickSlot], kRopeNoBrick);
    }
    const uint32_t block = t[kRopeNodePointer];
    ASSERT_GE(block, index.nodeCount);
    ASSERT_LT(block + 1, index.texels.size());
    EXPECT_EQ(index.texels[block + 1][2], kRopeNull);
    EXPECT_EQ(index.texels[block + 1][3], kRopeNull);

    for (uint32_t face = 0; face < kRopeFaceCount; ++face) {
      const uint32_t word = index.texels[ropeFaceTexel(block, face)][ropeFaceComponent(face)];
      const uint32_t axis = ropeFaceAxis(face);
      const int64_t step = ropeFaceIsPositive(face) ? 1 : -1;
      const int64_t neighbor = int64_t(leaf.coord[axis]) + step;
      if (neighbor < 0 || neighbor >= (int64_t(1) << leaf.depth)) {
        EXPECT_EQ(word, kRopeNull) << "leaf " << leafIndex << " face " << face;
        continue;
      }
      glm::u32vec3 cell = leaf.coord;
      cell[axis] = uint32_t(neighbor);
      const DecodedNode* expected = nullptr;
      for (const DecodedNode& other : nodes)
        if (contains(other, leaf.depth, cell) && (!expected || other.depth > expected->depth))
          expected = &other;
      ASSERT_NE(expected, nullptr);
      ASSERT_NE(word, kRopeNull) << "leaf " << leafIndex << " face " << face;
      EXPECT_EQ(ropeNeighborNode(word), expected->texel) << "leaf " << leafIndex << " face " << face;
      EXPECT_EQ(ropeNeighborDepth(word), expected->depth) << "leaf " << leafIndex << " face " << face;
    }
  }
  for (size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], 1) << "leaf " << i;
  EXPECT_EQ(index.maxDepth, maxDepth);
}

// A Solid leaf (an empty leaf inside a capped isosurface) keeps its kind in the tag, and no brick.
TEST(RopeIndex, SolidLeavesAreTaggedApart) {
  std::vector<CutLeaf> leaves;
  for (uint32_t o = 0; o < 8; ++o) {
    const LeafKind kind = o % 3 == 0 ? LeafKind::Data : o % 3 == 1 ? LeafKind::Solid : LeafKind::Empty;
    leaves.push_back(CutLeaf{1, glm::u32vec3(o & 1, (o >> 1) & 1, (o >> 2) & 1), kind, o});
  }
  const Cut cut{leaves};
  const RopeIndex index = buildRopeIndex(cut);
  for (uint32_t i = 0; i < 8; ++i) {
    const RopeTexel& t = index.texels[index.leafNodeTexel[i]];
    EXPECT_EQ(t[kRopeNodeTag], i % 3 == 0   ? kRopeTagDataLeaf
                               : i % 3 == 1 ? kRopeTagSolidLeaf
                                            : kRopeTagEmptyLeaf);
    EXPECT_EQ(t[kRopeNodeBrickSlot], i % 3 == 0 ? i : kRopeNoBrick);
  }
  checkIndex(cut);
}

TEST(RopeIndex, SingleRootLeaf) {
  const Cut cut{{CutLeaf{0, glm::u32vec3(0), LeafKind::Data, 7}}};
  const RopeIndex index = buildRopeIndex(cut);
  ASSERT_EQ(index.texels.size(), 1u + kRopeBlockTexels);
  EXPECT_EQ(index.texels[0], RopeTexel(kRopeTagDataLeaf, 1, 7, 0));
  EXPECT_EQ(index.texels[1], RopeTexel(kRopeNull));
  EXPECT_EQ(index.texels[2], RopeTexel(kRopeNull));
  EXPECT_EQ(index.maxDepth, 0u);
  checkIndex(cut);
}

TEST(RopeIndex, RandomCutsMatchTheDefinition) {
  for (uint64_t seed = 1; seed <= 30; ++seed) {
    RandomCutParams params;
    params.seed = seed;
    params.targetLeaves = std::array<uint32_t, 5>{1, 8, 50, 200, 600}[seed % 5];
    params.maxDepth = 1 + uint32_t(seed % 7);
    SCOPED_TRACE(testing::Message() << "seed " << seed);
    checkIndex(makeRandomCut(params));
    if (HasFailure()) return;
  }
}

// Very different depths side by side: ropes to much coarser leaves and to same-depth inner nodes.
TEST(RopeIndex, DeepLeafBesideCoarseOnes) {
  CutLeaf deep{kCutMaxDepth, glm::u32vec3(1u << (kCutMaxDepth - 1)), LeafKind::Data, 3};
  checkIndex(completeCut(std::vector<CutLeaf>{deep}));
  CutLeaf corner{12, glm::u32vec3(0, 4095, 2048), LeafKind::Data, 4};
  checkIndex(completeCut(std::vector<CutLeaf>{deep, corner}));
}

TEST(RopeIndex, BuilderReusesItsBuffers) {
  RopeIndexBuilder builder;
  RopeIndex index;
  RandomCutParams big;
  big.targetLeaves = 2000;
  builder.build(makeRandomCut(big), index);
  const RopeTexel* storage = index.texels.data();
  RandomCutParams small;
  small.targetLeaves = 100;
  small.seed = 2;
  const Cut smallCut = makeRandomCut(small);
  builder.build(smallCut, index);
  EXPECT_EQ(index.texels.data(), storage);  // shrinking keeps the allocation
  // And the result equals a fresh build.
  EXPECT_EQ(index.texels, buildRopeIndex(smallCut).texels);
}

TEST(RopeIndex, RejectsInvalidCuts) {
  Cut hole{{CutLeaf{1, glm::u32vec3(0), LeafKind::Empty, 0}}};
  EXPECT_THROW(buildRopeIndex(hole), std::invalid_argument);
  EXPECT_THROW(buildRopeIndex(Cut{}), std::invalid_argument);
}

}  // namespace
}  // namespace ropecast
