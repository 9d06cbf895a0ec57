// The texel layout of the rope index (the octree with neighbor pointers of Gobbetti et al. 2008, Sect. 5.1),
// defined once for the C++ encoder (index/rope_index.cpp) and the GLSL traversal
// (shaders/rope_traversal.glsl), which includes this file through the shader loader's textual #include.
// Constants and pure functions only; any thread. docs/INDEX.md has the same layout as tables.
//
// The index is an array of uvec4 texels (GL_RGBA32UI buffer texture, read with texelFetch on a
// usamplerBuffer).
//
// Node texel, one per octree node. Texel 0 is the root. The 8 children of an inner node are consecutive,
// child (x, y, z) in {0,1}^3 at firstChild + x + 2y + 4z (x fastest).
//   .x  tag: kRopeTagInner, kRopeTagDataLeaf, kRopeTagEmptyLeaf or kRopeTagSolidLeaf
//   .y  inner: texel of the first child.   leaf: texel of the leaf's rope block
//   .z  data leaf: brick slot in the GPU pool.   otherwise kRopeNoBrick
//   .w  leaf: index of the leaf in Cut::leaves (for feedback).   inner: the node's depth (informational)
//
// Rope block, kRopeBlockTexels texels per leaf: neighbor word of face f is component f % 4 of texel
// ropeBlock + f / 4. Faces: 0 -x, 1 +x, 2 -y, 3 +y, 4 -z, 5 +z (face = 2 * axis + (positive ? 1 : 0)). Words
// 6 and 7 are kRopeNull, so "no exit face" can index the block too (as in Gobbetti et al. 2008).
//
// Neighbor word: kRopeNull across a face of the root cube; otherwise (node texel << kRopeDepthBits) | depth
// of that node. The node is the adjacent node of the leaf's depth, or the smallest coarser leaf enclosing the
// adjacent region; it may be an inner node of the same depth, from which the traversal descends.
#ifndef ROPECAST_INDEX_ROPE_LAYOUT_H
#define ROPECAST_INDEX_ROPE_LAYOUT_H

#ifdef __cplusplus
#include <cstdint>
namespace ropecast {
using uint = std::uint32_t;
#define ROPE_CONST inline constexpr uint
#define ROPE_FN inline constexpr
#else
#define ROPE_CONST const uint
#define ROPE_FN
#endif

ROPE_CONST kRopeTexelComponents = 4u;  // uvec4 texels

// Node texel fields (component index).
ROPE_CONST kRopeNodeTag = 0u;
ROPE_CONST kRopeNodePointer = 1u;
ROPE_CONST kRopeNodeBrickSlot = 2u;
ROPE_CONST kRopeNodeLeafIndex = 3u;  // inner nodes: depth

// Node tags. 0 is never a tag, so a zeroed texel is recognisably invalid.
ROPE_CONST kRopeTagInner = 1u;
ROPE_CONST kRopeTagDataLeaf = 2u;
ROPE_CONST kRopeTagEmptyLeaf = 3u;
// An empty leaf whose values all lie above the isovalue: skipped like an empty one, but a ray whose first
// sample it holds is capped there (docs/RENDERING.md "Caps").
ROPE_CONST kRopeTagSolidLeaf = 4u;

ROPE_CONST kRopeNoBrick = 0xFFFFFFFFu;  // brick slot field of empty leaves and inner nodes

// Faces and the rope block.
ROPE_CONST kRopeFaceCount = 6u;
ROPE_CONST kRopeBlockTexels = 2u;  // 8 words: the 6 faces, then 2 x kRopeNull
ROPE_CONST kRopeNull = 0xFFFFFFFFu;

// Neighbor word packing.
ROPE_CONST kRopeDepthBits = 5u;
ROPE_CONST kRopeDepthMask = 31u;
ROPE_CONST kRopeMaxDepth = 20u;           // deepest node (== kCutMaxDepth)
ROPE_CONST kRopeMaxTexels = 0x07FFFFFFu;  // node texels must lie below this (27-bit pointers)
ROPE_CONST kRopeMaxHopsPerLeaf = 4096u;   // safety cap on zero-length hops inside one ropeNextLeaf

ROPE_FN uint ropeFace(uint axis, bool positive) {
  return 2u * axis + (positive ? 1u : 0u);
}
ROPE_FN uint ropeFaceAxis(uint face) {
  return face >> 1u;
}
ROPE_FN bool ropeFaceIsPositive(uint face) {
  return (face & 1u) == 1u;
}
ROPE_FN uint ropeChildOffset(uint x, uint y, uint z) {
  return x + 2u * y + 4u * z;
}
ROPE_FN uint ropeNeighborWord(uint nodeTexel, uint depth) {
  return (nodeTexel << kRopeDepthBits) | depth;
}
ROPE_FN uint ropeNeighborNode(uint word) {
  return word >> kRopeDepthBits;
}
ROPE_FN uint ropeNeighborDepth(uint word) {
  return word & kRopeDepthMask;
}
ROPE_FN uint ropeFaceTexel(uint ropeBlock, uint face) {
  return ropeBlock + face / 4u;
}
ROPE_FN uint ropeFaceComponent(uint face) {
  return face % 4u;
}

#ifdef __cplusplus
static_assert(kRopeTexelComponents == 4u);
static_assert(kRopeNodeTag < kRopeTexelComponents && kRopeNodePointer < kRopeTexelComponents &&
              kRopeNodeBrickSlot < kRopeTexelComponents && kRopeNodeLeafIndex < kRopeTexelComponents);
static_assert(kRopeTagInner != 0u && kRopeTagDataLeaf != 0u && kRopeTagEmptyLeaf != 0u &&
              kRopeTagSolidLeaf != 0u);
static_assert(kRopeTagInner != kRopeTagDataLeaf && kRopeTagDataLeaf != kRopeTagEmptyLeaf &&
              kRopeTagInner != kRopeTagEmptyLeaf && kRopeTagSolidLeaf != kRopeTagInner &&
              kRopeTagSolidLeaf != kRopeTagDataLeaf && kRopeTagSolidLeaf != kRopeTagEmptyLeaf);
static_assert(kRopeBlockTexels * kRopeTexelComponents >= kRopeFaceCount + 1u,
              "room for the faces and a NULL");
static_assert(kRopeMaxDepth <= kRopeDepthMask, "depth fits its bits");
static_assert(kRopeDepthMask == (1u << kRopeDepthBits) - 1u);
static_assert(uint64_t(kRopeMaxTexels) << kRopeDepthBits <= 0xFFFFFFFFull, "pointer fits its bits");
static_assert(ropeNeighborWord(kRopeMaxTexels - 1u, kRopeMaxDepth) != kRopeNull, "NULL is not a valid word");
static_assert(ropeFace(2u, true) == 5u && ropeFaceAxis(5u) == 2u && ropeFaceIsPositive(5u));
}  // namespace ropecast
#endif

#undef ROPE_CONST
#undef ROPE_FN

#endif  // ROPECAST_INDEX_ROPE_LAYOUT_H
