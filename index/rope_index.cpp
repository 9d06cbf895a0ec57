// Rope index construction: CutTree skeleton, then one pass over the nodes in pool order (parents first) that
// hands each node's six ropes down to its children in O(1) per face and writes the texels.
#include "index/rope_index.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace ropecast {

static_assert(kRopeBlockTexels == 2u && kRopeFaceCount == 6u, "build() writes the block as two texels");

void RopeIndexBuilder::build(const Cut& cut, RopeIndex& out) {
  tree_.clear();
  tree_.insert(cut.leaves);
  tree_.requireNoHoles();
  const auto& nodes = tree_.nodes();
  const auto nodeCount = uint32_t(nodes.size());
  const auto leafCount = uint32_t(cut.leaves.size());
  const uint64_t texelCount = uint64_t(nodeCount) + uint64_t(kRopeBlockTexels) * leafCount;
  if (texelCount > kRopeMaxTexels)
    throw std::invalid_argument("buildRopeIndex: " + std::to_string(texelCount) + " texels exceed the " +
                                std::to_string(kRopeMaxTexels) + " that 27-bit pointers address");

  out.texels.resize(texelCount);
  out.leafNodeTexel.resize(leafCount);
  out.nodeCount = nodeCount;
  out.leafCount = leafCount;
  out.maxDepth = 0;

  // ropes_[6n + f]: the neighbor word of node n across face f, i.e. the deepest node of depth <= depth(n)
  // that contains the cell adjacent to n across f (NULL outside the root cube).
  ropes_.resize(size_t(nodeCount) * kRopeFaceCount);
  std::fill_n(ropes_.begin(), kRopeFaceCount, kRopeNull);
  uint32_t nextRopeBlock = nodeCount;

  for (uint32_t n = 0; n < nodeCount; ++n) {
    const CutTree::Node& node = nodes[n];
    const uint32_t* ropes = &ropes_[size_t(n) * kRopeFaceCount];
    RopeTexel& texel = out.texels[n];
    if (node.isInner()) {
      texel = RopeTexel(kRopeTagInner, node.firstChild, kRopeNoBrick, node.depth);
      const uint32_t childDepth = node.depth + 1;
      for (uint32_t octant = 0; octant < 8; ++octant) {
        uint32_t* childRopes = &ropes_[size_t(node.firstChild + octant) * kRopeFaceCount];
        for (uint32_t axis = 0; axis < 3; ++axis) {
          const uint32_t mirrored = octant ^ (1u << axis);  // the octant across this axis
          const bool highSide = (octant >> axis) & 1u;
          for (uint32_t positive = 0; positive < 2; ++positive) {
            const uint32_t face = ropeFace(axis, positive == 1);
            if (highSide != (positive == 1)) {  // the face looks at a sibling
              childRopes[face] = ropeNeighborWord(node.firstChild + mirrored, childDepth);
              continue;
            }
            const uint32_t parentRope = ropes[face];
            // An inner neighbor of the parent's depth has a child of the child's depth facing this child;
            // a leaf neighbor (of the parent's depth or coarser) stays the smallest enclosing node.
            if (parentRope != kRopeNull && nodes[ropeNeighborNode(parentRope)].isInner())
              childRopes[face] =
                  ropeNeighborWord(nodes[ropeNeighborNode(parentRope)].firstChild + mirrored, childDepth);
            else
              childRopes[face] = parentRope;
          }
        }
      }
    } else {
      const CutLeaf& leaf = cut.leaves[node.leaf];
      const bool data = leaf.kind == LeafKind::Data;
      const uint32_t tag = data                           ? kRopeTagDataLeaf
                           : leaf.kind == LeafKind::Solid ? kRopeTagSolidLeaf
                                                          : kRopeTagEmptyLeaf;
      texel = RopeTexel(tag, nextRopeBlock, data ? leaf.brickSlot : kRopeNoBrick, node.leaf);
      out.texels[nextRopeBlock] = RopeTexel(ropes[0], ropes[1], ropes[2], ropes[3]);
      out.texels[nextRopeBlock + 1] = RopeTexel(ropes[4], ropes[5], kRopeNull, kRopeNull);
      nextRopeBlock += kRopeBlockTexels;
      out.leafNodeTexel[node.leaf] = n;
      out.maxDepth = std::max(out.maxDepth, node.depth);
    }
  }
}

RopeIndex buildRopeIndex(const Cut& cut) {
  RopeIndexBuilder builder;
  RopeIndex index;
  builder.build(cut, index);
  return index;
}

}  // namespace ropecast
