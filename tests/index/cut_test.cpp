// validateCut names each kind of problem; completeCut fills exactly the uncovered regions with Empty leaves;
// sameLeaves compares cuts in any order of their leaves.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "index/cut.h"
#include "index/random_cut.h"

namespace ropecast {
namespace {

// The message of the std::invalid_argument that validateCut throws, or "" when it accepts the cut.
std::string problemOf(const Cut& cut) {
  try {
    validateCut(cut);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

Cut octants(uint32_t skip = 8) {
  Cut cut;
  for (uint32_t o = 0; o < 8; ++o)
    if (o != skip) cut.leaves.push_back({1, {o & 1u, (o >> 1) & 1u, (o >> 2) & 1u}, LeafKind::Data, o});
  return cut;
}

TEST(Cut, AcceptsTilings) {
  EXPECT_EQ(problemOf(Cut{{CutLeaf{}}}), "");
  EXPECT_EQ(problemOf(octants()), "");
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    RandomCutParams params;
    params.seed = seed;
    params.targetLeaves = 300;
    EXPECT_EQ(problemOf(makeRandomCut(params)), "");
  }
}

TEST(Cut, SameLeavesInAnyOrder) {
  const Cut cut = octants();
  Cut reversed = cut;
  std::reverse(reversed.leaves.begin(), reversed.leaves.end());
  EXPECT_TRUE(sameLeaves(cut, reversed));
  Cut otherSlot = reversed;
  otherSlot.leaves[3].brickSlot = 99;
  EXPECT_FALSE(sameLeaves(cut, otherSlot));
  Cut otherKind = cut;
  otherKind.leaves[0].kind = LeafKind::Empty;
  EXPECT_FALSE(sameLeaves(cut, otherKind));
  EXPECT_FALSE(sameLeaves(cut, octants(2)));
}

TEST(Cut, NamesTheProblem) {
  EXPECT_NE(problemOf(Cut{}).find("hole at depth 0"), std::string::npos);
  EXPECT_NE(problemOf(octants(5)).find("hole at depth 1 coord (1,0,1)"), std::string::npos);

  Cut overlap = octants();
  overlap.leaves.push_back({2, {3, 3, 3}, LeafKind::Empty, 0});
  EXPECT_NE(problemOf(overlap).find("leaf 8 (depth 2 coord (3,3,3)) overlaps leaf 7"), std::string::npos);

  Cut coarseAfterFine{{CutLeaf{2, {0, 0, 0}, LeafKind::Empty, 0}, CutLeaf{1, {0, 0, 0}, LeafKind::Empty, 0}}};
  EXPECT_NE(problemOf(coarseAfterFine).find("leaf 1 (depth 1 coord (0,0,0)) overlaps finer leaves"),
            std::string::npos);

  Cut duplicate = octants();
  duplicate.leaves.push_back(duplicate.leaves[2]);
  EXPECT_NE(problemOf(duplicate).find("leaf 8 (depth 1 coord (0,1,0)) overlaps leaf 2"), std::string::npos);

  EXPECT_NE(problemOf(Cut{{CutLeaf{1, {2, 0, 0}, LeafKind::Empty, 0}}}).find("coord outside [0, 2)"),
            std::string::npos);
  EXPECT_NE(problemOf(Cut{{CutLeaf{kCutMaxDepth + 1, {0, 0, 0}, LeafKind::Empty, 0}}}).find("deeper than"),
            std::string::npos);
  EXPECT_NE(problemOf(Cut{{CutLeaf{0, {0, 0, 0}, LeafKind::Data, 0xFFFFFFFFu}}}).find("reserved brick slot"),
            std::string::npos);
}

TEST(Cut, CompleteAddsEmptySiblingsUpToTheRoot) {
  const Cut root = completeCut({});
  ASSERT_EQ(root.leaves.size(), 1u);
  EXPECT_EQ(root.leaves[0].depth, 0u);
  EXPECT_EQ(root.leaves[0].kind, LeafKind::Empty);

  const CutLeaf deep{5, {17, 3, 30}, LeafKind::Data, 9};
  const Cut cut = completeCut(std::vector<CutLeaf>{deep});
  ASSERT_EQ(cut.leaves.size(), 1u + 7u * 5u);  // 7 siblings at each of the 5 levels
  EXPECT_EQ(cut.leaves[0].coord, deep.coord);
  EXPECT_EQ(cut.leaves[0].kind, LeafKind::Data);
  std::vector<int> perDepth(6, 0);
  for (size_t i = 1; i < cut.leaves.size(); ++i) {
    EXPECT_EQ(cut.leaves[i].kind, LeafKind::Empty);
    ++perDepth[cut.leaves[i].depth];
  }
  EXPECT_EQ(perDepth, (std::vector<int>{0, 7, 7, 7, 7, 7}));
  EXPECT_EQ(problemOf(cut), "");
}

TEST(Cut, CompleteKeepsGivenLeavesAndAddsNothingToATiling) {
  RandomCutParams params;
  params.targetLeaves = 200;
  const Cut full = makeRandomCut(params);
  const Cut same = completeCut(full.leaves);
  ASSERT_EQ(same.leaves.size(), full.leaves.size());
  // Dropping the Empty leaves and completing gives a tiling again, with the Data leaves first and unchanged.
  std::vector<CutLeaf> data;
  for (const CutLeaf& leaf : full.leaves)
    if (leaf.kind == LeafKind::Data) data.push_back(leaf);
  const Cut completed = completeCut(data);
  EXPECT_EQ(problemOf(completed), "");
  ASSERT_GE(completed.leaves.size(), data.size());
  for (size_t i = 0; i < data.size(); ++i) EXPECT_EQ(completed.leaves[i].brickSlot, data[i].brickSlot);
  EXPECT_THROW(completeCut(std::vector<CutLeaf>{data[0], data[0]}), std::invalid_argument);
}

}  // namespace
}  // namespace ropecast
