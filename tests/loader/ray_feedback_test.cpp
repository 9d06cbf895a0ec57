// RayFeedback: answers mapped to the cut they describe, the hints they give and how long they hold.
#include <gtest/gtest.h>

#include "loader/ray_feedback.h"

namespace ropecast {
namespace {

const NodeKey kA{1, {0, 0, 0}}, kB{1, {1, 0, 0}}, kC{1, {0, 1, 0}}, kEmpty{1, {1, 1, 0}};

void rememberAbc(RayFeedback& f, uint64_t frame) {
  f.rememberCut(frame, {kA, kB, kC, kEmpty}, {1, 1, 1, 0});
}

TEST(RayFeedback, AnswersMapIndicesOfTheirFramesCut) {
  RayFeedback f;
  rememberAbc(f, 0);
  f.rememberCut(1, {kC, kB, kA, kEmpty}, {1, 1, 1, 0});  // another order: indices are per frame
  EXPECT_FALSE(f.answered());
  const uint32_t used[] = {0, 1}, requested[] = {1};
  ASSERT_TRUE(f.answer(1, used, requested));  // frame 0's cut is forgotten: its answer never came
  EXPECT_EQ(f.answeredFrame(), 1u);
  EXPECT_EQ(f.hint(kC, 2), NodeHint::Used);       // used
  EXPECT_EQ(f.hint(kB, 2), NodeHint::Requested);  // used and requested
  EXPECT_EQ(f.hint(kA, 2), NodeHint::Unused);     // a data leaf no ray sampled
  EXPECT_EQ(f.hint(kEmpty, 2), NodeHint::None);   // empty leaves are not answered for
  EXPECT_EQ(f.hint(NodeKey{2, {0, 0, 0}}, 2), NodeHint::None);
  EXPECT_EQ(f.usedNodes(), (std::vector<NodeKey>{kC, kB}));
  EXPECT_FALSE(f.answer(0, used, requested)) << "frame 0's cut was forgotten";
}

TEST(RayFeedback, HitsHoldAsTheirAnswerDoes) {
  RayFeedback f({/*answerLifetimeFrames=*/4});
  rememberAbc(f, 10);
  rememberAbc(f, 11);
  const uint32_t used[] = {0, 1}, hits[] = {1, 3, 7};  // 3: an empty leaf; 7: past the cut
  ASSERT_TRUE(f.answer(10, used, std::span<const uint32_t>(), hits));
  EXPECT_FALSE(f.hitByRays(kA, 11));
  EXPECT_TRUE(f.hitByRays(kB, 11));
  EXPECT_FALSE(f.hitByRays(kEmpty, 11)) << "empty leaves are not answered for";
  EXPECT_TRUE(f.hitByRays(kB, 14));
  EXPECT_FALSE(f.hitByRays(kB, 15)) << "too old";
  ASSERT_TRUE(f.answer(11, used, std::span<const uint32_t>()));
  EXPECT_FALSE(f.hitByRays(kB, 12)) << "the newer answer found it used, not hit";
  f.reset();
  EXPECT_FALSE(f.hitByRays(kB, 12));
}

TEST(RayFeedback, AnAnswerHoldsUntilANewerOneOrItsLifetime) {
  RayFeedback f({/*answerLifetimeFrames=*/4});
  rememberAbc(f, 10);
  rememberAbc(f, 11);
  const uint32_t none[] = {0};
  ASSERT_TRUE(f.answer(10, std::span<const uint32_t>(), std::span<const uint32_t>()));
  EXPECT_EQ(f.hint(kA, 14), NodeHint::Unused);
  EXPECT_EQ(f.hint(kA, 15), NodeHint::None) << "too old: the view may have moved";
  ASSERT_TRUE(f.answer(11, none, std::span<const uint32_t>()));
  EXPECT_EQ(f.hint(kA, 15), NodeHint::Used);    // used in frame 11
  EXPECT_EQ(f.hint(kB, 15), NodeHint::Unused);  // frame 11 says unused again, and it is newer
}

// A frame that draws the converged image again casts no feedback: the held answers are renewed instead, and
// an answer about an earlier frame arriving after the renewal does not drop them.
TEST(RayFeedback, RenewedAnswersHoldPastTheirLifetime) {
  RayFeedback f({/*answerLifetimeFrames=*/4});
  rememberAbc(f, 10);
  rememberAbc(f, 11);
  const uint32_t used[] = {1, 2}, requested[] = {2};
  ASSERT_TRUE(f.answer(10, used, requested));
  for (uint64_t frame = 12; frame <= 40; ++frame) f.renew(frame);
  EXPECT_EQ(f.hint(kA, 40), NodeHint::Unused);
  EXPECT_EQ(f.hint(kC, 40), NodeHint::Requested);
  EXPECT_EQ(f.answeredFrame(), 10u) << "no ray answered about the renewed frames";
  ASSERT_TRUE(f.answer(11, used, requested));
  EXPECT_EQ(f.hint(kA, 44), NodeHint::Unused) << "the late answer of frame 11 replaced the renewed ones";
  EXPECT_EQ(f.hint(kA, 45), NodeHint::None);
  EXPECT_EQ(f.answeredFrame(), 11u);
  // Expired answers are not renewed.
  f.renew(60);
  EXPECT_EQ(f.hint(kA, 60), NodeHint::None);
}

TEST(RayFeedback, ResetForgetsAnswersAndCuts) {
  RayFeedback f;
  rememberAbc(f, 0);
  ASSERT_TRUE(f.answer(0, std::span<const uint32_t>(), std::span<const uint32_t>()));
  rememberAbc(f, 1);
  f.reset();
  EXPECT_EQ(f.hint(kA, 1), NodeHint::None);
  EXPECT_FALSE(f.answered());
  EXPECT_FALSE(f.answer(1, std::span<const uint32_t>(), std::span<const uint32_t>()));
}

TEST(RayFeedback, IndicesPastTheCutAreIgnored) {
  RayFeedback f;
  rememberAbc(f, 0);
  const uint32_t bad[] = {99};
  ASSERT_TRUE(f.answer(0, bad, bad));
  EXPECT_TRUE(f.usedNodes().empty());
  EXPECT_EQ(f.hint(kA, 0), NodeHint::Unused);
}

}  // namespace
}  // namespace ropecast

namespace ropecast {
namespace {

TEST(RayFeedback, InnerNodesAreUsedWhenADataLeafBelowWasUsed) {
  // Root -> a (refined: a0 used, a1 unused) and b (refined: b0, b1 unused), one empty leaf.
  const NodeKey a{1, {0, 0, 0}}, b{1, {1, 0, 0}};
  const NodeKey a0 = a.child(0), a1 = a.child(1), b0 = b.child(0), b1 = b.child(1), e{1, {0, 1, 0}};
  RayFeedback f;
  f.rememberCut(3, {a0, a1, b0, b1, e}, {1, 1, 1, 1, 0});
  const uint32_t used[] = {0};
  ASSERT_TRUE(f.answer(3, used, std::span<const uint32_t>()));
  EXPECT_EQ(f.hint(a, 3, true), NodeHint::Used);
  EXPECT_EQ(f.hint(a, 3), NodeHint::Used) << "a leaf now, whose data the rays used below it";
  EXPECT_EQ(f.hint(NodeKey{}, 3, true), NodeHint::Used);
  EXPECT_EQ(f.hint(b, 3, true), NodeHint::Unused);
  EXPECT_EQ(f.hint(a1, 3), NodeHint::Unused);

  f.rememberCut(4, {a0, a1, b0, b1, e}, {1, 1, 1, 1, 0});
  ASSERT_TRUE(f.answer(4, std::span<const uint32_t>(), std::span<const uint32_t>()));
  EXPECT_EQ(f.hint(NodeKey{}, 4, true), NodeHint::Unused) << "no ray sampled anything";
}

}  // namespace
}  // namespace ropecast
