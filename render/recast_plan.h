// RecastPlan: which pixels a frame of a still view must cast again when its cut differs from the one the
// targets were last drawn with only in places (progressive frames: a few nodes refined or collapsed). A ray's
// color, depth, stop depth and feedback depend only on the leaves it passes through, the bricks they hold and
// the samples it takes in them (the sampling grid is anchored at the ray's entry into the volume, each leaf
// sampled at its level's step): a ray that meets no leaf that changed gives its pixel what it gave before.
// The pixels to cast are those of the changed leaves' boxes (both the leaves gone and the leaves new, whose
// screen rectangles hold every pixel whose ray meets them: occlusion/screen_rect.h), in blocks of kBlockSize
// pixels, one pixel wider than the rectangles for the GPU's rounding.
//
// Feedback (docs/RENDERING.md "Feedback") is an answer about the whole image: for the rays not cast, the
// answer about the drawn frame stands in. Which of a leaf's rays gave it is not known, so a leaf that answer
// lists as used or requested is listed again when some of its pixels are not cast (`keptIn`): it may be
// listed though only cast rays had used it and none does now, which keeps a node refined or refinable that
// a whole answer would let go (its occlusion query still judges it), and never lets detail go that rays
// use. Hits (enough rays stopped in the leaf to spare its query) are carried only for leaves none of whose
// pixels is cast (`keptWhole`): listed wrongly, a hit would spare a query that is needed.
//
// Plain data and a pure function; any thread.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "core/camera.h"
#include "loader/refiner.h"
#include "render/raycast_uniforms.h"
#include "store/octree_layout.h"

namespace ropecast {

// The leaves of a drawn cut: node -> the pool slot of its brick, kEmptyLeafSlot for an empty leaf.
using DrawnLeaves = std::unordered_map<NodeKey, uint32_t, NodeKeyHash>;
constexpr uint32_t kEmptyLeafSlot = UINT32_MAX;
// What DrawnLeaves holds for a leaf.
inline uint32_t drawnSlotOf(const PlannedLeaf& leaf) {
  return leaf.content == LeafContent::Brick ? leaf.slot : kEmptyLeafSlot;
}

struct RecastInput {
  Camera camera;
  uint32_t width = 0, height = 0;
  const OctreeLayout* layout = nullptr;
  glm::dvec3 spacing{1.0};
  const DrawnLeaves* drawn = nullptr;                // the cut the targets hold the image of
  const std::vector<PlannedLeaf>* leaves = nullptr;  // this frame's cut, in its order
  // The leaves the rays' answer about the drawn frame lists (used, requested or hit); null: no feedback.
  const std::unordered_set<NodeKey, NodeKeyHash>* answered = nullptr;
};

struct RecastPlan {
  static constexpr uint32_t kBlockSize = 16;  // pixels on a side; the cast pixels are whole blocks

  // Cast the whole image: a changed leaf's box holds the eye or reaches behind it.
  bool whole = false;
  // The pixels to cast, as disjoint rectangles (row 0 at the top), clipped to the image; empty when nothing
  // changed. Unused when `whole`.
  std::vector<PixelRect> rects;
  uint64_t pixels = 0;  // pixels in `rects` (width * height when `whole`)
  // Indices into RecastInput::leaves of the answered leaves some of whose pixels are not cast, and of those
  // none of whose pixels is (a subset).
  std::vector<uint32_t> keptIn, keptWhole;
  uint32_t changedLeaves = 0;  // leaves gone, new, or holding another slot
};

RecastPlan planRecast(const RecastInput& input);

}  // namespace ropecast
