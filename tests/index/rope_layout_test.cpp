// Field-by-field checks of index/rope_layout.h: the values docs/INDEX.md promises, and the packing helpers
// round-tripping over their whole range.
#include <gtest/gtest.h>

#include <set>

#include "index/cut.h"
#include "index/rope_index.h"
#include "index/rope_layout.h"

namespace ropecast {
namespace {

TEST(RopeLayout, TexelIsUvec4) {
  EXPECT_EQ(kRopeTexelComponents, 4u);
  EXPECT_EQ(sizeof(RopeTexel), 16u);
  EXPECT_EQ(alignof(RopeTexel), 4u);
}

TEST(RopeLayout, NodeTexelFields) {
  EXPECT_EQ(kRopeNodeTag, 0u);
  EXPECT_EQ(kRopeNodePointer, 1u);
  EXPECT_EQ(kRopeNodeBrickSlot, 2u);
  EXPECT_EQ(kRopeNodeLeafIndex, 3u);
  const std::set<uint32_t> fields{kRopeNodeTag, kRopeNodePointer, kRopeNodeBrickSlot, kRopeNodeLeafIndex};
  EXPECT_EQ(fields.size(), 4u);
}

TEST(RopeLayout, TagsAreDistinctAndNonZero) {
  EXPECT_EQ(kRopeTagInner, 1u);
  EXPECT_EQ(kRopeTagDataLeaf, 2u);
  EXPECT_EQ(kRopeTagEmptyLeaf, 3u);
  EXPECT_EQ(kRopeNoBrick, 0xFFFFFFFFu);
}

TEST(RopeLayout, FaceOrder) {
  // -x, +x, -y, +y, -z, +z
  EXPECT_EQ(ropeFace(0, false), 0u);
  EXPECT_EQ(ropeFace(0, true), 1u);
  EXPECT_EQ(ropeFace(1, false), 2u);
  EXPECT_EQ(ropeFace(1, true), 3u);
  EXPECT_EQ(ropeFace(2, false), 4u);
  EXPECT_EQ(ropeFace(2, true), 5u);
  for (uint32_t face = 0; face < kRopeFaceCount; ++face) {
    EXPECT_EQ(ropeFace(ropeFaceAxis(face), ropeFaceIsPositive(face)), face);
  }
}

TEST(RopeLayout, RopeBlockAddressing) {
  EXPECT_EQ(kRopeBlockTexels, 2u);
  EXPECT_EQ(kRopeFaceCount, 6u);
  // Faces 0..3 in the first texel, 4..5 then the NULL words 6 and 7 in the second.
  for (uint32_t face = 0; face < 8; ++face) {
    EXPECT_EQ(ropeFaceTexel(100, face), 100u + face / 4);
    EXPECT_EQ(ropeFaceComponent(face), face % 4);
  }
}

TEST(RopeLayout, ChildOffsetIsXFastest) {
  for (uint32_t z = 0; z < 2; ++z)
    for (uint32_t y = 0; y < 2; ++y)
      for (uint32_t x = 0; x < 2; ++x) EXPECT_EQ(ropeChildOffset(x, y, z), x + 2 * y + 4 * z);
}

TEST(RopeLayout, NeighborWordPacking) {
  EXPECT_EQ(kRopeNull, 0xFFFFFFFFu);
  EXPECT_EQ(kRopeDepthBits, 5u);
  EXPECT_EQ(kRopeMaxDepth, kCutMaxDepth);
  EXPECT_EQ(ropeNeighborWord(0, 0), 0u);
  EXPECT_EQ(ropeNeighborWord(1, 0), 32u);
  EXPECT_EQ(ropeNeighborWord(3, 7), 3u * 32u + 7u);
  for (uint32_t depth = 0; depth <= kRopeMaxDepth; ++depth) {
    for (uint32_t texel : {0u, 1u, 12345u, kRopeMaxTexels - 1}) {
      const uint32_t word = ropeNeighborWord(texel, depth);
      EXPECT_NE(word, kRopeNull);
      EXPECT_EQ(ropeNeighborNode(word), texel);
      EXPECT_EQ(ropeNeighborDepth(word), depth);
    }
  }
}

// The encoder writes exactly these fields (a one-inner-node index: root with 8 leaves).
TEST(RopeLayout, EncoderUsesTheFields) {
  Cut cut;
  for (uint32_t octant = 0; octant < 8; ++octant)
    cut.leaves.push_back({1,
                          {octant & 1u, (octant >> 1) & 1u, (octant >> 2) & 1u},
                          octant % 2 ? LeafKind::Data : LeafKind::Empty,
                          40 + octant});
  const RopeIndex index = buildRopeIndex(cut);
  ASSERT_EQ(index.texels.size(), 9u + 8u * kRopeBlockTexels);
  EXPECT_EQ(index.texels[0][kRopeNodeTag], kRopeTagInner);
  EXPECT_EQ(index.texels[0][kRopeNodePointer], 1u);
  EXPECT_EQ(index.texels[0][kRopeNodeBrickSlot], kRopeNoBrick);
  EXPECT_EQ(index.texels[0][kRopeNodeLeafIndex], 0u);  // inner: its depth
  for (uint32_t octant = 0; octant < 8; ++octant) {
    const RopeTexel& t = index.texels[1 + octant];
    EXPECT_EQ(t[kRopeNodeTag], octant % 2 ? kRopeTagDataLeaf : kRopeTagEmptyLeaf);
    EXPECT_EQ(t[kRopeNodeBrickSlot], octant % 2 ? 40 + octant : kRopeNoBrick);
    EXPECT_EQ(t[kRopeNodeLeafIndex], octant);
    const uint32_t block = t[kRopeNodePointer];
    ASSERT_GE(block, 9u);
    // +x of octant 0 is octant 1 (texel 2, depth 1); -x of octant 0 is outside the root.
    if (octant == 0) {
      EXPECT_EQ(index.texels[ropeFaceTexel(block, 1)][ropeFaceComponent(1)], ropeNeighborWord(2, 1));
      EXPECT_EQ(index.texels[ropeFaceTexel(block, 0)][ropeFaceComponent(0)], kRopeNull);
    }
    EXPECT_EQ(index.texels[block + 1][2], kRopeNull);
    EXPECT_EQ(index.texels[block + 1][3], kRopeNull);
  }
}

}  // namespace
}  // namespace ropecast
