// RopeIndex: the octree with neighbor pointers ("rope octree", Gobbetti et al. 2008, Sect. 5.1) over a Cut,
// encoded as the texels of index/rope_layout.h, ready to upload into a GL buffer texture. Rebuilt every
// frame.
//
// RopeIndexBuilder owns reusable buffers: one per thread (not thread-safe); build() allocates nothing once
// its buffers have grown to the frame's size. buildRopeIndex() is the one-shot convenience. Time and memory
// are linear in the number of leaves (each node is visited once; inserting a leaf walks its depth, <= 20).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec4.hpp>

#include "index/cut.h"
#include "index/cut_tree.h"
#include "index/rope_layout.h"

namespace ropecast {

using RopeTexel = glm::u32vec4;
static_assert(sizeof(RopeTexel) == kRopeTexelComponents * sizeof(uint32_t));

struct RopeIndex {
  std::vector<RopeTexel> texels;  // node texels [0, nodeCount), then the rope blocks of the leaves
  uint32_t maxDepth = 0;          // deepest leaf
  uint32_t nodeCount = 0;         // inner nodes + leaves
  uint32_t leafCount = 0;
  std::vector<uint32_t> leafNodeTexel;  // per Cut::leaves entry: its node texel

  uint64_t bytes() const { return texels.size() * sizeof(RopeTexel); }
};

class RopeIndexBuilder {
 public:
  // Validates the cut (throws std::invalid_argument as validateCut) and encodes it into `out`, reusing out's
  // storage.
  void build(const Cut& cut, RopeIndex& out);

 private:
  CutTree tree_;
  std::vector<uint32_t> ropes_;  // kRopeFaceCount neighbor words per node
};

RopeIndex buildRopeIndex(const Cut& cut);

}  // namespace ropecast
