// CutTree: the octree skeleton of a set of leaves, the shared first step of validateCut, completeCut and the
// rope index builder. Nodes live in one pool in creation order (a parent always before its children, the 8
// children of an inner node consecutive, x fastest), which is also the order of the index's node texels.
// Owned by its user and reused across frames (clear() keeps capacity); one thread at a time.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "index/cut.h"

namespace ropecast {

class CutTree {
 public:
  static constexpr uint32_t kNone = 0xFFFFFFFFu;

  struct Node {
    uint32_t firstChild = kNone;  // set when inner
    uint32_t leaf = kNone;        // index of the inserted leaf, set when leaf
    uint32_t depth = 0;
    bool isInner() const { return firstChild != kNone; }
    bool isLeaf() const { return leaf != kNone; }
    bool isHole() const { return !isInner() && !isLeaf(); }
  };

  void clear();  // back to a lone root hole
  // Inserts leaves[i] as leaf i for every i; throws std::invalid_argument naming a bad leaf or an overlap.
  void insert(std::span<const CutLeaf> leaves);
  // Throws std::invalid_argument naming the first hole (a region no leaf covers).
  void requireNoHoles() const;

  const std::vector<Node>& nodes() const { return nodes_; }
  std::vector<Node>& nodes() { return nodes_; }
  // Depth and coord of a node (walks up: for error messages and completion, not hot paths).
  CutLeaf placeOf(uint32_t node) const;

 private:
  std::vector<Node> nodes_;
  std::vector<uint32_t> parents_;  // per node
};

}  // namespace ropecast
