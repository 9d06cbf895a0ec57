// RecastTracker: a frame recasts only what changed over an image it holds; with feedback only once the answer
// about the held frame came back whole (not an older frame's, nothing dropped), which a frame redrawing the
// converged image keeps; the readback of a frame cast in part gets the carried answer (used and requested
// leaves with pixels kept, hits only for leaves kept whole), and only that frame's readback.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "recast_scene.h"
#include "render/recast_tracker.h"

namespace ropecast {
namespace {

using TrackerScene = test::RecastScene;

// Every leaf of `leaves` as used, requested and hit: an answer that lists all.
FeedbackReadback answerListingAll(uint64_t frame, size_t leaves) {
  FeedbackReadback r;
  r.frame = frame;
  for (uint32_t i = 0; i < leaves; ++i) {
    r.usedLeaves.push_back(i);
    r.requestedLeaves.push_back(i);
    r.hitLeaves.push_back(i);
  }
  return r;
}

TEST(RecastTracker, PlansOnlyOverAnImageItHolds) {
  const TrackerScene s;
  RecastTracker tracker;
  EXPECT_FALSE(tracker.plan(s.view(), s.cut(), 0, false));
  tracker.drew(0, s.cut(), false);
  const std::optional<RecastPlan> plan = tracker.plan(s.view(), s.cut({NodeKey{2, {1, 2, 3}}}), 1, false);
  ASSERT_TRUE(plan);
  EXPECT_GT(plan->pixels, 0u);
  tracker.forget();
  EXPECT_FALSE(tracker.plan(s.view(), s.cut(), 1, false));
}

TEST(RecastTracker, WithFeedbackItWaitsForAWholeAnswerAboutTheHeldFrame) {
  const TrackerScene s;
  const std::vector<PlannedLeaf> held = s.cut(), next = s.cut({NodeKey{2, {1, 2, 3}}});
  RecastTracker tracker;
  tracker.drew(5, held, false);
  EXPECT_FALSE(tracker.plan(s.view(), next, 6, true)) << "no answer yet";
  EXPECT_TRUE(tracker.plan(s.view(), next, 6, false)) << "without feedback no answer is needed";
  tracker.heard(answerListingAll(4, held.size()));
  EXPECT_FALSE(tracker.plan(s.view(), next, 6, true)) << "an answer about an older frame";
  FeedbackReadback dropped = answerListingAll(5, held.size());
  dropped.usedDropped = 1;
  tracker.heard(dropped);
  EXPECT_FALSE(tracker.plan(s.view(), next, 6, true)) << "an answer with entries dropped";
  tracker.heard(answerListingAll(5, held.size()));
  EXPECT_TRUE(tracker.plan(s.view(), next, 6, true));

  // A frame drawing the converged image again keeps the answer; any other frame drawn waits for its own.
  tracker.drew(6, held, true);
  EXPECT_TRUE(tracker.plan(s.view(), next, 7, true));
  tracker.drew(7, held, false);
  EXPECT_FALSE(tracker.plan(s.view(), next, 8, true));
}

TEST(RecastTracker, TheReadbackOfAFrameCastInPartGetsTheCarriedAnswer) {
  const TrackerScene s;
  const std::vector<PlannedLeaf> held = s.cut(), next = s.cut({NodeKey{2, {1, 2, 3}}});
  RecastTracker tracker;
  tracker.drew(5, held, false);
  // The held frame's answer lists every leaf: used, requested and hit.
  tracker.heard(answerListingAll(5, held.size()));
  const std::optional<RecastPlan> plan = tracker.plan(s.view(), next, 6, true);
  ASSERT_TRUE(plan);
  ASSERT_FALSE(plan->keptWhole.empty());
  ASSERT_GT(plan->keptIn.size(), plan->keptWhole.size()) << "no leaf kept in part: the test needs one";

  // An older frame's readback gets nothing; frame 6's gets the kept leaves, added once to what its rays said.
  FeedbackReadback older;
  older.frame = 4;
  tracker.addCarried(older);
  EXPECT_TRUE(older.usedLeaves.empty());
  FeedbackReadback readback;
  readback.frame = 6;
  readback.usedLeaves = {plan->keptIn.front(), uint32_t(next.size() - 1)};  // one listed by both
  tracker.addCarried(readback);
  std::vector<uint32_t> used = plan->keptIn;
  used.push_back(uint32_t(next.size() - 1));
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  EXPECT_EQ(readback.usedLeaves, used);
  EXPECT_EQ(readback.requestedLeaves, plan->keptIn);
  EXPECT_EQ(readback.hitLeaves, plan->keptWhole) << "hits only for leaves none of whose pixels is cast";

  // Carried once: frame 6's readback again, or a later one, gets nothing more.
  FeedbackReadback again;
  again.frame = 6;
  tracker.addCarried(again);
  EXPECT_TRUE(again.usedLeaves.empty());
}

}  // namespace
}  // namespace ropecast
