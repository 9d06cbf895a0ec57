// planTiles: the tiles partition the viewport, the queried rects lie inside the first tile, the budget holds,
// and each frame queries at least half the budget (or every candidate), for random rectangle sets.
#include "occlusion/tile_plan.h"

#include <algorithm>
#include <random>
#include <set>

#include <gtest/gtest.h>

namespace ropecast {
namespace {

std::vector<QueryCandidate> randomCandidates(std::mt19937& rng, uint32_t width, uint32_t height,
                                             uint32_t count) {
  std::uniform_int_distribution<int32_t> x(-8, int32_t(width) + 8), y(-8, int32_t(height) + 8);
  std::uniform_int_distribution<int> kind(0, 9);
  std::vector<QueryCandidate> out;
  for (uint32_t i = 0; i < count; ++i) {
    const int32_t x0 = x(rng), y0 = y(rng);
    // Mostly small rects, some large ones that straddle most splits, a few empty or outside the viewport.
    const int k = kind(rng);
    const int32_t maxSize = k < 6   ? std::max<int32_t>(2, int32_t(std::max(width, height)) / 16)
                            : k < 9 ? int32_t(std::max(width, height))
                                    : 2;
    std::uniform_int_distribution<int32_t> size(k == 9 ? -1 : 1, maxSize);
    out.push_back({1000 + i, {x0, y0, x0 + size(rng), y0 + size(rng)}});
  }
  return out;
}

// The checks every plan must pass; `exact` paints a count per pixel (small viewports).
void expectValidPlan(const TilePlan& plan, uint32_t width, uint32_t height,
                     std::span<const QueryCandidate> candidates, const TilePlanConfig& config, bool exact) {
  const ScreenRect viewport = viewportRect(width, height);
  ASSERT_FALSE(plan.tiles.empty());
  int64_t area = 0;
  for (const ScreenRect& t : plan.tiles) {
    EXPECT_TRUE(viewport.contains(t) || (viewport.empty() && t == viewport));
    area += t.area();
  }
  EXPECT_EQ(area, viewport.area());
  if (exact) {
    std::vector<int> painted(size_t(width) * height, 0);
    for (const ScreenRect& t : plan.tiles)
      for (int32_t py = t.y0; py < t.y1; ++py)
        for (int32_t px = t.x0; px < t.x1; ++px) ++painted[size_t(py) * width + px];
    EXPECT_TRUE(std::all_of(painted.begin(), painted.end(), [](int c) { return c == 1; }));
  } else {
    for (size_t i = 0; i < plan.tiles.size(); ++i)
      for (size_t j = i + 1; j < plan.tiles.size(); ++j) EXPECT_FALSE(plan.tiles[i].overlaps(plan.tiles[j]));
  }

  std::vector<uint32_t> visibleIds;  // candidates with a pixel in the viewport, in order
  for (const QueryCandidate& c : candidates)
    if (!intersect(c.rect, viewport).empty()) visibleIds.push_back(c.id);
  EXPECT_LE(plan.queried.size(), config.queryBudget);
  EXPECT_EQ(std::set<uint32_t>(plan.queried.begin(), plan.queried.end()).size(), plan.queried.size());
  for (uint32_t id : plan.queried) {
    const auto c =
        std::find_if(candidates.begin(), candidates.end(), [&](const auto& q) { return q.id == id; });
    ASSERT_NE(c, candidates.end());
    EXPECT_TRUE(plan.tiles[0].contains(intersect(c->rect, viewport)));
  }
  if (visibleIds.size() <= config.queryBudget) {
    EXPECT_EQ(plan.tiles, std::vector<ScreenRect>{viewport});
    EXPECT_EQ(plan.queried, visibleIds);
  } else {
    EXPECT_GE(plan.queried.size(), (config.queryBudget + 1) / 2);
  }
}

TEST(PlanTiles, PartitionsTheViewportAndQueriesInsideTheFirstTile) {
  const uint32_t sizes[][2] = {{1, 1},   {1, 9},   {9, 1},    {13, 9},   {64, 48},
                               {101, 3}, {3, 101}, {127, 65}, {200, 150}};
  const uint32_t budgets[] = {0, 1, 3, 16, 100};
  const int32_t minTiles[] = {1, 8, 64};
  std::mt19937 rng(6);
  int split = 0;
  for (int trial = 0; trial < 600; ++trial) {
    const uint32_t width = sizes[trial % 9][0], height = sizes[trial % 9][1];
    const TilePlanConfig config{budgets[(trial / 9) % 5], minTiles[(trial / 45) % 3]};
    const auto candidates = randomCandidates(rng, width, height, uint32_t(trial % 7 == 0 ? 0 : rng() % 400));
    const TilePlan plan = planTiles(width, height, candidates, config, uint64_t(trial));
    expectValidPlan(plan, width, height, candidates, config, true);
    if (plan.tiles.size() > 1) ++split;
    if (HasFatalFailure()) return;
  }
  EXPECT_GT(split, 100);
}

TEST(PlanTiles, PartitionsLargeViewports) {
  const uint32_t sizes[][2] = {{1920, 1080}, {4096, 17}, {17, 4096}, {2048, 2048}, {1023, 767}};
  std::mt19937 rng(60);
  int split = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const uint32_t width = sizes[trial % 5][0], height = sizes[trial % 5][1];
    const TilePlanConfig config{uint32_t(1 + rng() % 600), trial % 2 ? 64 : 16};
    const auto candidates = randomCandidates(rng, width, height, uint32_t(rng() % 5000));
    const TilePlan plan = planTiles(width, height, candidates, config, uint64_t(trial));
    expectValidPlan(plan, width, height, candidates, config, false);
    if (plan.tiles.size() > 1) ++split;
    if (HasFatalFailure()) return;
  }
  EXPECT_GT(split, 20);
}

TEST(PlanTiles, NarrowsTheFirstTileToAClusterOfSmallRects) {
  // 8 small rects in the top-left corner, 8 in the bottom-right: a budget of 8 is met by one half.
  std::vector<QueryCandidate> candidates;
  for (uint32_t i = 0; i < 8; ++i) {
    const int32_t x = int32_t(i % 4) * 10, y = int32_t(i / 4) * 10;
    candidates.push_back({i, {x, y, x + 8, y + 8}});
    candidates.push_back({100 + i, {600 - x - 8, 400 - y - 8, 600 - x, 400 - y}});
  }
  const TilePlanConfig config{8, 64};
  const TilePlan even = planTiles(600, 400, candidates, config, 0);
  const TilePlan odd = planTiles(600, 400, candidates, config, 1);
  ASSERT_EQ(even.tiles.size(), 2u);
  // An even split: the frame's parity picks the half, so consecutive frames query both clusters.
  EXPECT_EQ(even.tiles[0], (ScreenRect{0, 0, 300, 400}));  // halfway between the clusters' middle centers
  EXPECT_EQ(even.queried, (std::vector<uint32_t>{0, 1, 2, 3, 4, 5, 6, 7}));
  EXPECT_EQ(odd.tiles[0], (ScreenRect{300, 0, 600, 400}));
  EXPECT_EQ(odd.queried, (std::vector<uint32_t>{100, 101, 102, 103, 104, 105, 106, 107}));
}

TEST(PlanTiles, StopsAtADegenerateSplitAndQueriesInCandidateOrder) {
  // Every rect the same, centered: any split straddles all of them.
  std::vector<QueryCandidate> same;
  for (uint32_t i = 0; i < 10; ++i) same.push_back({i, {40, 30, 60, 50}});
  const TilePlan plan = planTiles(100, 80, same, {3, 1}, 0);
  EXPECT_EQ(plan.tiles, std::vector<ScreenRect>{viewportRect(100, 80)});
  EXPECT_EQ(plan.queried, (std::vector<uint32_t>{0, 1, 2}));
}

TEST(PlanTiles, DoesNotSplitTilesBelowTheMinimumSize) {
  std::vector<QueryCandidate> spread;
  for (uint32_t i = 0; i < 16; ++i) spread.push_back({i, {int32_t(i) * 3, 0, int32_t(i) * 3 + 2, 2}});
  const TilePlan small = planTiles(50, 40, spread, {4, 64}, 0);
  EXPECT_EQ(small.tiles.size(), 1u);
  EXPECT_EQ(small.queried, (std::vector<uint32_t>{0, 1, 2, 3}));
  const TilePlan fine = planTiles(50, 40, spread, {4, 8}, 0);
  EXPECT_GT(fine.tiles.size(), 1u);
  EXPECT_EQ(fine.queried.size(), 4u);
  EXPECT_LT(fine.tiles[0].area(), 50 * 40 / 4);
}

TEST(PlanTiles, GivesOneTileAndNoQueriesWithoutCandidates) {
  const TilePlan plan = planTiles(320, 200, {}, {}, 5);
  EXPECT_EQ(plan.tiles, std::vector<ScreenRect>{viewportRect(320, 200)});
  EXPECT_TRUE(plan.queried.empty());
  EXPECT_EQ(planTiles(0, 0, {}, {}, 0).tiles, std::vector<ScreenRect>{ScreenRect{}});
}

}  // namespace
}  // namespace ropecast
