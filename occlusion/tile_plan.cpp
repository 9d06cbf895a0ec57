#include "occlusion/tile_plan.h"

#include <algorithm>
#include <optional>

namespace ropecast {

namespace {

struct Item {
  uint32_t id = 0;
  ScreenRect rect;  // clipped to the viewport, never empty
};

int32_t lowEdge(const ScreenRect& r, int axis) {
  return axis == 0 ? r.x0 : r.y0;
}
int32_t highEdge(const ScreenRect& r, int axis) {
  return axis == 0 ? r.x1 : r.y1;
}

struct Split {
  ScreenRect kept, finished;
};

// The split of `tile` at the median of the subset's centers along `axis`, continuing into the half with more
// of the subset inside it; nullopt when that half would hold fewer than `minKept` (which includes a split on
// the tile's border and one where every rect straddles).
std::optional<Split> splitAtMedian(const ScreenRect& tile, const std::vector<Item>& subset, int axis,
                                   uint64_t frame, size_t minKept, std::vector<int64_t>& centers) {
  centers.clear();
  for (const Item& item : subset)
    centers.push_back(int64_t(lowEdge(item.rect, axis)) + highEdge(item.rect, axis));
  // The median is halfway between the two middle centers (one when the count is odd), so that a gap between
  // two groups of rects takes the split rather than a rect beside it.
  const auto upper = centers.begin() + ptrdiff_t(centers.size() / 2);
  std::nth_element(centers.begin(), upper, centers.end());
  const int64_t lower = centers.size() % 2 ? *upper : *std::max_element(centers.begin(), upper);
  // Centers are doubled to stay integral; the split is the first pixel edge at or after the median.
  const int32_t at = int32_t((lower + *upper + 3) / 4);
  if (at <= lowEdge(tile, axis) || at >= highEdge(tile, axis)) return std::nullopt;

  size_t below = 0, above = 0;
  for (const Item& item : subset) {
    if (highEdge(item.rect, axis) <= at)
      ++below;
    else if (lowEdge(item.rect, axis) >= at)
      ++above;
  }
  // Ties alternate with the frame, so a set split evenly is not always queried on the same side.
  const bool keepAbove = above > below || (above == below && (frame & 1u) != 0);
  if ((keepAbove ? above : below) < minKept) return std::nullopt;

  ScreenRect low = tile, high = tile;
  (axis == 0 ? low.x1 : low.y1) = at;
  (axis == 0 ? high.x0 : high.y0) = at;
  return keepAbove ? Split{high, low} : Split{low, high};
}

}  // namespace

TilePlan planTiles(uint32_t width, uint32_t height, std::span<const QueryCandidate> candidates,
                   const TilePlanConfig& config, uint64_t frame) {
  ScreenRect tile = viewportRect(width, height);
  std::vector<Item> subset;
  subset.reserve(candidates.size());
  for (const QueryCandidate& c : candidates)
    if (const ScreenRect r = intersect(c.rect, tile); !r.empty()) subset.push_back({c.id, r});

  const size_t budget = config.queryBudget;
  // A split is taken only if the frame still queries at least half the budget after it: a smaller query
  // tile saves little, and fewer queries per frame would lengthen the time to cover every node.
  const size_t minKept = (budget + 1) / 2;
  std::vector<ScreenRect> finished;
  std::vector<int64_t> centers;
  int axis = tile.width() >= tile.height() ? 0 : 1;
  while (budget > 0 && subset.size() > budget &&
         std::max(tile.width(), tile.height()) >= config.minTilePixels) {
    std::optional<Split> split;
    int used = axis;
    for (int attempt = 0; attempt < 2 && !split; ++attempt) {
      used = attempt == 0 ? axis : 1 - axis;
      split = splitAtMedian(tile, subset, used, frame, minKept, centers);
    }
    if (!split) break;
    finished.push_back(split->finished);
    tile = split->kept;
    std::erase_if(subset, [&](const Item& item) { return !tile.contains(item.rect); });
    axis = 1 - used;
  }

  TilePlan plan;
  plan.tiles.reserve(finished.size() + 1);
  plan.tiles.push_back(tile);
  plan.tiles.insert(plan.tiles.end(), finished.begin(), finished.end());
  const size_t count = std::min(budget, subset.size());
  plan.queried.reserve(count);
  for (size_t i = 0; i < count; ++i) plan.queried.push_back(subset[i].id);
  return plan;
}

}  // namespace ropecast
