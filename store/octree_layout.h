// OctreeLayout: the geometry of the bricked octree over a volume, shared by the converter, the store, the
// loader and the renderer. Plain data and pure functions; any thread.
//
// Bricks hold B^3 samples (B = brickSize) plus a replicated border of kBrickBorder samples on every side,
// so a stored brick has (B + 2*kBrickBorder)^3 samples: enough for trilinear filtering and central-difference
// gradients of trilinear samples without ever reading across a brick edge.
//
// The octree subdivides the smallest cube of 2^k bricks that holds the volume. Depth 0 is the root; the
// leaves of the full tree sit at depth k = maxDepth and hold the original samples. The *resolution level* of
// a depth is L = maxDepth - depth (0 = full resolution), and level L has ceil(n / 2^L) samples per axis: each
// is the 2x2x2 box filter of level L-1 (at an odd edge the last sample repeats).
//
// Node (depth d, coord c) covers samples [c*B, (c+1)*B) of its level's grid. Nodes with any such sample
// inside the level's dims are "inside"; the others are outside the data and never stored.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace ropecast {

inline constexpr uint32_t kBrickBorder = 2;
inline constexpr uint32_t kDefaultBrickSize = 32;

struct NodeKey {
  uint32_t depth = 0;     // 0 = root
  glm::u32vec3 coord{0};  // node coordinate at its depth, each in [0, 2^depth)

  friend bool operator==(const NodeKey&, const NodeKey&) = default;
  NodeKey parent() const { return {depth - 1, coord / 2u}; }
  NodeKey child(uint32_t octant) const {  // octant bit 0 = +x, bit 1 = +y, bit 2 = +z
    return {depth + 1, coord * 2u + glm::u32vec3(octant & 1u, (octant >> 1) & 1u, (octant >> 2) & 1u)};
  }
};

struct NodeKeyHash {
  size_t operator()(const NodeKey& k) const {
    uint64_t h = k.depth;
    h = h * 0x9E3779B97F4A7C15ull ^ k.coord.x;
    h = h * 0x9E3779B97F4A7C15ull ^ k.coord.y;
    h = h * 0x9E3779B97F4A7C15ull ^ k.coord.z;
    return size_t(h ^ (h >> 29));
  }
};

struct OctreeLayout {
  glm::u32vec3 dims{0};  // level-0 samples per axis
  uint32_t brickSize = kDefaultBrickSize;
  uint32_t maxDepth = 0;  // depth of the full-resolution leaves

  static OctreeLayout forVolume(glm::u32vec3 dims, uint32_t brickSize);

  uint32_t storedBrickEdge() const { return brickSize + 2 * kBrickBorder; }
  uint64_t storedBrickSamples() const {
    const uint64_t e = storedBrickEdge();
    return e * e * e;
  }
  uint32_t levelOfDepth(uint32_t depth) const { return maxDepth - depth; }
  // Samples per axis at a resolution level: ceil(dims / 2^level).
  glm::u32vec3 levelDims(uint32_t level) const;
  // Nodes per axis at a depth that are inside the data: ceil(levelDims / brickSize); none deeper than
  // maxDepth or in a layout not made by forVolume.
  glm::u32vec3 insideNodes(uint32_t depth) const {
    return depth < insideNodes_.size() ? insideNodes_[depth] : glm::u32vec3(0);
  }
  bool isInside(const NodeKey& k) const;
  // Dense numbering of the inside nodes, depth by depth from the root, x fastest within a depth.
  uint64_t insideNodeCount() const;
  uint64_t insideNodeCount(uint32_t depth) const;
  uint64_t nodeIndex(const NodeKey& k) const;  // k must be inside
  NodeKey nodeAt(uint64_t index) const;        // inverse of nodeIndex
  // Edge of the octree's root cube in level-0 samples: brickSize * 2^maxDepth.
  uint64_t cubeSamples() const { return uint64_t(brickSize) << maxDepth; }

 private:
  // Filled by forVolume, per depth (the refinement asks for them at every node it reaches).
  std::vector<uint64_t> depthOffsets_;
  std::vector<glm::u32vec3> insideNodes_;
};

}  // namespace ropecast
