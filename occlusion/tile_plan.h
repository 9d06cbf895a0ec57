// planTiles: the screen-space subdivision of Gobbetti et al. 2008, Sect. 6, which separates the nodes whose
// visibility is queried this frame from the rest of the image. The screen is cut into tiles; the first tile
// holds the projections of the queried nodes entirely, so the ray caster draws it first, the occlusion
// queries follow it, and the GPU answers them while it ray casts the other tiles. Plain data and a pure
// function; any thread.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "occlusion/screen_rect.h"

namespace ropecast {

// A node that could be queried: `id` is the caller's (an index into its list), `rect` its projection.
struct QueryCandidate {
  uint32_t id = 0;
  ScreenRect rect;
};

struct TilePlanConfig {
  // --query-budget: queries per frame. A query is one box drawn against the depth buffer; a cold cut of about
  // 10 000 leaves is covered in a few frames.
  uint32_t queryBudget = 4096;
  int32_t minTilePixels = 64;  // splitting stops when the tile's longer side is below this
};

struct TilePlan {
  // Cover the viewport exactly once, without overlap; tiles[0] is the query tile (cast first). Always at
  // least one tile (for a zero-sized viewport, that empty viewport).
  std::vector<ScreenRect> tiles;
  // Candidate ids to query after tiles[0]: each rect entirely inside tiles[0]; at most queryBudget.
  std::vector<uint32_t> queried;
};

// The 2D binary space partition of Gobbetti et al. 2008, Sect. 6. The current tile starts as the viewport and
// the current subset as the candidates entirely inside it (rects are clipped to the viewport first; a rect
// with no pixel in it is never queried). Each step splits the current tile at the median of the subset's
// rectangle centers along one axis, axes alternating (the first along the longer side), into two tiles;
// candidates straddling the split belong to neither half. Splitting continues into the half holding more of
// the subset entirely inside it (ties: `frame` parity picks, so the choice rotates between frames); the other
// half is a finished tile.
//
// Splitting stops when the subset fits the budget (all of it is queried), when the tile's longer side is
// below minTilePixels, or when no split along either axis leaves at least half the budget in the better half
// (a degenerate split: all centers equal, the median on the tile's border, or most of the subset straddling).
// In the last two cases the first queryBudget of the subset, in candidate order, are queried. So a frame
// queries min(budget, subset) >= min(budget / 2, candidates) nodes: a caller that drops the queried ones
// from its next frame's candidates covers them all in a bounded number of frames.
TilePlan planTiles(uint32_t width, uint32_t height, std::span<const QueryCandidate> candidates,
                   const TilePlanConfig& config, uint64_t frame);

}  // namespace ropecast
