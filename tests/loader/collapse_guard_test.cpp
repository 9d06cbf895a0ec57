// CollapseGuard: on a still view a refined node collapses at most once, the rays' "unused" never collapses
// one they requested, the occlusion marks do once; other hints pass through; reset() (a new view) forgets
// both.
#include <gtest/gtest.h>

#include "loader/collapse_guard.h"

namespace ropecast {
namespace {

const NodeKey kNode{2, {1, 0, 3}};
const NodeKey kOther{2, {0, 0, 0}};

TEST(CollapseGuard, ARefinedNodeCollapsesOnceOnAStillView) {
  CollapseGuard guard;
  EXPECT_EQ(guard.filter(kNode, NodeHint::Occluded, /*refinedNow=*/true), NodeHint::Occluded);
  EXPECT_TRUE(guard.collapsed(kNode));
  // Refined again (it showed as a leaf), hidden again: the second collapse is refused, the refinement kept.
  EXPECT_EQ(guard.filter(kNode, NodeHint::Unused, true), NodeHint::Used);
  EXPECT_EQ(guard.filter(kNode, NodeHint::Occluded, true), NodeHint::Used);
  EXPECT_FALSE(guard.collapsed(kOther));
  EXPECT_EQ(guard.filter(kOther, NodeHint::Unused, true), NodeHint::Unused);
}

TEST(CollapseGuard, ANodeTheRaysRequestedDoesNotCollapseForTheRays) {
  CollapseGuard guard;
  // A leaf the rays asked to refine; refined, its leaves go unused: its coarse data showed what the finer
  // data does not, and collapsed it would be asked for again.
  EXPECT_EQ(guard.filter(kNode, NodeHint::Requested, /*refinedNow=*/false), NodeHint::Requested);
  EXPECT_EQ(guard.filter(kNode, NodeHint::Unused, true), NodeHint::Used);
  EXPECT_FALSE(guard.collapsed(kNode));
}

TEST(CollapseGuard, ANodeTheRaysRequestedCollapsesOnceWhereTheQueriesHideIt) {
  CollapseGuard guard;
  // The queries found its finer data hidden: its own query, part by part, keeps it collapsed while the rays
  // request its coarse data.
  EXPECT_EQ(guard.filter(kNode, NodeHint::Requested, /*refinedNow=*/false), NodeHint::Requested);
  EXPECT_EQ(guard.filter(kNode, NodeHint::Occluded, true), NodeHint::Occluded);
  EXPECT_TRUE(guard.collapsed(kNode));
  // Refined again (its query answered visible): once only.
  EXPECT_EQ(guard.filter(kNode, NodeHint::Requested, false), NodeHint::Requested);
  EXPECT_EQ(guard.filter(kNode, NodeHint::Occluded, true), NodeHint::Used);
}

TEST(CollapseGuard, HintsThatCollapseNothingPassThrough) {
  CollapseGuard guard;
  for (const NodeHint hint : {NodeHint::None, NodeHint::Used, NodeHint::Requested}) {
    EXPECT_EQ(guard.filter(kNode, hint, true), hint);
    EXPECT_EQ(guard.filter(kOther, hint, false), hint);
  }
  // A leaf hinted hidden is not refined; that is not a collapse.
  EXPECT_EQ(guard.filter(kOther, NodeHint::Occluded, false), NodeHint::Occluded);
  EXPECT_EQ(guard.filter(kOther, NodeHint::Occluded, false), NodeHint::Occluded);
  EXPECT_FALSE(guard.collapsed(kOther));
}

TEST(CollapseGuard, ANewViewForgetsCollapsesAndRequests) {
  CollapseGuard guard;
  guard.filter(kNode, NodeHint::Occluded, true);
  guard.filter(kOther, NodeHint::Requested, false);
  guard.reset();
  EXPECT_FALSE(guard.collapsed(kNode));
  EXPECT_EQ(guard.filter(kNode, NodeHint::Occluded, true), NodeHint::Occluded);
  EXPECT_EQ(guard.filter(kOther, NodeHint::Unused, true), NodeHint::Unused);
}

}  // namespace
}  // namespace ropecast
