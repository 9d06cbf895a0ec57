// planRecast: the pixels a frame of a still view casts again when its cut changed in places. Every pixel
// whose ray meets a changed leaf (gone, new, or holding another slot) is cast and most others are not; an
// unchanged cut casts nothing; a changed box holding the eye casts the whole image; of the leaves the rays'
// answer lists, those with pixels not cast are kept in the answer, and those with none cast kept whole.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "recast_scene.h"
#include "render/recast_plan.h"

namespace ropecast {
namespace {

constexpr uint32_t kWidth = test::RecastScene::kWidth, kHeight = test::RecastScene::kHeight;

struct Scene : test::RecastScene {
  RecastPlan plan(const std::vector<PlannedLeaf>& drawnCut, const std::vector<PlannedLeaf>& now,
                  const std::unordered_set<NodeKey, NodeKeyHash>* answered = nullptr) const {
    DrawnLeaves drawn;
    for (const PlannedLeaf& leaf : drawnCut) drawn[leaf.key] = drawnSlotOf(leaf);
    RecastInput in = view();
    in.drawn = &drawn;
    in.leaves = &now;
    in.answered = answered;
    return planRecast(in);
  }
  bool rayMeets(uint32_t px, uint32_t py, const NodeKey& key) const {
    const WorldBox box = nodeWorldBox(layout, glm::dvec3(1.0), key);
    const Ray ray = pixelRay(camera, kWidth, kHeight, px, py);
    double t0 = 0.0, t1 = 0.0;
    return clipToBox({ray.origin - box.lo, ray.dir}, box.hi - box.lo, t0, t1);
  }
};

// Which pixels the plan casts, row-major.
std::vector<uint8_t> castPixels(const RecastPlan& plan) {
  std::vector<uint8_t> cast(size_t(kWidth) * kHeight, 0);
  for (const PixelRect& r : plan.rects)
    for (uint32_t y = r.y; y < r.y + r.height; ++y)
      for (uint32_t x = r.x; x < r.x + r.width; ++x) {
        EXPECT_EQ(cast[size_t(y) * kWidth + x], 0) << "rectangles overlap at " << x << "," << y;
        cast[size_t(y) * kWidth + x] = 1;
      }
  return cast;
}

TEST(RecastPlan, AnUnchangedCutCastsNothing) {
  const Scene s;
  const RecastPlan plan = s.plan(s.cut(), s.cut());
  EXPECT_FALSE(plan.whole);
  EXPECT_TRUE(plan.rects.empty());
  EXPECT_EQ(plan.pixels, 0u);
  EXPECT_EQ(plan.changedLeaves, 0u);
}

TEST(RecastPlan, CastsEveryPixelWhoseRayMeetsARefinedNodeAndFewOthers) {
  const Scene s;
  for (const NodeKey& refined : {NodeKey{2, {1, 2, 3}}, NodeKey{2, {0, 0, 0}}, NodeKey{2, {3, 3, 1}}}) {
    const RecastPlan plan = s.plan(s.cut(), s.cut({refined}));
    ASSERT_FALSE(plan.whole);
    EXPECT_EQ(plan.changedLeaves, 9u) << "the node gone and its eight children";
    const std::vector<uint8_t> cast = castPixels(plan);
    uint64_t met = 0, castCount = 0;
    for (uint32_t y = 0; y < kHeight; ++y)
      for (uint32_t x = 0; x < kWidth; ++x) {
        castCount += cast[size_t(y) * kWidth + x];
        if (!s.rayMeets(x, y, refined)) continue;
        ++met;
        ASSERT_TRUE(cast[size_t(y) * kWidth + x]) << "pixel " << x << "," << y << " meets the refined node";
      }
    EXPECT_EQ(castCount, plan.pixels);
    EXPECT_GT(met, 0u);
    EXPECT_LT(plan.pixels, uint64_t(kWidth) * kHeight / 2) << "a sixty-fourth of the volume changed";
    for (const PixelRect& r : plan.rects) {
      EXPECT_EQ(r.x % RecastPlan::kBlockSize, 0u);
      EXPECT_EQ(r.y % RecastPlan::kBlockSize, 0u);
      EXPECT_LE(r.x + r.width, kWidth);
      EXPECT_LE(r.y + r.height, kHeight);
    }
  }
}

TEST(RecastPlan, ALeafInAnotherSlotOrGoneEmptyIsAChange) {
  const Scene s;
  std::vector<PlannedLeaf> moved = s.cut();
  moved[5].slot = 999;
  EXPECT_EQ(s.plan(s.cut(), moved).changedLeaves, 1u);
  std::vector<PlannedLeaf> emptied = s.cut();
  emptied[7].content = LeafContent::Empty;
  const RecastPlan plan = s.plan(s.cut(), emptied);
  EXPECT_EQ(plan.changedLeaves, 1u);
  EXPECT_GT(plan.pixels, 0u);
}

TEST(RecastPlan, AChangedBoxHoldingTheEyeCastsTheWholeImage) {
  Scene s;
  s.camera.eye = glm::dvec3(80.0, 80.0, 80.0);  // inside node (2, {1, 1, 1})
  s.camera.target = glm::dvec3(128.0, 140.0, 100.0);
  const RecastPlan plan = s.plan(s.cut(), s.cut({NodeKey{2, {1, 1, 1}}}));
  EXPECT_TRUE(plan.whole);
  EXPECT_EQ(plan.pixels, uint64_t(kWidth) * kHeight);
}

TEST(RecastPlan, SaysWhichAnsweredLeavesKeepPixelsNotCast) {
  const Scene s;
  const NodeKey refined{2, {1, 2, 3}};
  const std::vector<PlannedLeaf> now = s.cut({refined});
  std::unordered_set<NodeKey, NodeKeyHash> answered;
  for (const PlannedLeaf& leaf : now) answered.insert(leaf.key);
  const RecastPlan plan = s.plan(s.cut(), now, &answered);
  EXPECT_EQ(plan.pixels, s.plan(s.cut(), now).pixels)
      << "the answer changes which leaves are kept, not the pixels";
  const std::vector<uint8_t> cast = castPixels(plan);
  uint32_t whole = 0, in = 0, none = 0;
  for (uint32_t i = 0; i < now.size(); ++i) {
    uint64_t met = 0, metCast = 0;
    for (uint32_t y = 0; y < kHeight; ++y)
      for (uint32_t x = 0; x < kWidth; ++x)
        if (s.rayMeets(x, y, now[i].key)) {
          ++met;
          metCast += cast[size_t(y) * kWidth + x];
        }
    const bool keptIn = std::find(plan.keptIn.begin(), plan.keptIn.end(), i) != plan.keptIn.end();
    const bool keptWhole = std::find(plan.keptWhole.begin(), plan.keptWhole.end(), i) != plan.keptWhole.end();
    if (keptWhole) {
      EXPECT_TRUE(keptIn) << "leaf " << i;
      EXPECT_EQ(metCast, 0u) << "leaf " << i << " is kept whole, yet some of its pixels are cast";
    }
    if (!keptIn) {
      EXPECT_EQ(metCast, met) << "leaf " << i << " keeps pixels not cast";
    }
    if (now[i].key.depth == 3) {
      EXPECT_FALSE(keptIn) << "a new leaf has all its pixels cast";
    }
    whole += keptWhole;
    in += keptIn && !keptWhole;
    none += !keptIn;
  }
  EXPECT_GT(whole, 0u);
  EXPECT_GT(in, 0u);
  EXPECT_GT(none, 0u);
}

}  // namespace
}  // namespace ropecast
