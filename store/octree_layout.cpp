#include "store/octree_layout.h"

#include <algorithm>
#include <stdexcept>

namespace ropecast {

namespace {
uint32_t ceilDiv(uint32_t a, uint32_t b) {
  return (a + b - 1) / b;
}
uint32_t ceilShift(uint32_t a, uint32_t s) {
  return uint32_t((uint64_t(a) + (uint64_t(1) << s) - 1) >> s);
}
}  // namespace

OctreeLayout OctreeLayout::forVolume(glm::u32vec3 dims, uint32_t brickSize) {
  if (dims.x == 0 || dims.y == 0 || dims.z == 0) throw std::invalid_argument("OctreeLayout: empty volume");
  if (brickSize < 4 || brickSize > 256)
    throw std::invalid_argument("OctreeLayout: brick size must be in [4, 256]");
  OctreeLayout l;
  l.dims = dims;
  l.brickSize = brickSize;
  const uint32_t bricks =
      std::max({ceilDiv(dims.x, brickSize), ceilDiv(dims.y, brickSize), ceilDiv(dims.z, brickSize)});
  while ((1u << l.maxDepth) < bricks) ++l.maxDepth;
  uint64_t offset = 0;
  for (uint32_t d = 0; d <= l.maxDepth; ++d) {
    const glm::u32vec3 n = l.levelDims(l.levelOfDepth(d));
    l.insideNodes_.push_back({ceilDiv(n.x, brickSize), ceilDiv(n.y, brickSize), ceilDiv(n.z, brickSize)});
    l.depthOffsets_.push_back(offset);
    offset += l.insideNodeCount(d);
  }
  l.depthOffsets_.push_back(offset);
  return l;
}

glm::u32vec3 OctreeLayout::levelDims(uint32_t level) const {
  return {ceilShift(dims.x, level), ceilShift(dims.y, level), ceilShift(dims.z, level)};
}

bool OctreeLayout::isInside(const NodeKey& k) const {
  if (k.depth > maxDepth) return false;
  const glm::u32vec3 n = insideNodes(k.depth);
  return k.coord.x < n.x && k.coord.y < n.y && k.coord.z < n.z;
}

uint64_t OctreeLayout::insideNodeCount(uint32_t depth) const {
  const glm::u32vec3 n = insideNodes(depth);
  return uint64_t(n.x) * n.y * n.z;
}

uint64_t OctreeLayout::insideNodeCount() const {
  return depthOffsets_.empty() ? 0 : depthOffsets_.back();
}

uint64_t OctreeLayout::nodeIndex(const NodeKey& k) const {
  const glm::u32vec3 n = insideNodes(k.depth);
  return depthOffsets_[k.depth] + k.coord.x + uint64_t(n.x) * (k.coord.y + uint64_t(n.y) * k.coord.z);
}

NodeKey OctreeLayout::nodeAt(uint64_t index) const {
  uint32_t d = 0;
  while (d + 1 < depthOffsets_.size() - 1 && depthOffsets_[d + 1] <= index) ++d;
  const glm::u32vec3 n = insideNodes(d);
  uint64_t i = index - depthOffsets_[d];
  NodeKey k;
  k.depth = d;
  k.coord.x = uint32_t(i % n.x);
  i /= n.x;
  k.coord.y = uint32_t(i % n.y);
  k.coord.z = uint32_t(i / n.y);
  return k;
}

}  // namespace ropecast
