// The CPU reference of the stackless rope-octree traversal (Gobbetti et al. 2008, Sect. 5.2, Fig. 5): step
// for step the algorithm of shaders/rope_traversal.glsl, in float like the GPU, with the same names. It is
// what the index and shader tests compare with. Pure functions over a caller-owned cursor; any thread.
//
// The ray is P(t) = origin + t * dir in root-cube coordinates ([0,1]^3; dir need not be normalized), so t is
// the caller's own (world) t. The traversal hands out the leaves pierced over [tStart, tEnd], front to back,
// each with [tEnter, tExit); consecutive leaves chain exactly (tExit == next tEnter).
//
// Robustness: every decision is made in t, with one formula for the t of an axis plane, ropePlaneT (the GLSL
// twin marks it `precise`). The down traversal's step(center) test becomes "has the ray reached the center
// plane at tEnter" (ties go to the side the ray is moving into), and a box's exit is the least of its exit
// planes' t. Because ropePlaneT is monotone in the plane, the boxes' [tEnter, tExit) intervals partition the
// ray exactly, with no epsilon, at any depth: a point on a shared face goes to the box the ray enters. A box
// the ray touches over a zero-length interval (an edge or corner crossing, or planes whose t rounds together)
// is stepped through without being reported. An axis whose dir component is 0 (or so small that 1/dir
// overflows) does not move: the ray is in a box when boxMin <= origin < boxMax on that axis (<= 1 at the
// root's top face).
#pragma once

#include <cstdint>

#include <glm/vec3.hpp>

#include "index/rope_index.h"
#include "index/rope_layout.h"

namespace ropecast {

struct RopeCursor {
  glm::vec3 origin{0.0f};
  glm::vec3 invDir{0.0f};     // 1/dir on moving axes, 0 on axes that do not move
  float tEnter = 0.0f;        // where the next leaf begins
  float tEnd = 0.0f;          // min(caller's tEnd, where the ray leaves the root cube)
  uint32_t node = kRopeNull;  // node texel where the next down traversal starts; kRopeNull when done
  uint32_t depth = 0;         // depth of that node
  glm::vec3 boxMin{0.0f};     // box of that node
  float boxSize = 1.0f;
};

struct RopeLeaf {
  uint32_t kind = kRopeTagEmptyLeaf;  // kRopeTagDataLeaf, kRopeTagEmptyLeaf or kRopeTagSolidLeaf
  uint32_t brickSlot = kRopeNoBrick;  // data leaves only
  uint32_t leafIndex = 0;             // index in the Cut's leaves
  uint32_t depth = 0;
  glm::vec3 boxMin{0.0f};
  float boxSize = 1.0f;  // 2^-depth
  float tEnter = 0.0f;
  float tExit = 0.0f;
};

// The t at which the ray crosses the plane {x_axis = plane}: (plane - origin) * invDir, one rounding each.
inline float ropePlaneT(float plane, float origin, float invDir) {
  return (plane - origin) * invDir;
}

// 2^-depth and 2^depth, exact (built from the exponent bits, as in the shader).
float ropeBoxSize(uint32_t depth);
float ropeBoxScale(uint32_t depth);

// Clips the ray to the root cube and [tStart, tEnd]; false when that leaves nothing (the ray misses, or
// touches the cube over a zero-length interval). Needs no index access.
bool ropeBegin(RopeCursor& cursor, const RopeIndex& index, glm::vec3 origin, glm::vec3 dir, float tStart,
               float tEnd);

// The next leaf along the ray, front to back; false when the ray has left the cube or reached tEnd. Throws
// std::invalid_argument if the index points outside itself.
bool ropeNextLeaf(RopeCursor& cursor, const RopeIndex& index, RopeLeaf& leaf);

}  // namespace ropecast
