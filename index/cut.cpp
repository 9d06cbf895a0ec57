// Cut validation and completion, over the CutTree skeleton.
#include "index/cut.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <tuple>

#include "index/cut_tree.h"
#include "index/rope_layout.h"

namespace ropecast {

namespace {

std::string describe(const CutLeaf& leaf) {
  return "depth " + std::to_string(leaf.depth) + " coord (" + std::to_string(leaf.coord.x) + "," +
         std::to_string(leaf.coord.y) + "," + std::to_string(leaf.coord.z) + ")";
}

std::string describeIndexed(std::span<const CutLeaf> leaves, uint32_t i) {
  return "leaf " + std::to_string(i) + " (" + describe(leaves[i]) + ")";
}

}  // namespace

void CutTree::clear() {
  nodes_.clear();
  parents_.clear();
  nodes_.push_back(Node{});
  parents_.push_back(kNone);
}

void CutTree::insert(std::span<const CutLeaf> leaves) {
  static_assert(kCutMaxDepth == kRopeMaxDepth);
  for (uint32_t i = 0; i < leaves.size(); ++i) {
    const CutLeaf& leaf = leaves[i];
    if (leaf.depth > kCutMaxDepth)
      throw std::invalid_argument("validateCut: " + describeIndexed(leaves, i) +
                                  " is deeper than the maximum " + std::to_string(kCutMaxDepth));
    const uint32_t side = 1u << leaf.depth;
    if (leaf.coord.x >= side || leaf.coord.y >= side || leaf.coord.z >= side)
      throw std::invalid_argument("validateCut: " + describeIndexed(leaves, i) + " has a coord outside [0, " +
                                  std::to_string(side) + ") at its depth");
    if (leaf.kind == LeafKind::Data && leaf.brickSlot == kRopeNoBrick)
      throw std::invalid_argument("validateCut: " + describeIndexed(leaves, i) +
                                  " is a Data leaf with the reserved brick slot 0xFFFFFFFF");
    uint32_t node = 0;
    for (uint32_t level = 0; level < leaf.depth; ++level) {
      if (nodes_[node].isLeaf())
        throw std::invalid_argument("validateCut: " + describeIndexed(leaves, i) + " overlaps " +
                                    describeIndexed(leaves, nodes_[node].leaf));
      if (!nodes_[node].isInner()) {
        const auto first = uint32_t(nodes_.size());
        nodes_[node].firstChild = first;
        nodes_.resize(first + 8, Node{kNone, kNone, level + 1});
        parents_.resize(first + 8, node);
      }
      const uint32_t shift = leaf.depth - 1 - level;
      const uint32_t octant = ((leaf.coord.x >> shift) & 1u) | (((leaf.coord.y >> shift) & 1u) << 1) |
                              (((leaf.coord.z >> shift) & 1u) << 2);
      node = nodes_[node].firstChild + octant;
    }
    Node& target = nodes_[node];
    if (target.isLeaf())
      throw std::invalid_argument("validateCut: " + describeIndexed(leaves, i) + " overlaps " +
                                  describeIndexed(leaves, target.leaf));
    if (target.isInner())
      throw std::invalid_argument("validateCut: " + describeIndexed(leaves, i) +
                                  " overlaps finer leaves inserted before it");
    target.leaf = i;
  }
}

CutLeaf CutTree::placeOf(uint32_t node) const {
  CutLeaf place;
  place.depth = nodes_[node].depth;
  for (uint32_t bit = 0; parents_[node] != kNone; ++bit) {
    const uint32_t octant = node - nodes_[parents_[node]].firstChild;
    place.coord.x |= (octant & 1u) << bit;
    place.coord.y |= ((octant >> 1) & 1u) << bit;
    place.coord.z |= ((octant >> 2) & 1u) << bit;
    node = parents_[node];
  }
  return place;
}

void CutTree::requireNoHoles() const {
  for (uint32_t n = 0; n < nodes_.size(); ++n)
    if (nodes_[n].isHole())
      throw std::invalid_argument("validateCut: the leaves leave a hole at " + describe(placeOf(n)) +
                                  " (every point of the root cube needs exactly one leaf; see completeCut)");
}

bool sameLeaves(const Cut& a, const Cut& b) {
  if (a.leaves.size() != b.leaves.size()) return false;
  const auto byPlace = [](const CutLeaf& l, const CutLeaf& r) {
    return std::tie(l.depth, l.coord.x, l.coord.y, l.coord.z) <
           std::tie(r.depth, r.coord.x, r.coord.y, r.coord.z);
  };
  std::vector<CutLeaf> sortedA = a.leaves, sortedB = b.leaves;
  std::sort(sortedA.begin(), sortedA.end(), byPlace);
  std::sort(sortedB.begin(), sortedB.end(), byPlace);
  return sortedA == sortedB;
}

void validateCut(const Cut& cut) {
  CutTree tree;
  tree.clear();
  tree.insert(cut.leaves);
  tree.requireNoHoles();
}

Cut completeCut(std::span<const CutLeaf> leaves) {
  CutTree tree;
  tree.clear();
  tree.insert(leaves);
  Cut cut;
  cut.leaves.assign(leaves.begin(), leaves.end());
  for (uint32_t n = 0; n < tree.nodes().size(); ++n) {
    if (!tree.nodes()[n].isHole()) continue;
    CutLeaf empty = tree.placeOf(n);
    empty.kind = LeafKind::Empty;
    empty.brickSlot = 0;
    cut.leaves.push_back(empty);
  }
  return cut;
}

}  // namespace ropecast
