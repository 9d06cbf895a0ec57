// The stackless rope-octree traversal (Gobbetti et al. 2008, Sect. 5.2, Fig. 5), the GLSL twin of index/rope_traversal.h:
// same names, same steps, same float formulas (read that header for the robustness argument: every decision
// is made in t with ropePlaneT, marked `precise` here so the compiler cannot fuse or reorder it differently in
// the down traversal and the box clip). Include it from any entry point (fragment or compute); it declares the
// index sampler. No #version line: the including shader has it (GLSL 4.50 core).
//
// Use:
//   RopeCursor cursor;
//   if (ropeBegin(cursor, origin, dir, tStart, tEnd)) {
//     RopeLeaf leaf;
//     while (ropeNextLeaf(cursor, leaf)) { if (leaf.kind == kRopeTagDataLeaf) { ... } }
//   }
// origin/dir are the ray in root-cube coordinates ([0,1]^3); t is the caller's own t.

#include "index/rope_layout.h"

uniform usamplerBuffer uRopeIndex;  // GL_RGBA32UI buffer texture holding RopeIndex::texels

struct RopeCursor {
  vec3 origin;
  vec3 invDir;   // 1/dir on moving axes, 0 on axes that do not move
  float tEnter;  // where the next leaf begins
  float tEnd;    // min(caller's tEnd, where the ray leaves the root cube)
  uint node;     // node texel where the next down traversal starts; kRopeNull when done
  uint depth;    // depth of that node
  vec3 boxMin;   // box of that node
  float boxSize;
};

struct RopeLeaf {
  uint kind;       // kRopeTagDataLeaf, kRopeTagEmptyLeaf or kRopeTagSolidLeaf
  uint brickSlot;  // data leaves only
  uint leafIndex;  // index in the Cut's leaves
  uint depth;
  vec3 boxMin;
  float boxSize;  // 2^-depth
  float tEnter;
  float tExit;
};

uvec4 ropeFetch(uint texel) { return texelFetch(uRopeIndex, int(texel)); }

// The t at which the ray crosses the plane {x_axis = plane}, componentwise: one subtraction, one product.
vec3 ropePlaneT(vec3 plane, vec3 origin, vec3 invDir) {
  precise vec3 t = (plane - origin) * invDir;
  return t;
}

// 2^-depth and 2^depth, exact (exp2 need not be).
float ropeBoxSize(uint depth) { return uintBitsToFloat((127u - depth) << 23u); }
float ropeBoxScale(uint depth) { return uintBitsToFloat((127u + depth) << 23u); }

bool ropeBegin(inout RopeCursor c, vec3 origin, vec3 dir, float tStart, float tEnd) {
  c.origin = origin;
  c.node = kRopeNull;
  float tEnter = tStart;
  float tExit = tEnd;
  for (uint axis = 0u; axis < 3u; ++axis) {
    float inv = dir[axis] != 0.0 ? 1.0 / dir[axis] : 0.0;
    c.invDir[axis] = (isinf(inv) || isnan(inv)) ? 0.0 : inv;
    if (c.invDir[axis] == 0.0) {
      if (!(origin[axis] >= 0.0 && origin[axis] <= 1.0)) return false;
    }
  }
  vec3 tAtZero = ropePlaneT(vec3(0.0), origin, c.invDir);
  vec3 tAtOne = ropePlaneT(vec3(1.0), origin, c.invDir);
  for (uint axis = 0u; axis < 3u; ++axis) {
    if (c.invDir[axis] == 0.0) continue;
    bool positive = c.invDir[axis] > 0.0;
    tEnter = max(tEnter, positive ? tAtZero[axis] : tAtOne[axis]);
    tExit = min(tExit, positive ? tAtOne[axis] : tAtZero[axis]);
  }
  if (!(tEnter < tExit)) return false;
  c.tEnter = tEnter;
  c.tEnd = tExit;
  c.node = 0u;
  c.depth = 0u;
  c.boxMin = vec3(0.0);
  c.boxSize = 1.0;
  return true;
}

bool ropeNextLeaf(inout RopeCursor c, out RopeLeaf leaf) {
  bvec3 moving = notEqual(c.invDir, vec3(0.0));
  bvec3 positive = greaterThan(c.invDir, vec3(0.0));
  for (uint hop = 0u; hop < kRopeMaxHopsPerLeaf; ++hop) {
    if (c.node == kRopeNull) return false;

    // Down traversal to the leaf holding the ray at tEnter, by box subdivision. step(center) in t: has the ray
    // reached the center plane (ties go to the side it moves into); a still axis compares the origin.
    uvec4 node = ropeFetch(c.node);
    while (node[kRopeNodeTag] == kRopeTagInner) {
      c.boxSize *= 0.5;
      vec3 center = c.boxMin + vec3(c.boxSize);
      vec3 tCenter = ropePlaneT(center, c.origin, c.invDir);
      bvec3 reached = greaterThanEqual(vec3(c.tEnter), tCenter);
      bvec3 notReached = lessThan(vec3(c.tEnter), tCenter);
      bvec3 still = greaterThanEqual(c.origin, center);
      uvec3 s = uvec3(mix(still, mix(notReached, reached, positive), moving));
      c.boxMin = mix(c.boxMin, center, bvec3(s));
      c.node = node[kRopeNodePointer] + ropeChildOffset(s.x, s.y, s.z);
      node = ropeFetch(c.node);
      ++c.depth;
    }

    // Clip the ray to the box: the exit face is the first exit plane reached (kRopeFaceCount: none before tEnd).
    vec3 tPlane = ropePlaneT(c.boxMin + vec3(positive) * c.boxSize, c.origin, c.invDir);
    float tExit = c.tEnd;
    uint exitFace = kRopeFaceCount;
    for (uint axis = 0u; axis < 3u; ++axis) {
      if (moving[axis] && tPlane[axis] < tExit) {
        tExit = tPlane[axis];
        exitFace = ropeFace(axis, positive[axis]);
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
    uint ropeBlock = node[kRopeNodePointer];
    uint word = ropeFetch(ropeFaceTexel(ropeBlock, exitFace))[ropeFaceComponent(exitFace)];
    if (word == kRopeNull) {
      c.node = kRopeNull;
    } else {
      uint axis = ropeFaceAxis(exitFace);
      c.boxMin[axis] += ropeFaceIsPositive(exitFace) ? c.boxSize : -c.boxSize;
      c.node = ropeNeighborNode(word);
      c.depth = ropeNeighborDepth(word);
      c.boxSize = ropeBoxSize(c.depth);
      c.boxMin = floor(c.boxMin * ropeBoxScale(c.depth)) * c.boxSize;
      c.tEnter = tExit;
    }
    if (tExit > leaf.tEnter) return true;  // zero-length boxes are stepped through, not reported
  }
  c.node = kRopeNull;  // safety cap (kRopeMaxHopsPerLeaf): end the ray rather than loop
  return false;
}
