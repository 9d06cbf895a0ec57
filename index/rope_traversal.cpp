// CPU reference traversal. Keep it step for step with shaders/rope_traversal.glsl (which does the per-axis
// arithmetic as vec3 operations: the same operations, component by component).
#include "index/rope_traversal.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>

#include <glm/common.hpp>

namespace ropecast {

namespace {

const RopeTexel& ropeFetch(const RopeIndex& index, uint32_t texel) {
  if (texel >= index.texels.size())
    throw std::invalid_argument("ropeNextLeaf: the index points at texel " + std::to_string(texel) +
                                " outside its " + std::to_string(index.texels.size()) + " texels");
  return index.texels[texel];
}

// Is the ray, at time t, on the high side of the plane {x_axis = center}? Ties go to the side it moves into.
bool ropeIsHighSide(const RopeCursor& c, uint32_t axis, float center, float t) {
  const float inv = c.invDir[axis];
  if (inv == 0.0f) return c.origin[axis] >= center;
  const float tCenter = ropePlaneT(center, c.origin[axis], inv);
  return inv > 0.0f ? t >= tCenter : t < tCenter;
}

}  // namespace

float ropeBoxSize(uint32_t depth) {
  return std::bit_cast<float>((127u - depth) << 23);
}
float ropeBoxScale(uint32_t depth) {
  return std::bit_cast<float>((127u + depth) << 23);
}

bool ropeBegin(RopeCursor& c, const RopeIndex& index, glm::vec3 origin, glm::vec3 dir, float tStart,
               float tEnd) {
  c.origin = origin;
  c.node = kRopeNull;
  float tEnter = tStart;
  float tExit = tEnd;
  for (uint32_t axis = 0; axis < 3; ++axis) {
    const float inv = 1.0f / dir[axis];
    c.invDir[axis] = std::isfinite(inv) ? inv : 0.0f;
    if (c.invDir[axis] == 0.0f) {
      if (!(origin[axis] >= 0.0f && origin[axis] <= 1.0f)) return false;
      continue;
    }
    const float tAtZero = ropePlaneT(0.0f, origin[axis], c.invDir[axis]);
    const float tAtOne = ropePlaneT(1.0f, origin[axis], c.invDir[axis]);
    const bool positive = c.invDir[axis] > 0.0f;
    tEnter = std::max(tEnter, positive ? tAtZero : tAtOne);
    tExit = std::min(tExit, positive ? tAtOne : tAtZero);
  }
  if (!(tEnter < tExit)) return false;
  c.tEnter = tEnter;
  c.tEnd = tExit;
  c.node = 0;
  c.depth = 0;
  c.boxMin = glm::vec3(0.0f);
  c.boxSize = 1.0f;
  return true;
}

bool ropeNextLeaf(RopeCursor& c, const RopeIndex& index, RopeLeaf& leaf) {
  for (uint32_t hop = 0; hop < kRopeMaxHopsPerLeaf; ++hop) {
    if (c.node == kRopeNull) return false;

    // Down traversal to the leaf holding the ray at tEnter, by box subdivision.
    RopeTexel node = ropeFetch(index, c.node);
    while (node[kRopeNodeTag] == kRopeTagInner) {
      c.boxSize *= 0.5f;
      uint32_t octant = 0;
      for (uint32_t axis = 0; axis < 3; ++axis) {
        const float center = c.boxMin[axis] + c.boxSize;
        if (ropeIsHighSide(c, axis, center, c.tEnter)) {
          c.boxMin[axis] = center;
          octant |= 1u << axis;
        }
      }
      c.node = node[kRopeNodePointer] + octant;
      node = ropeFetch(index, c.node);
      ++c.depth;
    }

    // Clip the ray to the box: the exit face is the first exit plane reached (kRopeFaceCount: none before
    // tEnd).
    float tExit = c.tEnd;
    uint32_t exitFace = kRopeFaceCount;
    for (uint32_t axis = 0; axis < 3; ++axis) {
      const float inv = c.invDir[axis];
      if (inv == 0.0f) continue;
      const bool positive = inv > 0.0f;
      const float tPlane = ropePlaneT(c.boxMin[axis] + (positive ? c.boxSize : 0.0f), c.origin[axis], inv);
      if (tPlane < tExit) {
        tExit = tPlane;
        exitFace = ropeFace(axis, positive);
      }
    }

    leaf.kind = node[kRopeNodeTag];
    leaf.brickSlot = node[kRopeNodeBrickSlot];
    leaf.leafIndex = node[kRopeNodeLeafIndex];
    leaf.depth = c.depth;
    leaf.boxMin = c.boxMin;
    leaf.boxSize = c.boxSize;
    leaf.tEnter = c.tEnter;
    leaf.tExit = tExit;

    // Follow the rope of the exit face (word 6 of the block is NULL: no exit face ends the ray) and snap the
    // shifted box to the neighbor's depth.
    const uint32_t ropeBlock = node[kRopeNodePointer];
    const uint32_t word = ropeFetch(index, ropeFaceTexel(ropeBlock, exitFace))[ropeFaceComponent(exitFace)];
    if (word == kRopeNull) {
      c.node = kRopeNull;
    } else {
      const uint32_t axis = ropeFaceAxis(exitFace);
      c.boxMin[axis] += ropeFaceIsPositive(exitFace) ? c.boxSize : -c.boxSize;
      c.node = ropeNeighborNode(word);
      c.depth = ropeNeighborDepth(word);
      c.boxSize = ropeBoxSize(c.depth);
      c.boxMin = glm::floor(c.boxMin * ropeBoxScale(c.depth)) * c.boxSize;
      c.tEnter = tExit;
    }
    if (tExit > leaf.tEnter) return true;  // zero-length boxes are stepped through, not reported
  }
  c.node = kRopeNull;  // safety cap (kRopeMaxHopsPerLeaf): end the ray rather than loop
  return false;
}

}  // namespace ropecast
