// Cut: the current leaves of the octree (what the loader's refinement chose for this frame), the input of the
// rope index. Plain data and pure functions owned by index/; any thread (no shared state).
//
// The root cube [0,1]^3 is depth 0; a leaf at depth d with coord c covers [c, c+1) * 2^-d. The leaves of a
// valid cut tile the root cube exactly: no holes, no overlaps. Regions outside the volume and empty regions
// are Empty leaves; Data leaves name the slot of their brick in the GPU brick pool.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace ropecast {

// Deepest level the index and its float traversal support: box bounds k * 2^-20 stay exact in float and a
// box spans at least 16 float ulps anywhere in [0,1].
inline constexpr uint32_t kCutMaxDepth = 20;

// Solid: an Empty leaf whose values all lie above the isovalue, which caps a ray entering it through a cut
// (docs/RENDERING.md "Caps").
enum class LeafKind : uint8_t { Empty, Data, Solid };

struct CutLeaf {
  uint32_t depth = 0;     // 0 = root cube [0,1]^3
  glm::u32vec3 coord{0};  // at that depth, each in [0, 2^depth)
  LeafKind kind = LeafKind::Empty;
  uint32_t brickSlot = 0;  // slot of the brick in the GPU pool; only meaningful for Data leaves

  friend bool operator==(const CutLeaf&, const CutLeaf&) = default;
};

struct Cut {
  std::vector<CutLeaf> leaves;
};

// Throws std::invalid_argument naming the first problem found: a depth above kCutMaxDepth, a coord outside
// its depth, a Data leaf whose brickSlot is 0xFFFFFFFF (reserved), two leaves overlapping, or a hole.
void validateCut(const Cut& cut);

// Whether two cuts have the same leaves (place, kind and brick slot) in any order: the order is the caller's,
// and the loader's can change from frame to frame while the cut does not.
bool sameLeaves(const Cut& a, const Cut& b);

// Completes leaves that tile part of the cube into a valid cut by adding Empty leaves: every sibling of a
// given leaf or of one of its ancestors that no given leaf covers becomes an Empty leaf. The given leaves
// come first, in order. No leaves at all gives one Empty root. Throws std::invalid_argument as validateCut
// for overlaps and bad leaves.
Cut completeCut(std::span<const CutLeaf> leaves);

}  // namespace ropecast
