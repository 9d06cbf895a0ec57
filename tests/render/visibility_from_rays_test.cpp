// markVisibilityFromRays: the rays' answer marks the occlusion queries' leaves (a leaf no ray sampled hidden,
// one enough rays stopped in visible, one sampled otherwise left to its query), but for a node collapsed on
// this view, whose coarse data the rays see where its finer data is hidden.
#include "render/visibility_from_rays.h"

#include <vector>

#include <gtest/gtest.h>

namespace ropecast {
namespace {

const NodeKey kA{3, {0, 0, 0}}, kB{3, {1, 0, 0}}, kC{3, {2, 0, 0}};
const std::vector<NodeKey> kLeaves{kA, kB, kC};

// The rays' answer about frame `frame`, cast over kLeaves (all data leaves).
void answerRays(RayFeedback& rays, uint64_t frame, std::vector<uint32_t> used,
                std::vector<uint32_t> requested, std::vector<uint32_t> hits) {
  rays.rememberCut(frame, kLeaves, std::vector<uint8_t>(kLeaves.size(), 1));
  ASSERT_TRUE(rays.answer(frame, used, requested, hits));
}

TEST(VisibilityFromRays, UnsampledLeavesAreHiddenAndHitOnesVisible) {
  VisibilityTracker visibility({{}, 4, 64});
  RayFeedback rays;
  const CollapseGuard collapses;
  visibility.answer(kC, 1, 0);  // a query found kC hidden; enough rays of the same frame stopped in it
  answerRays(rays, 1, {1, 2}, {1}, {2});
  markVisibilityFromRays(kLeaves, rays, collapses, 2, visibility);
  EXPECT_TRUE(visibility.isOccluded(kA, 2)) << "no ray sampled it";
  EXPECT_FALSE(visibility.isOccluded(kB, 2));
  EXPECT_FALSE(visibility.isOccluded(kC, 2)) << "rays stopped in it";
}

TEST(VisibilityFromRays, ALeafSampledAgainKeepsItsMarkUntilItsQueryAnswers) {
  VisibilityTracker visibility({{}, 4, 64});
  RayFeedback rays;
  const CollapseGuard collapses;
  answerRays(rays, 1, {1, 2}, {}, {});
  markVisibilityFromRays(kLeaves, rays, collapses, 2, visibility);
  ASSERT_TRUE(visibility.isOccluded(kA, 2));
  // Rays pass through kA and kB without stopping: maybe fewer than the threshold, so their queries decide.
  answerRays(rays, 2, {0, 1}, {0}, {});
  markVisibilityFromRays(kLeaves, rays, collapses, 3, visibility);
  EXPECT_TRUE(visibility.isOccluded(kA, 3)) << "a ray's passing withdrew the mark";
  visibility.answer(kA, 3, 2);
  EXPECT_TRUE(visibility.isOccluded(kA, 4)) << "2 samples, below the threshold";
  visibility.answer(kA, 4, 10);
  EXPECT_FALSE(visibility.isOccluded(kA, 5));
  // Enough rays stop in kB: visible at once.
  answerRays(rays, 3, {0, 1}, {}, {1});
  visibility.answer(kB, 2, 0);
  markVisibilityFromRays(kLeaves, rays, collapses, 4, visibility);
  EXPECT_FALSE(visibility.isOccluded(kB, 4));
}

TEST(VisibilityFromRays, ACollapsedNodeIsLeftToItsQuery) {
  VisibilityTracker visibility({{}, 4, 64});
  RayFeedback rays;
  CollapseGuard collapses;
  // kA and kB were refined and hidden, and collapsed; no ray reached kA's leaves, a query hid kB's.
  for (const NodeKey& node : {kA, kB})
    ASSERT_EQ(collapses.filter(node, NodeHint::Occluded, true), NodeHint::Occluded);
  answerRays(rays, 1, {1, 2}, {}, {});
  visibility.answer(kB, 1, 0);
  markVisibilityFromRays(kLeaves, rays, collapses, 2, visibility);
  ASSERT_TRUE(visibility.isOccluded(kA, 2));
  ASSERT_TRUE(visibility.isOccluded(kB, 2));
  // Drawn coarse, their filtered data shows surfaces: the rays sample them, request them, stop in them.
  answerRays(rays, 2, {0, 1, 2}, {0, 1}, {0, 1});
  markVisibilityFromRays(kLeaves, rays, collapses, 3, visibility);
  EXPECT_TRUE(visibility.isOccluded(kA, 3)) << "hits in coarse data overrode the rays' earlier answer";
  EXPECT_TRUE(visibility.isOccluded(kB, 3)) << "hits in coarse data overrode the query";
  // Their own queries answer for them.
  visibility.answer(kA, 3, 10);
  EXPECT_FALSE(visibility.isOccluded(kA, 4));
}

}  // namespace
}  // namespace ropecast
