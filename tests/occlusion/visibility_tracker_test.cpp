// VisibilityTracker: rounds that query every leaf of the cut in a bounded number of frames, answers against
// the threshold and their lifetime, renewed marks, leaves marked unseen or hit without a query, reset,
// propagation to inner nodes, the list of occluded nodes, and convergence (answers since a frame).
#include "occlusion/visibility_tracker.h"

#include <algorithm>
#include <deque>
#include <random>
#include <set>
#include <utility>

#include <gtest/gtest.h>

namespace ropecast {
namespace {

NodeKey leafKey(uint32_t i) {
  return {6, {i % 64, (i / 64) % 64, i / 4096}};
}

LeafToQuery leafAt(NodeKey key, ScreenRect rect) {
  return {key, {rect, false}};
}

// n leaves over a width x height viewport; about a third of them large enough to straddle most splits.
std::vector<LeafToQuery> randomLeaves(std::mt19937& rng, uint32_t n, uint32_t width, uint32_t height) {
  std::vector<LeafToQuery> leaves;
  for (uint32_t i = 0; i < n; ++i) {
    const bool large = rng() % 3 == 0;
    const int32_t w = int32_t(1 + rng() % (large ? width / 2 : 24)),
                  h = int32_t(1 + rng() % (large ? height / 2 : 24));
    const int32_t x = int32_t(rng() % (width - std::min<uint32_t>(width - 1, w))),
                  y = int32_t(rng() % (height - std::min<uint32_t>(height - 1, h)));
    leaves.push_back(leafAt(leafKey(i), intersect({x, y, x + w, y + h}, viewportRect(width, height))));
  }
  return leaves;
}

// The frames a round may take with n queryable leaves and a budget B. planTiles queries every remaining leaf
// once at most B remain; before that each frame queries at least ceil(B / 2) (a split is taken only while the
// kept half holds that many, and otherwise B are queried from the current tile). So n - B leaves take at most
// ceil((n - B) / ceil(B / 2)) frames before the rest fits, plus the one frame that queries the rest.
uint64_t roundBound(uint64_t n, uint64_t budget) {
  if (n <= budget) return 1;
  const uint64_t perFrame = (budget + 1) / 2;
  return 1 + (n - budget + perFrame - 1) / perFrame;
}

TEST(VisibilityTracker, QueriesEveryLeafOnceARoundWithinTheBound) {
  const uint32_t width = 640, height = 480;
  const uint32_t budgets[] = {1, 7, 64, 512};
  for (uint32_t seed = 0; seed < 8; ++seed) {
    std::mt19937 rng(seed);
    const uint32_t budget = budgets[seed % 4];
    const uint32_t n = 50 + rng() % (budget == 1 ? 200 : 2000);  // a budget of 1 takes n frames
    std::vector<LeafToQuery> leaves = randomLeaves(rng, n, width, height);
    // A few leaves are never queried: one holding the eye, one outside the viewport.
    leaves.push_back({leafKey(n), {viewportRect(width, height), true}});
    leaves.push_back(leafAt(leafKey(n + 1), {}));
    const uint64_t bound = roundBound(n, budget);

    VisibilityConfig config;
    config.tiles = {budget, 16};
    VisibilityTracker tracker(config);
    uint64_t frame = 0;
    for (int round = 0; round < 3; ++round) {
      std::set<uint32_t> queried;
      uint64_t frames = 0;
      const uint64_t before = frame;
      do {
        const FrameQueryPlan plan = tracker.plan(frame++, width, height, leaves);
        ++frames;
        ASSERT_LE(plan.queries.size(), budget);
        ASSERT_EQ(plan.queriedIndices.size(), plan.queries.size());
        for (size_t q = 0; q < plan.queries.size(); ++q)
          ASSERT_EQ(leaves[plan.queriedIndices[q]].key, plan.queries[q]);
        for (const NodeKey& k : plan.queries) {
          const uint32_t i = k.coord.x + 64 * k.coord.y + 4096 * k.coord.z;
          ASSERT_LT(i, n) << "a nearEye or outside leaf was queried";
          EXPECT_TRUE(queried.insert(i).second) << "leaf " << i << " queried twice in one round";
          EXPECT_TRUE(plan.tiles[0].contains(leaves[i].projection.rect));
        }
        ASSERT_LE(frames, bound) << "seed " << seed << ": the round did not end within the bound";
      } while (queried.size() < n);
      EXPECT_EQ(tracker.lastRoundFrames(), frame - before) << "seed " << seed;
    }
  }
}

TEST(VisibilityTracker, QueriesEverythingEachFrameWhenTheCutFitsTheBudget) {
  VisibilityTracker tracker({{16, 64}, 4, 64});
  std::vector<LeafToQuery> leaves;
  for (uint32_t i = 0; i < 16; ++i)
    leaves.push_back(leafAt(leafKey(i), {int32_t(i), 0, int32_t(i) + 30, 30}));
  for (uint64_t frame = 0; frame < 3; ++frame) {
    const FrameQueryPlan plan = tracker.plan(frame, 100, 50, leaves);
    EXPECT_EQ(plan.tiles, std::vector<ScreenRect>{viewportRect(100, 50)});
    EXPECT_EQ(plan.queries.size(), 16u);
    EXPECT_EQ(tracker.lastRoundFrames(), 1u);
  }
  const FrameQueryPlan none = tracker.plan(3, 100, 50, {});
  EXPECT_EQ(none.tiles, std::vector<ScreenRect>{viewportRect(100, 50)});
  EXPECT_TRUE(none.queries.empty());
}

TEST(VisibilityTracker, MarksOccludedBelowTheThresholdUntilTheAnswerExpires) {
  VisibilityTracker tracker({{}, 4, 64});
  const NodeKey a = leafKey(0), b = leafKey(1), never = leafKey(2);
  const std::vector<LeafToQuery> leaves{leafAt(a, {0, 0, 4, 4}), leafAt(b, {4, 0, 8, 4}),
                                        leafAt(never, {0, 4, 4, 8})};
  tracker.plan(10, 8, 8, leaves);
  tracker.answer(a, 10, 3);
  tracker.answer(b, 10, 4);
  EXPECT_TRUE(tracker.isOccluded(a, 12));
  EXPECT_FALSE(tracker.isOccluded(b, 12));
  EXPECT_FALSE(tracker.isOccluded(never, 12));  // never answered counts visible
  EXPECT_EQ(tracker.counts(12).occluded, 1u);
  EXPECT_EQ(tracker.counts(12).visible, 2u);
  // An answer holds markLifetimeFrames frames after the frame its query was issued in.
  EXPECT_TRUE(tracker.isOccluded(a, 74));
  EXPECT_FALSE(tracker.isOccluded(a, 75));
  EXPECT_EQ(tracker.counts(75).occluded, 0u);

  // A newer answer replaces the mark; an older one arriving late does not.
  tracker.answer(a, 12, 100);
  EXPECT_FALSE(tracker.isOccluded(a, 13));
  tracker.answer(a, 11, 0);
  EXPECT_FALSE(tracker.isOccluded(a, 13));
  tracker.answer(a, 13, 0);
  EXPECT_TRUE(tracker.isOccluded(a, 13));

  // Expired marks are forgotten when a later frame is planned.
  EXPECT_GT(tracker.markCount(), 0u);
  tracker.plan(200, 8, 8, leaves);
  EXPECT_EQ(tracker.markCount(), 0u);
  EXPECT_FALSE(tracker.isOccluded(a, 200));
}

// A frame that draws the same image again renews the marks instead of querying: they outlive their
// lifetime while renewed, a round's convergence stands, and an answer from before the renewal is stale.
TEST(VisibilityTracker, RenewedMarksHoldWithoutQueries) {
  VisibilityTracker tracker({{}, 4, 64});
  const NodeKey a = leafKey(0), b = leafKey(1);
  const std::vector<LeafToQuery> leaves{leafAt(a, {0, 0, 4, 4}), leafAt(b, {4, 0, 8, 4})};
  EXPECT_EQ(tracker.plan(10, 8, 8, leaves).queries.size(), 2u);
  tracker.answer(a, 10, 0);
  tracker.answer(b, 10, 9);
  ASSERT_TRUE(tracker.answeredSince(10));
  for (uint64_t frame = 11; frame <= 200; ++frame) tracker.renew(frame);
  EXPECT_TRUE(tracker.isOccluded(a, 200));
  EXPECT_FALSE(tracker.isOccluded(b, 200));
  EXPECT_TRUE(tracker.answeredSince(10));
  tracker.answer(a, 150, 50);  // asked before the last renewal: the renewed mark is newer
  EXPECT_TRUE(tracker.isOccluded(a, 200));
  // Not renewed, the mark expires as an answer would.
  EXPECT_TRUE(tracker.isOccluded(a, 264));
  EXPECT_FALSE(tracker.isOccluded(a, 265));
}

TEST(VisibilityTracker, ResetForgetsMarksAndAnswersAskedBeforeIt) {
  VisibilityTracker tracker({{}, 4, 64});
  const NodeKey a = leafKey(0);
  const std::vector<LeafToQuery> leaves{leafAt(a, {0, 0, 4, 4})};
  tracker.plan(10, 8, 8, leaves);
  tracker.answer(a, 10, 0);
  EXPECT_TRUE(tracker.isOccluded(a, 11));
  tracker.reset();
  EXPECT_FALSE(tracker.isOccluded(a, 11));
  EXPECT_EQ(tracker.markCount(), 0u);
  tracker.answer(a, 10, 0);  // in flight across the reset: about the old transfer function
  tracker.plan(11, 8, 8, leaves);
  tracker.answer(a, 10, 0);
  EXPECT_FALSE(tracker.isOccluded(a, 11));
  tracker.answer(a, 11, 0);
  EXPECT_TRUE(tracker.isOccluded(a, 11));
}

TEST(VisibilityTracker, NeverQueriesOrOccludesALeafNearTheEye) {
  VisibilityTracker tracker({{}, 4, 64});
  const NodeKey a = leafKey(0);
  tracker.plan(1, 8, 8, std::vector<LeafToQuery>{leafAt(a, {0, 0, 4, 4})});
  tracker.answer(a, 1, 0);
  EXPECT_TRUE(tracker.isOccluded(a, 2));
  const FrameQueryPlan plan =
      tracker.plan(2, 8, 8, std::vector<LeafToQuery>{{a, {viewportRect(8, 8), true}}});
  EXPECT_TRUE(plan.queries.empty());
  EXPECT_FALSE(tracker.isOccluded(a, 2));
  EXPECT_EQ(tracker.counts(2).visible, 1u);
}

// A parent P (depth 1) with non-empty children c0, c1, c2 and, under child 3, one grandchild g.
struct SmallTree {
  NodeKey root{0, {0, 0, 0}};
  NodeKey p = root.child(0);
  NodeKey c0 = p.child(0), c1 = p.child(1), c2 = p.child(2);
  NodeKey g = p.child(3).child(5);
  std::vector<NodeKey> cut{c0, c1, c2, g};
  std::vector<LeafToQuery> toQuery() const {
    std::vector<LeafToQuery> out;
    for (uint32_t i = 0; i < cut.size(); ++i)
      out.push_back(leafAt(cut[i], {int32_t(i), 0, int32_t(i) + 1, 1}));
    return out;
  }
};

TEST(VisibilityTracker, PropagatesOcclusionOnlyWhenTheNonEmptyDescendantsShowTooFewSamples) {
  VisibilityTracker tracker({{}, 4, 64});
  const SmallTree t;
  tracker.plan(30, 8, 8, t.toQuery());
  tracker.answer(t.c0, 10, 0);
  tracker.answer(t.c1, 20, 0);
  tracker.answer(t.g, 30, 0);
  tracker.propagate(t.cut);  // c2 never answered: visible
  EXPECT_FALSE(tracker.isOccluded(t.p, 30));
  EXPECT_FALSE(tracker.isOccluded(t.root, 30));
  EXPECT_TRUE(tracker.isOccluded(t.g.parent(), 30));  // its only non-empty descendant is occluded

  tracker.answer(t.c2, 30, 1);
  tracker.propagate(t.cut);
  EXPECT_TRUE(tracker.isOccluded(t.p, 30));
  EXPECT_TRUE(tracker.isOccluded(t.root, 30));
  // As old as the oldest answer below (c0's, issued in frame 10).
  EXPECT_TRUE(tracker.isOccluded(t.p, 74));
  EXPECT_FALSE(tracker.isOccluded(t.p, 75));

  // One visible grandchild makes every ancestor visible.
  tracker.answer(t.g, 31, 50);
  tracker.propagate(t.cut);
  EXPECT_FALSE(tracker.isOccluded(t.g.parent(), 31));
  EXPECT_FALSE(tracker.isOccluded(t.p, 31));
  EXPECT_FALSE(tracker.isOccluded(t.root, 31));

  // Leaves each below the threshold but together above it: their parent shows as many pixels as a visible
  // node would, and is visible (so it is not collapsed only to be refined again when queried itself).
  tracker.answer(t.g, 32, 0);
  tracker.answer(t.c0, 32, 2);
  tracker.answer(t.c1, 32, 1);
  tracker.answer(t.c2, 32, 1);
  tracker.propagate(t.cut);
  EXPECT_TRUE(tracker.isOccluded(t.c0, 32));
  EXPECT_FALSE(tracker.isOccluded(t.p, 32));
}

bool isBelow(NodeKey node, const NodeKey& ancestor) {
  while (node.depth > ancestor.depth) node = node.parent();
  return node == ancestor;
}

// The non-empty leaves of a random cut down to depth 5; a third of the cut's nodes are empty and left out.
std::vector<NodeKey> randomNonEmptyLeaves(std::mt19937& rng) {
  std::vector<NodeKey> leaves, open{NodeKey{}};
  while (!open.empty()) {
    const NodeKey n = open.back();
    open.pop_back();
    if (n.depth < 5 && (n.depth == 0 || rng() % 5 < 3)) {
      for (uint32_t o = 0; o < 8; ++o) open.push_back(n.child(o));
    } else if (rng() % 3 != 0) {
      leaves.push_back(n);
    }
  }
  return leaves;
}

TEST(VisibilityTracker, PropagatesAsTheDefinitionSaysOnRandomCuts) {
  std::mt19937 rng(11);
  int occludedInner = 0, visibleInner = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const std::vector<NodeKey> leaves = randomNonEmptyLeaves(rng);
    VisibilityTracker tracker({{}, 4, 64});
    std::vector<LeafToQuery> toQuery;
    for (const NodeKey& k : leaves) toQuery.push_back(leafAt(k, {0, 0, 1, 1}));
    const uint64_t now = 100;
    tracker.plan(now, 8, 8, toQuery);
    // Each leaf: occluded (0 to 3 samples, fresh or expired), visible, or never answered; mostly occluded
    // with no sample, so that some inner nodes are.
    std::unordered_map<NodeKey, uint64_t, NodeKeyHash> occludedSince;  // live occluded leaves
    std::unordered_map<NodeKey, uint64_t, NodeKeyHash> samplesOf;      // of those
    for (const NodeKey& k : leaves) {
      const uint32_t kind = rng() % 20;
      const uint64_t issued = now - rng() % 80;
      const uint64_t samples = kind < 13 ? 0 : rng() % 4;
      if (kind < 16)
        tracker.answer(k, issued, samples);
      else if (kind < 18)
        tracker.answer(k, issued, 10);
      if (kind < 16 && now - issued <= 64) {
        occludedSince[k] = issued;
        samplesOf[k] = samples;
      }
    }
    tracker.propagate(leaves);

    std::unordered_set<NodeKey, NodeKeyHash> inner;
    for (const NodeKey& k : leaves)
      for (NodeKey a = k; a.depth > 0;) inner.insert(a = a.parent());
    for (const NodeKey& a : inner) {
      // Occluded when the leaves below show fewer samples than the threshold together (a leaf not live and
      // occluded counts as visible: at least the threshold).
      uint64_t samples = 0;
      uint64_t oldest = now;
      for (const NodeKey& k : leaves) {
        if (!isBelow(k, a)) continue;
        const auto it = occludedSince.find(k);
        samples += it == occludedSince.end() ? 4 : samplesOf.at(k);
        if (it != occludedSince.end()) oldest = std::min(oldest, it->second);
      }
      const bool occluded = samples < 4;
      ++(occluded ? occludedInner : visibleInner);
      ASSERT_EQ(tracker.isOccluded(a, now), occluded) << "trial " << trial << " depth " << a.depth;
      if (occluded) {
        EXPECT_TRUE(tracker.isOccluded(a, oldest + 64));
        EXPECT_FALSE(tracker.isOccluded(a, oldest + 65));
      }
    }
  }
  EXPECT_GT(occludedInner, 50);
  EXPECT_GT(visibleInner, 50);
}

TEST(VisibilityTracker, ListsExactlyTheNodesItSaysAreOccluded) {
  std::mt19937 rng(17);
  size_t listed = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const std::vector<NodeKey> leaves = randomNonEmptyLeaves(rng);
    VisibilityTracker tracker({{}, 4, 64});
    const uint64_t now = 100;
    // Leaves answered occluded or visible, fresh or expiring, some never; a few near the eye (unqueryable,
    // visible whatever they answered).
    std::vector<LeafToQuery> toQuery;
    for (const NodeKey& k : leaves) toQuery.push_back({k, {{0, 0, 1, 1}, rng() % 10 == 0}});
    tracker.plan(now, 8, 8, toQuery);
    for (const NodeKey& k : leaves) {
      if (rng() % 5 == 0) continue;
      const uint64_t issued = now - rng() % 80;
      const uint64_t samples = rng() % 3 == 0 ? 10 : rng() % 4;
      tracker.answer(k, issued, samples);
    }
    tracker.propagate(leaves);
    // Every node that may hold a mark (the leaves and the nodes above them), and some that cannot.
    std::unordered_set<NodeKey, NodeKeyHash> nodes;
    for (const NodeKey& k : leaves) {
      nodes.insert(k.child(rng() % 8));
      for (NodeKey a = k;; a = a.parent()) {
        nodes.insert(a);
        if (a.depth == 0) break;
      }
    }
    std::vector<NodeKey> out{leaves.front()};  // cleared first
    for (const uint64_t frame : {now, now + 10, now + 40}) {
      tracker.occludedNodes(frame, out);
      const std::unordered_set<NodeKey, NodeKeyHash> got(out.begin(), out.end());
      ASSERT_EQ(got.size(), out.size()) << "a node listed twice";
      std::unordered_set<NodeKey, NodeKeyHash> expected;
      for (const NodeKey& k : nodes)
        if (tracker.isOccluded(k, frame)) expected.insert(k);
      ASSERT_EQ(got, expected) << "trial " << trial << " frame " << frame;
      listed += out.size();
    }
  }
  EXPECT_GT(listed, 200u);
}

TEST(VisibilityTracker, ACollapsedParentKeepsItsMarkUntilItIsQueried) {
  VisibilityTracker tracker({{}, 4, 64});
  const SmallTree t;
  tracker.plan(20, 8, 8, t.toQuery());
  for (const NodeKey& k : t.cut) tracker.answer(k, 20, 0);
  tracker.propagate(t.cut);
  ASSERT_TRUE(tracker.isOccluded(t.p, 21));

  // The refiner did not refine P: P is now a leaf of the cut, not answered yet.
  const std::vector<NodeKey> collapsed{t.p};
  const FrameQueryPlan plan = tracker.plan(21, 8, 8, std::vector<LeafToQuery>{leafAt(t.p, {0, 0, 4, 1})});
  EXPECT_EQ(plan.queries, collapsed);
  tracker.propagate(collapsed);
  EXPECT_TRUE(tracker.isOccluded(t.p, 22));
  EXPECT_TRUE(tracker.isOccluded(t.root, 22));
  EXPECT_EQ(tracker.counts(22).occluded, 1u);
  // Its own answer decides from then on.
  tracker.answer(t.p, 21, 9);
  tracker.propagate(collapsed);
  EXPECT_FALSE(tracker.isOccluded(t.p, 22));
  EXPECT_FALSE(tracker.isOccluded(t.root, 22));
}

TEST(VisibilityTracker, ALeafMarkedUnseenIsOccludedWithoutAQueryOrARound) {
  VisibilityTracker tracker({{}, 4, 64});
  const SmallTree t;
  // c0 and c1 were answered visible; the rays then left c0, c1 and c2 unused: only g is queried.
  tracker.plan(10, 8, 8, t.toQuery());
  tracker.answer(t.c0, 10, 9);
  tracker.answer(t.c1, 10, 9);
  std::vector<LeafToQuery> queried = t.toQuery();
  queried.erase(queried.begin(), queried.begin() + 3);
  for (const NodeKey& k : {t.c0, t.c1, t.c2}) tracker.markUnseen(k, 11);
  const FrameQueryPlan plan = tracker.plan(11, 8, 8, queried);
  EXPECT_EQ(plan.queries, std::vector<NodeKey>{t.g});
  EXPECT_FALSE(tracker.answeredSince(11)) << "g's query is out; the unseen leaves count in no round";
  tracker.answer(t.g, 11, 0);
  EXPECT_TRUE(tracker.answeredSince(11));
  tracker.propagate(t.cut);
  for (const NodeKey& k : {t.c0, t.c1, t.c2, t.g, t.p, t.root}) EXPECT_TRUE(tracker.isOccluded(k, 12));
  // An older answer does not replace the mark; a newer one does.
  tracker.answer(t.c0, 10, 9);
  EXPECT_TRUE(tracker.isOccluded(t.c0, 12));
  tracker.answer(t.c0, 12, 9);
  tracker.propagate(t.cut);
  EXPECT_FALSE(tracker.isOccluded(t.c0, 13));
  EXPECT_FALSE(tracker.isOccluded(t.p, 13));
}

TEST(VisibilityTracker, AnUnseenMarkHoldsUntilTheLeafsQueryAnswers) {
  VisibilityTracker tracker({{}, 4, 64});
  const SmallTree t;
  tracker.markUnseen(t.c0, 5);
  EXPECT_TRUE(tracker.isOccluded(t.c0, 6));
  tracker.answer(t.c0, 4, 9);  // a query issued before the rays' answer
  EXPECT_TRUE(tracker.isOccluded(t.c0, 6));
  tracker.answer(t.c0, 6, 9);
  EXPECT_FALSE(tracker.isOccluded(t.c0, 7));
}

TEST(VisibilityTracker, ALeafTheRaysHitIsVisibleCountedAndNotQueried) {
  VisibilityTracker tracker({{}, 4, 64});
  const SmallTree t;
  // Frame 10 queried every leaf and found c0 and c1 hidden; the rays of frame 10 stopped in c0 often enough.
  tracker.plan(10, 8, 8, t.toQuery());
  tracker.answer(t.c0, 10, 1);
  tracker.answer(t.c1, 10, 1);
  tracker.answer(t.c2, 10, 9);
  tracker.answer(t.g, 10, 9);
  tracker.markHit(t.c0, 10);
  tracker.propagate(t.cut);
  EXPECT_FALSE(tracker.isOccluded(t.c0, 11)) << "the rays' hits replace a query's answer about their frame";
  EXPECT_TRUE(tracker.isOccluded(t.c1, 11));
  // A newer query's answer is not replaced by older hits.
  tracker.answer(t.c1, 12, 0);
  tracker.markHit(t.c1, 11);
  EXPECT_TRUE(tracker.isOccluded(t.c1, 13));

  // Frame 13: c0 and c2 are known visible from hits; only c1 and g are queried, and all four are counted.
  std::vector<LeafToQuery> leaves = t.toQuery();
  leaves[0].hitByRays = leaves[2].hitByRays = true;
  tracker.markHit(t.c2, 12);
  const FrameQueryPlan plan = tracker.plan(13, 8, 8, leaves);
  ASSERT_EQ(plan.queries.size(), 2u);
  const std::vector<NodeKey> queried{t.c1, t.g};
  EXPECT_TRUE(std::is_permutation(plan.queries.begin(), plan.queries.end(), queried.begin()));
  const VisibilityCounts counts = tracker.counts(13);
  EXPECT_EQ(counts.visible + counts.occluded, 4u);
  EXPECT_EQ(counts.occluded, 1u);  // c1
  EXPECT_FALSE(tracker.answeredSince(13));
  tracker.answer(t.c1, 13, 0);
  tracker.answer(t.g, 13, 9);
  EXPECT_TRUE(tracker.answeredSince(13)) << "the round is the queried leaves'";

  // Every leaf hit: nothing to query, and nothing outstanding.
  for (LeafToQuery& l : leaves) l.hitByRays = true;
  for (const NodeKey& k : t.cut) tracker.markHit(k, 14);
  EXPECT_TRUE(tracker.plan(15, 8, 8, leaves).queries.empty());
  EXPECT_TRUE(tracker.answeredSince(15));
  EXPECT_EQ(tracker.counts(15).visible, 4u);
}

TEST(VisibilityTracker, RoundsSpanFramesAndTheMarksFollowTheAnswers) {
  const uint32_t width = 320, height = 240, n = 400;
  std::mt19937 rng(3);
  const std::vector<LeafToQuery> leaves = randomLeaves(rng, n, width, height);
  std::set<uint32_t> hidden;  // the scene's truth: which leaves the GPU finds occluded
  for (uint32_t i = 0; i < n; i += 3) hidden.insert(i);

  VisibilityTracker tracker({{64, 16}, 4, 64});
  std::deque<std::pair<NodeKey, uint64_t>> inFlight;
  // Renders frames; each query's answer comes back two frames after it was issued.
  auto run = [&](uint64_t from, uint64_t to) {
    for (uint64_t frame = from; frame < to; ++frame) {
      while (!inFlight.empty() && inFlight.front().second + 2 <= frame) {
        const auto [key, issued] = inFlight.front();
        inFlight.pop_front();
        const uint32_t i = key.coord.x + 64 * key.coord.y + 4096 * key.coord.z;
        tracker.answer(key, issued, hidden.contains(i) ? 0 : 100);
      }
      for (const NodeKey& k : tracker.plan(frame, width, height, leaves).queries)
        inFlight.push_back({k, frame});
    }
  };
  run(0, 60);
  EXPECT_GT(tracker.lastRoundFrames(), 1u);
  EXPECT_EQ(tracker.counts(60).occluded, hidden.size());

  // The view changes: a hidden leaf shows, and the next round's answer about it unmarks it.
  hidden.erase(0);
  EXPECT_TRUE(tracker.isOccluded(leaves[0].key, 60));
  run(60, 120);
  EXPECT_FALSE(tracker.isOccluded(leaves[0].key, 120));
  EXPECT_EQ(tracker.counts(120).occluded, hidden.size());
}

TEST(VisibilityTracker, AnswersSinceAFrameOnceARoundStartedThenCameBackWhole) {
  const uint32_t width = 320, height = 240, n = 400;
  std::mt19937 rng(5);
  const std::vector<LeafToQuery> leaves = randomLeaves(rng, n, width, height);
  VisibilityTracker tracker({{64, 16}, 4, 64});
  std::deque<std::pair<NodeKey, uint64_t>> inFlight;
  NodeKey heldBack{};
  uint64_t heldIssued = 0;
  bool holdOne = false;
  // Each query's answer comes back two frames after it was issued; with holdOne, the first query issued
  // from then on never comes back.
  auto run = [&](uint64_t from, uint64_t to) {
    for (uint64_t frame = from; frame < to; ++frame) {
      while (!inFlight.empty() && inFlight.front().second + 2 <= frame) {
        const auto [key, issued] = inFlight.front();
        inFlight.pop_front();
        if (holdOne && key == heldBack && issued == heldIssued) continue;
        tracker.answer(key, issued, 100);
      }
      for (const NodeKey& k : tracker.plan(frame, width, height, leaves).queries) {
        if (holdOne && heldBack == NodeKey{}) {
          heldBack = k;
          heldIssued = frame;
        }
        inFlight.push_back({k, frame});
      }
    }
  };
  run(0, 1);
  EXPECT_FALSE(tracker.answeredSince(0));
  // The first round: frames [0, rounds); its last answers come back in frame rounds + 1.
  uint64_t frame = 1;
  for (; tracker.lastRoundFrames() == 0; ++frame) run(frame, frame + 1);
  const uint64_t rounds = tracker.lastRoundFrames();
  ASSERT_GT(rounds, 1u);
  ASSERT_EQ(frame, rounds);
  run(frame, rounds + 1);
  EXPECT_FALSE(tracker.answeredSince(0)) << "the answers of frame " << rounds - 1 << " are still out";
  run(rounds + 1, rounds + 2);
  EXPECT_TRUE(tracker.answeredSince(0));
  EXPECT_FALSE(tracker.answeredSince(1)) << "no round started at frame 1 or later came back yet";
  // The second round, frames [rounds, 2 rounds), comes back whole in frame 2 rounds + 1.
  run(rounds + 2, 2 * rounds + 1);
  EXPECT_FALSE(tracker.answeredSince(rounds));
  run(2 * rounds + 1, 2 * rounds + 2);
  EXPECT_TRUE(tracker.answeredSince(rounds));

  // A round with an answer missing does not count; the next one, whole, does.
  run(2 * rounds + 2, 3 * rounds);
  holdOne = true;
  run(3 * rounds, 4 * rounds + 2);
  EXPECT_NE(heldBack, NodeKey{});
  EXPECT_TRUE(tracker.answeredSince(2 * rounds));
  EXPECT_FALSE(tracker.answeredSince(3 * rounds))
      << "an answer of the round of frame " << 3 * rounds << " is missing";
  run(4 * rounds + 2, 5 * rounds + 2);
  EXPECT_TRUE(tracker.answeredSince(3 * rounds)) << "the round of frame " << 4 * rounds << " came back whole";
  holdOne = false;
  const uint64_t from = 5 * rounds + 2;

  // reset() forgets every answer; a cut with no leaf to query has nothing to wait for.
  tracker.reset();
  EXPECT_FALSE(tracker.answeredSince(0));
  tracker.plan(from + 4 * rounds, width, height, {});
  EXPECT_TRUE(tracker.answeredSince(from + 4 * rounds));
  EXPECT_FALSE(tracker.answeredSince(from + 4 * rounds + 1));
}

TEST(VisibilityTracker, KeepsMemoryBoundedAsTheCutChanges) {
  VisibilityTracker tracker({{64, 16}, 4, 16});
  for (uint64_t frame = 0; frame < 400; ++frame) {
    // A cut of 50 leaves that moves on every frame; every query answers occluded at once.
    std::vector<LeafToQuery> leaves;
    for (uint32_t i = 0; i < 50; ++i)
      leaves.push_back(leafAt(leafKey(uint32_t(frame) * 50 + i), {int32_t(i), 0, int32_t(i) + 2, 2}));
    for (const NodeKey& k : tracker.plan(frame, 64, 8, leaves).queries) tracker.answer(k, frame, 0);
  }
  EXPECT_LE(tracker.markCount(), 17u * 50u);
}

}  // namespace
}  // namespace ropecast
