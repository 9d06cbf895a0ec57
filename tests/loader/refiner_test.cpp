// Refinement order and stopping rules on hand-made trees, with a fake data path (BrickResidency).
#include "loader/refiner.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "loader/ray_feedback.h"
#include "tests/loader/testutil_fake_brick_source.h"

namespace ropecast {
namespace {

using testing::FakeBrickSource;
using testing::isFullTiling;
using testing::KeyLess;

// A data path where everything is in core and the pool has `slotCapacity` slots; chosen nodes' children are
// "not in core". Records every acquire.
class FakeResidency : public BrickResidency {
 public:
  Outcome acquire(std::span<const NodeKey> keys, double priority, std::span<uint32_t> slotsOut) override {
    askedFor.insert(keys.begin(), keys.end());
    for (const NodeKey& k : keys) {
      if (notInCore.count(k)) return Outcome::NotInCore;
    }
    if (pinned + keys.size() > slotCapacity) return Outcome::PoolFull;
    for (size_t i = 0; i < keys.size(); ++i) slotsOut[i] = nextSlot++;
    pinned += keys.size();
    acquired.insert(keys.begin(), keys.end());
    return Outcome::Ready;
  }
  std::set<NodeKey, KeyLess> notInCore;
  std::set<NodeKey, KeyLess> acquired;
  size_t readAheadRoom() const override { return aheadRoom; }
  size_t poolFullReadAheadRoom() const override { return poolFullRoom; }
  std::set<NodeKey, KeyLess> askedFor;  // acquired or not
  size_t aheadRoom = 0;
  size_t poolFullRoom = 0;
  size_t slotCapacity = 1u << 30;
  size_t pinned = 0;
  uint32_t nextSlot = 0;
};

// 64^3 samples, bricks of 16: depths 0..2.
FakeBrickSource makeSource(FakeBrickSource::NodeFn fn = {}) {
  return FakeBrickSource({64, 64, 64}, 16, fn);
}

RefineView viewFrom(glm::dvec3 eye, glm::dvec3 target, uint32_t heightPx = 100, double fovDeg = 90.0) {
  RefineView v;
  v.camera.eye = eye;
  v.camera.target = target;
  v.camera.up = {0, 1, 0};
  v.camera.fovYDeg = fovDeg;
  v.viewportWidth = heightPx;
  v.viewportHeight = heightPx;
  return v;
}

TEST(Refiner, ProjectedVoxelPixelsMatchesThePinholeFormula) {
  const FakeBrickSource src = makeSource();
  const RefineView v = viewFrom({32, 32, -100}, {32, 32, 32});
  // Root: level 2 (voxel = 4 samples), nearest point (32,32,0) at distance 100, tan(45 deg) = 1, 100 px high.
  EXPECT_NEAR(projectedVoxelPixels(src.info().layout, glm::dvec3(1.0), NodeKey{}, v), 4.0 / 200.0 * 100.0,
              1e-9);
  // A child facing the eye at the same distance has half the voxel size.
  const NodeKey child{1, {0, 0, 0}};  // box [0,32]^3, nearest point (32,32,0)
  EXPECT_NEAR(projectedVoxelPixels(src.info().layout, glm::dvec3(1.0), child, v), 1.0, 1e-9);
  // Anisotropic spacing: the largest spacing counts.
  EXPECT_NEAR(projectedVoxelPixels(src.info().layout, glm::dvec3(1.0, 1.0, 0.5), NodeKey{},
                                   viewFrom({32, 32, -100}, {32, 32, 16})),
              4.0 / 200.0 * 100.0, 1e-9);
}

TEST(Refiner, EyeInsideANodeGivesAHugeButFiniteSize) {
  const FakeBrickSource src = makeSource();
  const RefineView v = viewFrom({10, 10, 10}, {32, 32, 32});
  const double px = projectedVoxelPixels(src.info().layout, glm::dvec3(1.0), NodeKey{2, {0, 0, 0}}, v);
  EXPECT_TRUE(std::isfinite(px));
  EXPECT_GT(px, 50.0);
}

TEST(Refiner, ANodesDataPartsAreItsChildrenThatHoldDataAndTheirBoxBoundsThem) {
  // 64^3, bricks of 16: depths 0..2. Below the root, child (1,1,1) is NodeKind::Empty and children with
  // x = 1 have values [0, 10]; below depth-1 node (0,0,0) every child but (0,0,0) is empty.
  auto fn = [](const NodeKey& k) -> NodeInfo {
    if (k.depth == 1 && k.coord == glm::u32vec3(1, 1, 1)) return {NodeKind::Empty, 0, 0};
    if (k.depth == 1 && k.coord.x == 1) return {NodeKind::Data, 0, 10};
    if (k.depth == 2 && k.coord.x < 2 && k.coord.y < 2 && k.coord.z < 2 && k.coord != glm::u32vec3(0))
      return {NodeKind::Empty, 0, 0};
    return {NodeKind::Data, 0, 255};
  };
  const FakeBrickSource src({64, 64, 64}, 16, fn);
  const auto isoEmpty = [](uint16_t lo, uint16_t hi) { return !(lo <= 100 && 100 <= hi); };  // iso 100
  auto expectBox = [](const WorldBox& b, glm::dvec3 lo, glm::dvec3 hi) {
    EXPECT_EQ(b.lo, lo);
    EXPECT_EQ(b.hi, hi);
  };
  // Without a predicate only NodeKind::Empty is empty: the children's bounding box is the whole root.
  expectBox(boundingBox(nodeDataParts(src, {}, NodeKey{}, unboundedBox())), glm::dvec3(0), glm::dvec3(64));
  // With the isovalue the x = 1 children are empty too: the x = 0 half.
  expectBox(boundingBox(nodeDataParts(src, isoEmpty, NodeKey{}, unboundedBox())), glm::dvec3(0),
            glm::dvec3(32, 64, 64));
  // One child with data: its box.
  expectBox(boundingBox(nodeDataParts(src, isoEmpty, NodeKey{1, {0, 0, 0}}, unboundedBox())), glm::dvec3(0),
            glm::dvec3(16));
  // The finest depth, and a node whose children all count empty: the node's own box.
  expectBox(boundingBox(nodeDataParts(src, isoEmpty, NodeKey{2, {1, 0, 0}}, unboundedBox())),
            glm::dvec3(16, 0, 0), glm::dvec3(32, 16, 16));
  const auto allEmpty = [](uint16_t, uint16_t) { return true; };
  expectBox(boundingBox(nodeDataParts(src, allEmpty, NodeKey{}, unboundedBox())), glm::dvec3(0),
            glm::dvec3(64));
  // The parts themselves: the four x = 0 children of the root, each its own box.
  const NodeDataParts parts = nodeDataParts(src, isoEmpty, NodeKey{}, unboundedBox());
  ASSERT_EQ(parts.count, 4u);
  for (uint32_t i = 0; i < parts.count; ++i) {
    EXPECT_EQ(parts.boxes[i].lo.x, 0.0);
    EXPECT_EQ(parts.boxes[i].hi - parts.boxes[i].lo, glm::dvec3(32));
  }
  EXPECT_EQ(nodeDataParts(src, allEmpty, NodeKey{}, unboundedBox()).count, 1u);
  expectBox(nodeDataParts(src, allEmpty, NodeKey{}, unboundedBox()).boxes[0], glm::dvec3(0), glm::dvec3(64));
}

TEST(Refiner, FrustumCullingIsConservative) {
  const RefineView v = viewFrom({0, 0, -10}, {0, 0, 0});  // looking along +z, 90 degrees
  EXPECT_TRUE(boxInFrustum({{-1, -1, 0}, {1, 1, 1}}, v));
  EXPECT_FALSE(boxInFrustum({{-1, -1, -20}, {1, 1, -11}}, v));          // behind the eye
  EXPECT_FALSE(boxInFrustum({{30, -1, 0}, {31, 1, 1}}, v));             // right of the 45-degree side plane
  EXPECT_TRUE(boxInFrustum({{5, -1, 0}, {31, 1, 1}}, v));               // straddles the side plane
  EXPECT_TRUE(boxInFrustum({{-100, -100, -100}, {100, 100, 100}}, v));  // contains the eye
}

TEST(Refiner, FarCameraKeepsTheRootAndNearCameraRefinesToTheFinestLevel) {
  const FakeBrickSource src = makeSource();
  FakeResidency far;
  const RefineResult r1 = refine(src, viewFrom({32, 32, -1e5}, {32, 32, 32}), {}, far);
  ASSERT_EQ(r1.leaves.size(), 1u);
  EXPECT_EQ(r1.leaves[0].reason, LeafReason::Adequate);
  EXPECT_EQ(r1.leaves[0].content, LeafContent::Brick);
  EXPECT_TRUE(r1.complete);

  FakeResidency near;
  RefineView v = viewFrom({32, 32, -1}, {32, 32, 32}, 4000);
  const RefineResult r2 = refine(src, v, {}, near);
  EXPECT_TRUE(isFullTiling(r2.leaves, 2));
  EXPECT_EQ(r2.leaves.size(), 64u);
  for (const PlannedLeaf& l : r2.leaves) {
    EXPECT_EQ(l.key.depth, 2u);
    EXPECT_EQ(l.reason, LeafReason::Finest);
    EXPECT_EQ(l.content, LeafContent::Brick);
  }
  // Every leaf has its own slot.
  std::set<uint32_t> slots;
  for (const PlannedLeaf& l : r2.leaves) slots.insert(l.slot);
  EXPECT_EQ(slots.size(), r2.leaves.size());
}

TEST(Refiner, RefinesByDecreasingProjectedVoxelSize) {
  // 256^3, bricks of 16: depths 0..4; an oblique camera near a corner gives many distinct priorities.
  const FakeBrickSource src({256, 256, 256}, 16);
  FakeResidency res;
  const RefineView v = viewFrom({-20, -30, -40}, {128, 128, 128}, 512, 60.0);
  const RefineResult r = refine(src, v, {}, res);
  ASSERT_GT(r.refinedOrder.size(), 20u);
  double previous = INFINITY;
  for (const NodeKey& k : r.refinedOrder) {
    const double px = projectedVoxelPixels(src.info().layout, glm::dvec3(1.0), k, v);
    EXPECT_LE(px, previous) << "depth " << k.depth;
    EXPECT_GT(px, 1.0);  // only inadequate nodes are refined
    previous = px;
  }
  EXPECT_TRUE(isFullTiling(r.leaves, 4));
  for (const PlannedLeaf& l : r.leaves) {
    if (l.reason == LeafReason::Adequate) {
      EXPECT_LE(l.voxelPixels, 1.0);
    }
  }
  // A coarser target refines less.
  FakeResidency coarse;
  RefineView v2 = v;
  v2.voxelsPerPixel = 0.25;
  const RefineResult r2 = refine(src, v2, {}, coarse);
  EXPECT_LT(r2.leaves.size(), r.leaves.size());
  for (const PlannedLeaf& l : r2.leaves) {
    if (l.reason == LeafReason::Adequate) {
      EXPECT_LE(l.voxelPixels, 4.0);
    }
  }
}

TEST(Refiner, EmptyOutsideAndConstantNodesAreTerminalWithoutBricks) {
  // 48^3 with bricks of 16: depth 2 has 3 inside nodes per axis, so x = 3 is outside the data.
  // Node min/max: value range [0, 10] for x < 2 at depth 2 ("air"), constant 100 (the isovalue) for depth-2
  // nodes at x = 2, NodeKind::Empty at depth 1 coord (0,1,1).
  auto fn = [](const NodeKey& k) -> NodeInfo {
    if (k.depth == 1 && k.coord == glm::u32vec3(0, 1, 1)) return {NodeKind::Empty, 0, 0};
    if (k.depth == 2 && k.coord.x == 2) return {NodeKind::Constant, 100, 100};
    if (k.depth == 2 && k.coord.x < 2 && k.coord.y == 0) return {NodeKind::Data, 0, 10};
    return {NodeKind::Data, 0, 255};
  };
  const FakeBrickSource src({48, 48, 48}, 16, fn);
  const auto isoEmpty = [](uint16_t lo, uint16_t hi) { return !(lo <= 100 && 100 <= hi); };  // iso 100
  FakeResidency res;
  const RefineResult r = refine(src, viewFrom({24, 24, -2}, {24, 24, 24}, 4000), isoEmpty, res);
  EXPECT_TRUE(isFullTiling(r.leaves, 2));
  EXPECT_TRUE(r.complete);
  std::map<LeafReason, size_t> byReason;
  for (const PlannedLeaf& l : r.leaves) ++byReason[l.reason];
  EXPECT_GT(byReason[LeafReason::Outside], 0u);
  EXPECT_GT(byReason[LeafReason::Empty], 1u);
  EXPECT_GT(byReason[LeafReason::Constant], 0u);
  EXPECT_GT(byReason[LeafReason::Finest], 0u);
  for (const PlannedLeaf& l : r.leaves) {
    const NodeInfo info = src.node(l.key);
    if (!src.info().layout.isInside(l.key)) {
      EXPECT_EQ(l.reason, LeafReason::Outside);
      EXPECT_EQ(l.content, LeafContent::Empty);
    } else if (info.kind == NodeKind::Empty || isoEmpty(info.minValue, info.maxValue)) {
      EXPECT_EQ(l.reason, LeafReason::Empty);
      EXPECT_EQ(l.content, LeafContent::Empty);
    } else if (info.kind == NodeKind::Constant) {
      EXPECT_EQ(l.reason, LeafReason::Constant);
      EXPECT_EQ(l.content, LeafContent::Brick);
    } else {
      EXPECT_EQ(l.content, LeafContent::Brick);
    }
    // Empty leaves never asked for a brick.
    EXPECT_EQ(res.acquired.count(l.key) != 0, l.content == LeafContent::Brick);
  }
  // The Empty node at depth 1 is a leaf; its children were never considered.
  EXPECT_TRUE(std::any_of(r.leaves.begin(), r.leaves.end(), [](const PlannedLeaf& l) {
    return l.key == NodeKey{1, {0, 1, 1}};
  }));
}

TEST(Refiner, ChildrenNotInCoreKeepTheParentAsALeaf) {
  const FakeBrickSource src = makeSource();
  FakeResidency res;
  const NodeKey held{1, {1, 1, 0}};
  res.notInCore.insert(held.child(0));  // one missing child is enough
  const RefineResult r = refine(src, viewFrom({32, 32, -1}, {32, 32, 32}, 4000), {}, res);
  EXPECT_FALSE(r.complete);
  EXPECT_TRUE(isFullTiling(r.leaves, 2));
  bool found = false;
  for (const PlannedLeaf& l : r.leaves) {
    if (l.key == held) {
      found = true;
      EXPECT_EQ(l.reason, LeafReason::NotInCore);
      EXPECT_EQ(l.content, LeafContent::Brick);  // renders at its coarser level: no hole
    } else {
      EXPECT_EQ(l.key.depth, 2u);
    }
  }
  EXPECT_TRUE(found);
  // Missing root: a Missing leaf and nothing else.
  FakeResidency cold;
  cold.notInCore.insert(NodeKey{});
  const RefineResult r0 = refine(src, viewFrom({32, 32, -1}, {32, 32, 32}), {}, cold);
  ASSERT_EQ(r0.leaves.size(), 1u);
  EXPECT_EQ(r0.leaves[0].content, LeafContent::Missing);
  EXPECT_FALSE(r0.complete);
}

TEST(Refiner, FullPoolStopsRefinementButTheCutIsComplete) {
  const FakeBrickSource src({256, 256, 256}, 16);
  FakeResidency res;
  res.slotCapacity = 30;
  const RefineResult r = refine(src, viewFrom({-20, -30, -40}, {128, 128, 128}, 512, 60.0), {}, res);
  EXPECT_TRUE(r.complete);
  EXPECT_TRUE(isFullTiling(r.leaves, 4));
  size_t bricks = 0, poolFull = 0;
  for (const PlannedLeaf& l : r.leaves) {
    bricks += l.content == LeafContent::Brick;
    poolFull += l.reason == LeafReason::PoolFull;
  }
  EXPECT_LE(bricks, 30u);
  EXPECT_GT(poolFull, 0u);
}

TEST(Refiner, AFullPoolGoesToNodesInPriorityOrder) {
  // Depth-2 nodes with an odd x have one data child, the others eight: once a node's eight children no longer
  // fit, a node of lower priority with one child would, and taking it would make the cut depend on which
  // children happen to be empty: the next frame's hints reorder the nodes and the cut swaps them back and
  // forth.
  auto fn = [](const NodeKey& k) -> NodeInfo {
    if (k.depth == 3 && k.coord.x / 2 % 2 == 1 && k.coord != k.parent().child(0).coord)
      return {NodeKind::Empty, 0, 0};
    return {NodeKind::Data, 0, 255};
  };
  const FakeBrickSource src({256, 256, 256}, 16, fn);
  const RefineView view = viewFrom({-20, -30, -40}, {128, 128, 128}, 512, 60.0);
  for (size_t capacity = 40; capacity < 200; capacity += 3) {
    FakeResidency res;
    res.slotCapacity = capacity;
    const RefineResult r = refine(src, view, {}, res);
    EXPECT_TRUE(isFullTiling(r.leaves, 4));
    double lowestRefined = INFINITY, highestRefused = 0.0;
    for (const NodeKey& k : r.refinedOrder)
      lowestRefined =
          std::min(lowestRefined, projectedVoxelPixels(src.info().layout, glm::dvec3(1.0), k, view));
    for (const PlannedLeaf& l : r.leaves)
      if (l.reason == LeafReason::PoolFull) highestRefused = std::max(highestRefused, l.voxelPixels);
    EXPECT_GT(highestRefused, 0.0) << "capacity " << capacity;
    EXPECT_GE(lowestRefined, highestRefused) << "capacity " << capacity;
  }
}

TEST(Refiner, AFullPoolReadsAheadBelowTheLeavesItHadNoRoomForInTheirOrder) {
  // Depth-3 children of odd depth-2 nodes are empty or constant but one: only data children are read.
  auto fn = [](const NodeKey& k) -> NodeInfo {
    if (k.depth == 3 && k.parent().coord.x % 2 == 1) {
      const uint32_t octant = (k.coord.x & 1u) | (k.coord.y & 1u) << 1 | (k.coord.z & 1u) << 2;
      if (octant == 1) return {NodeKind::Constant, 7, 7};
      if (octant != 0) return {NodeKind::Empty, 0, 0};
    }
    return {NodeKind::Data, 0, 255};
  };
  const FakeBrickSource src({256, 256, 256}, 16, fn);
  const RefineView view = viewFrom({-20, -30, -40}, {128, 128, 128}, 512, 60.0);
  FakeResidency res;
  res.slotCapacity = 60;
  res.poolFullRoom = 1u << 20;
  const RefineResult r = refine(src, view, {}, res);
  // The data children in view of the PoolFull leaves, leaf by leaf in the cut's order.
  std::vector<NodeKey> expected;
  for (const PlannedLeaf& l : r.leaves) {
    if (l.reason != LeafReason::PoolFull) continue;
    for (uint32_t o = 0; o < 8; ++o) {
      const NodeKey c = l.key.child(o);
      if (src.node(c).kind == NodeKind::Data &&
          boxInFrustum(nodeWorldBox(src.info().layout, glm::dvec3(1.0), c), view))
        expected.push_back(c);
    }
  }
  ASSERT_GT(expected.size(), 16u);
  EXPECT_EQ(r.poolFullReadAhead, expected);
  EXPECT_TRUE(std::none_of(r.poolFullReadAhead.begin(), r.poolFullReadAhead.end(),
                           [&](const NodeKey& k) { return res.acquired.count(k) != 0; }));

  // Within the room, the first ones; none without room, nor when the pool held everything.
  FakeResidency small = res;
  small.poolFullRoom = 11;
  small.pinned = 0;
  const RefineResult r11 = refine(src, view, {}, small);
  EXPECT_EQ(r11.poolFullReadAhead, std::vector<NodeKey>(expected.begin(), expected.begin() + 11));
  FakeResidency none = res;
  none.poolFullRoom = 0;
  none.pinned = 0;
  EXPECT_TRUE(refine(src, view, {}, none).poolFullReadAhead.empty());
  FakeResidency roomy;
  roomy.poolFullRoom = 1u << 20;
  EXPECT_TRUE(refine(src, view, {}, roomy).poolFullReadAhead.empty());
}

TEST(Refiner, NodesOutsideTheFrustumAreCulled) {
  const FakeBrickSource src = makeSource();
  FakeResidency res;
  // Close to the x = 0 face, looking at -x away from most of the volume: only the half x < 32 at most is
  // seen.
  const RefineResult r = refine(src, viewFrom({8, 32, 32}, {-100, 32, 32}, 1000, 30.0), {}, res);
  EXPECT_TRUE(isFullTiling(r.leaves, 2));
  size_t culled = 0;
  for (const PlannedLeaf& l : r.leaves) {
    if (l.reason == LeafReason::Culled) {
      ++culled;
      EXPECT_EQ(l.content, LeafContent::Empty);
      EXPECT_FALSE(boxInFrustum(nodeWorldBox(src.info().layout, glm::dvec3(1.0), l.key),
                                viewFrom({8, 32, 32}, {-100, 32, 32}, 1000, 30.0)));
    }
  }
  EXPECT_GT(culled, 0u);
}

TEST(Refiner, NodesWhollyOutsideTheCropBoxAreCulledAndNeverAcquired) {
  const FakeBrickSource src = makeSource();
  FakeResidency whole, cropped;
  RefineView view = viewFrom({32, 32, -60}, {32, 32, 32}, 4000);  // fine enough to refine to depth 2
  const RefineResult all = refine(src, view, {}, whole);
  // Voxels x 20..47 and z 0..15: depth-2 nodes (16 voxels a side) with x in 1..2 and z = 0 hold them.
  view.sampled = {glm::dvec3(20, 0, 0), glm::dvec3(48, 64, 16)};
  const RefineResult r = refine(src, view, {}, cropped);
  EXPECT_TRUE(isFullTiling(r.leaves, 2));
  const auto overlapsCrop = [&](const NodeKey& k) {
    return hasVolume(intersection(nodeWorldBox(src.info().layout, glm::dvec3(1.0), k), view.sampled));
  };
  size_t bricks = 0;
  for (const PlannedLeaf& l : r.leaves) {
    if (l.content == LeafContent::Brick) {
      ++bricks;
      EXPECT_TRUE(overlapsCrop(l.key)) << "depth " << l.key.depth << " x " << l.key.coord.x;
    } else if (!overlapsCrop(l.key)) {
      EXPECT_EQ(l.reason, LeafReason::Culled);
    }
  }
  // 2 x 4 x 1 depth-2 leaves; nodes x = 3 and z = 1 touch the box only at a face and are culled too.
  EXPECT_EQ(bricks, 8u);
  for (const NodeKey& k : cropped.acquired) EXPECT_TRUE(overlapsCrop(k));
  EXPECT_LT(cropped.acquired.size(), whole.acquired.size());
  // A crop box without volume culls everything but the root, whose brick every frame acquires.
  FakeResidency none;
  view.sampled = {glm::dvec3(20, 0, 0), glm::dvec3(20, 64, 64)};
  const RefineResult empty = refine(src, view, {}, none);
  ASSERT_EQ(empty.leaves.size(), 1u);
  EXPECT_EQ(empty.leaves[0].reason, LeafReason::Culled);
  EXPECT_TRUE(none.acquired.empty());
  EXPECT_EQ(std::count_if(all.leaves.begin(), all.leaves.end(),
                          [](const PlannedLeaf& l) { return l.content == LeafContent::Brick; }),
            64);
}

TEST(Refiner, NodesWhollyOnTheSideAClipPlaneCutsAwayAreCulled) {
  const FakeBrickSource src = makeSource();
  FakeResidency res;
  RefineView view = viewFrom({32, 32, -60}, {32, 32, 32}, 4000);
  // Keeps x + z >= 64 (normal (1, 0, 1) / sqrt 2 through (32, 0, 32)).
  view.clipPlane = {glm::dvec3(32, 0, 32), glm::normalize(glm::dvec3(1, 0, 1))};
  const RefineResult r = refine(src, view, {}, res);
  EXPECT_TRUE(isFullTiling(r.leaves, 2));
  const auto kept = [&](const NodeKey& k) {
    const WorldBox b = nodeWorldBox(src.info().layout, glm::dvec3(1.0), k);
    return b.hi.x + b.hi.z >= 64.0;  // its corner farthest along the normal
  };
  size_t bricks = 0, culled = 0;
  for (const PlannedLeaf& l : r.leaves) {
    EXPECT_EQ(l.content == LeafContent::Brick, kept(l.key))
        << "depth " << l.key.depth << " x " << l.key.coord.x << " z " << l.key.coord.z;
    bricks += l.content == LeafContent::Brick;
    culled += l.reason == LeafReason::Culled;
  }
  // Depth-2 nodes (16 a side) of the 4 x 4 columns with (x + 1) + (z + 1) >= 4: all but (0, 0), (1, 0) and
  // (0, 1), 13 columns (those with x + z = 2 touch the plane along an edge and are kept), 4 high.
  EXPECT_EQ(bricks, 52u);
  EXPECT_GT(culled, 0u);
  for (const NodeKey& k : res.acquired) EXPECT_TRUE(kept(k));
  EXPECT_TRUE(boxKeptByPlane({glm::dvec3(0), glm::dvec3(1)}, ClipPlane{}));  // no plane keeps everything
}

TEST(Refiner, ASlabKeepsOnlyTheNodesWithinItsFaces) {
  const FakeBrickSource src = makeSource();
  FakeResidency res;
  RefineView view = viewFrom({32, 32, -60}, {32, 32, 32}, 4000);
  view.clipPlane = {glm::dvec3(0, 0, 40), glm::dvec3(0, 0, -1), 8.0};  // 36 <= z <= 44, the normal either way
  const RefineResult r = refine(src, view, {}, res);
  EXPECT_TRUE(isFullTiling(r.leaves, 2));
  const auto kept = [&](const NodeKey& k) {
    const WorldBox b = nodeWorldBox(src.info().layout, glm::dvec3(1.0), k);
    return b.hi.z >= 36.0 && b.lo.z <= 44.0;
  };
  size_t bricks = 0;
  for (const PlannedLeaf& l : r.leaves) {
    EXPECT_EQ(l.content == LeafContent::Brick, kept(l.key))
        << "depth " << l.key.depth << " z " << l.key.coord.z;
    bricks += l.content == LeafContent::Brick;
  }
  EXPECT_EQ(bricks, 16u);  // the depth-2 layer z in [32, 48), 4 x 4 nodes
  for (const NodeKey& k : res.acquired) EXPECT_TRUE(kept(k));
  // From an eye 100 below the slab's near face (z = 36), a node is measured no nearer than it.
  const NodeKey child{1,
                      {0, 0, 0}};  // box [0,32]^3, nearest point (32,32,0) at distance 100 from (32,32,-100)
  RefineView below = viewFrom({32, 32, -100}, {32, 32, 32});
  below.clipPlane = view.clipPlane;
  EXPECT_NEAR(projectedVoxelPixels(src.info().layout, glm::dvec3(1.0), child, below), 100.0 / 136.0, 1e-9);
}

TEST(Refiner, ASliceKeepsOnlyTheNodesItsPlaneCrosses) {
  const FakeBrickSource src = makeSource();
  FakeResidency res;
  RefineView view = viewFrom({32, 32, -60}, {32, 32, 32}, 4000);
  // x + z = 64 (normal (1, 0, 1) / sqrt 2 through (32, 0, 32)), shown on its own.
  view.clipPlane = {glm::dvec3(32, 0, 32), glm::normalize(glm::dvec3(1, 0, 1))};
  view.slice = true;
  const RefineResult r = refine(src, view, {}, res);
  EXPECT_TRUE(isFullTiling(r.leaves, 2));
  const auto crossed = [&](const NodeKey& k) {
    const WorldBox b = nodeWorldBox(src.info().layout, glm::dvec3(1.0), k);
    return b.lo.x + b.lo.z <= 64.0 && b.hi.x + b.hi.z >= 64.0;
  };
  size_t bricks = 0;
  for (const PlannedLeaf& l : r.leaves) {
    EXPECT_EQ(l.content == LeafContent::Brick, crossed(l.key))
        << "depth " << l.key.depth << " x " << l.key.coord.x << " z " << l.key.coord.z;
    bricks += l.content == LeafContent::Brick;
  }
  // Depth-2 nodes (16 a side) of the 4 x 4 columns with x + z <= 4 <= (x + 1) + (z + 1): 4 + 3 + 2 (the
  // diagonal x + z = 3 and the columns touching the plane along an edge, x + z = 2 and 4), 4 high.
  EXPECT_EQ(bricks, 4u * (4 + 3 + 3));
  for (const NodeKey& k : res.acquired) EXPECT_TRUE(crossed(k));
  EXPECT_TRUE(boxMeetsPlane({glm::dvec3(0), glm::dvec3(1)}, ClipPlane{}));  // no plane: everything
  EXPECT_TRUE(boxMeetsPlane({glm::dvec3(0), glm::dvec3(1)}, {glm::dvec3(1, 0, 0), glm::dvec3(1, 0, 0)}));
  EXPECT_FALSE(boxMeetsPlane({glm::dvec3(0), glm::dvec3(1)}, {glm::dvec3(1.5, 0, 0), glm::dvec3(-1, 0, 0)}));
}

TEST(Refiner, FromAnEyeOnTheCutSideAProjectedSizeIsMeasuredNoNearerThanTheClipPlane) {
  const FakeBrickSource src = makeSource();
  RefineView view = viewFrom({32, 32, -100}, {32, 32, 32});
  const NodeKey child{1, {0, 0, 0}};  // box [0,32]^3, nearest point (32,32,0) at distance 100
  // The plane z = 20 keeping z >= 20: the eye is on the cut side, 120 from the plane.
  view.clipPlane = {glm::dvec3(0, 0, 20), glm::dvec3(0, 0, 1)};
  EXPECT_NEAR(projectedVoxelPixels(src.info().layout, glm::dvec3(1.0), child, view), 100.0 / 120.0, 1e-9);
  // Keeping z <= 20 instead, the eye is on the kept side: the box's nearest point counts.
  view.clipPlane = {glm::dvec3(0, 0, 20), glm::dvec3(0, 0, -1)};
  EXPECT_NEAR(projectedVoxelPixels(src.info().layout, glm::dvec3(1.0), child, view), 1.0, 1e-9);
  // A slice's samples all lie on its plane, 120 from the eye, whichever side the normal points to.
  view.slice = true;
  EXPECT_NEAR(projectedVoxelPixels(src.info().layout, glm::dvec3(1.0), child, view), 100.0 / 120.0, 1e-9);
}

TEST(Refiner, ANodesProjectedSizeIsMeasuredOnItsPartInsideTheCropBox) {
  const FakeBrickSource src = makeSource();
  RefineView view = viewFrom({32, 32, -100}, {32, 32, 32});
  const NodeKey child{1, {0, 0, 0}};  // box [0,32]^3, nearest point (32,32,0) at distance 100
  EXPECT_NEAR(projectedVoxelPixels(src.info().layout, glm::dvec3(1.0), child, view), 1.0, 1e-9);
  // Cut to z >= 20: its nearest point inside is at z = 20, distance 120. Cut to z >= 50, it has no part
  // inside (the refiner culls it), and its whole box counts.
  view.sampled = {glm::dvec3(0, 0, 20), glm::dvec3(64)};
  EXPECT_NEAR(projectedVoxelPixels(src.info().layout, glm::dvec3(1.0), child, view), 100.0 / 120.0, 1e-9);
  view.sampled = {glm::dvec3(0, 0, 50), glm::dvec3(64)};
  EXPECT_NEAR(projectedVoxelPixels(src.info().layout, glm::dvec3(1.0), child, view), 1.0, 1e-9);
}

TEST(Refiner, ANodesDataPartsAreCutToTheCropBox) {
  const FakeBrickSource src = makeSource();
  const WorldBox crop{glm::dvec3(10, 0, 0), glm::dvec3(40, 64, 30)};
  const NodeDataParts parts = nodeDataParts(src, {}, NodeKey{}, crop);
  // The root's four children below z = 32 reach into the box.
  ASSERT_EQ(parts.count, 4u);
  for (uint32_t i = 0; i < parts.count; ++i) {
    EXPECT_TRUE(hasVolume(parts.boxes[i]));
    EXPECT_TRUE(glm::all(glm::greaterThanEqual(parts.boxes[i].lo, crop.lo)));
    EXPECT_TRUE(glm::all(glm::lessThanEqual(parts.boxes[i].hi, crop.hi)));
  }
  EXPECT_EQ(boundingBox(parts), crop);
  // A finest node is its own part, cut to the box.
  const NodeDataParts leaf = nodeDataParts(src, {}, NodeKey{2, {0, 0, 0}}, crop);
  ASSERT_EQ(leaf.count, 1u);
  EXPECT_EQ(leaf.boxes[0], (WorldBox{glm::dvec3(10, 0, 0), glm::dvec3(16, 16, 16)}));
}

TEST(Refiner, AnOccludedNodeStaysALeafAndItsChildrenAreNeverAcquired) {
  const FakeBrickSource src = makeSource();
  const RefineView v = viewFrom({32, 32, -1}, {32, 32, 32}, 4000);
  const NodeKey hidden{1, {1, 1, 1}};
  FakeResidency res;
  const RefineResult r = refine(
      src, v, {}, res, [&](const NodeKey& k) { return k == hidden ? NodeHint::Occluded : NodeHint::None; });
  EXPECT_TRUE(r.complete);  // an occluded leaf waits for nothing
  EXPECT_TRUE(isFullTiling(r.leaves, 2));
  size_t occluded = 0;
  for (const PlannedLeaf& l : r.leaves) {
    if (l.key == hidden) {
      ++occluded;
      EXPECT_EQ(l.reason, LeafReason::Occluded);
      EXPECT_EQ(l.content, LeafContent::Brick);  // still drawn at its own level
    } else {
      EXPECT_EQ(l.key.depth, 2u);
    }
  }
  EXPECT_EQ(occluded, 1u);
  for (uint32_t o = 0; o < 8; ++o) EXPECT_EQ(res.acquired.count(hidden.child(o)), 0u);
  EXPECT_STREQ(leafReasonName(LeafReason::Occluded), "occluded");
  EXPECT_STREQ(leafReasonName(LeafReason::Unused), "unused");

  // A missing child of the hidden node is not requested either: the data path is never asked for it.
  FakeResidency cold;
  cold.notInCore.insert(hidden.child(3));
  const RefineResult rc = refine(
      src, v, {}, cold, [&](const NodeKey& k) { return k == hidden ? NodeHint::Occluded : NodeHint::None; });
  EXPECT_TRUE(rc.complete);
  EXPECT_EQ(cold.askedFor.count(hidden.child(3)), 0u);
}

TEST(Refiner, AnOccludedOrUnusedInnerNodeCollapsesItsSubtree) {
  // 256^3, bricks of 16: depths 0..4; the near view refines node (1, 0,0,0) down to depth 4.
  const FakeBrickSource src({256, 256, 256}, 16);
  const RefineView v = viewFrom({-20, -30, -40}, {128, 128, 128}, 512, 60.0);
  FakeResidency plain;
  const RefineResult full = refine(src, v, {}, plain);
  const NodeKey inner{1, {0, 0, 0}};
  ASSERT_TRUE(std::find(full.refinedOrder.begin(), full.refinedOrder.end(), inner) !=
              full.refinedOrder.end());

  for (const NodeHint hint : {NodeHint::Occluded, NodeHint::Unused}) {
    FakeResidency res;
    const RefineResult r =
        refine(src, v, {}, res, [&](const NodeKey& k) { return k == inner ? hint : NodeHint::None; });
    EXPECT_TRUE(r.complete);
    EXPECT_TRUE(isFullTiling(r.leaves, 4));
    EXPECT_LT(r.leaves.size(), full.leaves.size());
    const auto it =
        std::find_if(r.leaves.begin(), r.leaves.end(), [&](const PlannedLeaf& l) { return l.key == inner; });
    ASSERT_NE(it, r.leaves.end());
    EXPECT_EQ(it->reason, hint == NodeHint::Occluded ? LeafReason::Occluded : LeafReason::Unused);
    EXPECT_EQ(std::count(r.refinedOrder.begin(), r.refinedOrder.end(), inner), 0);
  }
}

TEST(Refiner, RequestedNodesAreRefinedBeforeHigherPriorityOnes) {
  const FakeBrickSource src = makeSource();
  const RefineView v = viewFrom({-20, -30, -40}, {32, 32, 32}, 2000);
  // Without hints the depth-1 node nearest the eye is refined first; (1, 1,1,1) is the farthest.
  const NodeKey nearest{1, {0, 0, 0}}, farthest{1, {1, 1, 1}};
  const auto px = [&](const NodeKey& k) {
    return projectedVoxelPixels(src.info().layout, glm::dvec3(1.0), k, v);
  };
  ASSERT_GT(px(nearest), px(farthest));
  ASSERT_GT(px(farthest), 1.0);  // both would be refined given room

  // Root + its 8 children + one node's 8 children: room to refine only one depth-1 node.
  FakeResidency plain;
  plain.slotCapacity = 17;
  const RefineResult r0 = refine(src, v, {}, plain);
  ASSERT_EQ(r0.refinedOrder.size(), 2u);
  EXPECT_EQ(r0.refinedOrder[1], nearest);

  FakeResidency res;
  res.slotCapacity = 17;
  const RefineResult r = refine(src, v, {}, res, [&](const NodeKey& k) {
    return k == farthest ? NodeHint::Requested : NodeHint::None;
  });
  ASSERT_EQ(r.refinedOrder.size(), 2u);
  EXPECT_EQ(r.refinedOrder[0], NodeKey{});  // the root first, always
  EXPECT_EQ(r.refinedOrder[1], farthest);
  for (uint32_t o = 0; o < 8; ++o) {
    EXPECT_EQ(res.acquired.count(farthest.child(o)), 1u);
    EXPECT_EQ(res.acquired.count(nearest.child(o)), 0u);
  }
  for (const PlannedLeaf& l : r.leaves) {
    if (l.key == nearest) {
      EXPECT_EQ(l.reason, LeafReason::PoolFull);
    }
  }
}

TEST(Refiner, UsedInnerNodesKeepTheirRefinementAgainstRequestsOfSmallerVoxels) {
  const FakeBrickSource src = makeSource();
  const RefineView v = viewFrom({-20, -30, -40}, {32, 32, 32}, 2000);
  const NodeKey nearest{1, {0, 0, 0}}, farthest{1, {1, 1, 1}};
  FakeResidency res;
  res.slotCapacity = 17;  // room to refine one depth-1 node
  const RefineResult r = refine(src, v, {}, res, [&](const NodeKey& k) {
    if (k == farthest) return NodeHint::Requested;
    return k == nearest || k == NodeKey{} ? NodeHint::Used : NodeHint::None;
  });
  ASSERT_EQ(r.refinedOrder.size(), 2u);
  EXPECT_EQ(r.refinedOrder[1], nearest) << "ranked together, the larger projected voxel wins";
}

// The loop of a still view with feedback: each frame's hints come from the rays' answer about a cut cast
// `latency` frames before (every data leaf used, every leaf the pool kept coarse requested). With a pool that
// cannot hold what the view asks for, the cut must settle instead of alternating between the requested and
// the kept nodes, whatever the latency.
TEST(Refiner, AFullPoolWithFeedbackSettlesOnOneCut) {
  const FakeBrickSource src({256, 256, 256}, 16);
  const RefineView v = viewFrom({-20, -30, -40}, {128, 128, 128}, 512, 60.0);
  FakeResidency unlimited;
  const size_t wanted = refine(src, v, {}, unlimited).refinedOrder.size() * 8 + 1;

  for (uint64_t latency = 1; latency <= 3; ++latency) {
    RayFeedback feedback;
    struct Answer {
      std::vector<uint32_t> used, requested;
    };
    std::vector<Answer> answers;
    std::vector<std::vector<NodeKey>> cuts;
    std::set<NodeKey, KeyLess> innerNow;  // the last frame's refined nodes: the tree on the GPU
    for (uint64_t frame = 0; frame < 16; ++frame) {
      if (frame >= latency) {
        const Answer& a = answers[frame - latency];
        ASSERT_TRUE(feedback.answer(frame - latency, a.used, a.requested));
      }
      FakeResidency res;
      res.slotCapacity = wanted / 2;
      const RefineResult r = refine(
          src, v, {}, res, [&](const NodeKey& k) { return feedback.hint(k, frame, innerNow.count(k)); });
      innerNow = {r.refinedOrder.begin(), r.refinedOrder.end()};
      std::vector<NodeKey> keys;
      std::vector<uint8_t> dataLeaf;
      Answer a;
      for (const PlannedLeaf& l : r.leaves) {
        if (l.content == LeafContent::Brick) {
          a.used.push_back(uint32_t(keys.size()));
          if (l.reason == LeafReason::PoolFull) a.requested.push_back(uint32_t(keys.size()));
        }
        keys.push_back(l.key);
        dataLeaf.push_back(l.content == LeafContent::Brick);
      }
      ASSERT_FALSE(a.requested.empty()) << "the pool must be too small for the view";
      feedback.rememberCut(frame, keys, dataLeaf);
      answers.push_back(std::move(a));
      cuts.push_back(std::move(keys));
    }
    for (size_t f = cuts.size() - 6; f < cuts.size(); ++f)
      EXPECT_EQ(cuts[f], cuts[f - 1])
          << "latency " << latency << ": frame " << f << " changed the cut of a still view";
  }
}

TEST(Refiner, ReadsAheadWhatTheNextRefinementsWillAskFor) {
  // 256^3, bricks of 16: depths 0..4. The root's children are not in core: the refinement stops at the root
  // and reads ahead every brick a refinement with everything in core would acquire below them.
  const FakeBrickSource src({256, 256, 256}, 16);
  const RefineView v = viewFrom({-20, -30, -40}, {128, 128, 128}, 512, 60.0);
  FakeResidency all;
  refine(src, v, {}, all);
  std::set<NodeKey, KeyLess> expected = all.acquired;
  expected.erase(NodeKey{});
  for (uint32_t o = 0; o < 8; ++o) expected.erase(NodeKey{}.child(o));
  ASSERT_GT(expected.size(), 100u);

  FakeResidency cold;
  cold.aheadRoom = 1u << 20;
  for (uint32_t o = 0; o < 8; ++o) cold.notInCore.insert(NodeKey{}.child(o));
  const RefineResult r = refine(src, v, {}, cold);
  ASSERT_EQ(r.leaves.size(), 1u);
  EXPECT_EQ(r.leaves[0].reason, LeafReason::NotInCore);
  const std::set<NodeKey, KeyLess> ahead(r.readAhead.begin(), r.readAhead.end());
  EXPECT_EQ(ahead.size(), r.readAhead.size());  // each once
  EXPECT_EQ(ahead, expected);
  for (size_t i = 1; i < r.readAhead.size(); ++i) EXPECT_LE(r.readAhead[i - 1].depth, r.readAhead[i].depth);

  // Within the room only, the first ones of the same order; none without room (the default).
  FakeResidency small = cold;
  small.aheadRoom = 10;
  const RefineResult r10 = refine(src, v, {}, small);
  ASSERT_EQ(r10.readAhead.size(), 10u);
  EXPECT_TRUE(std::equal(r10.readAhead.begin(), r10.readAhead.end(), r.readAhead.begin()));
  FakeResidency none = cold;
  none.aheadRoom = 0;
  EXPECT_TRUE(refine(src, v, {}, none).readAhead.empty());

  // Nothing below an occluded node is read ahead.
  const NodeKey hidden{1, {0, 0, 0}};
  FakeResidency hinted = cold;
  const RefineResult rh = refine(src, v, {}, hinted, [&](const NodeKey& k) {
    return k == hidden ? NodeHint::Occluded : NodeHint::None;
  });
  for (const NodeKey& k : rh.readAhead) {
    NodeKey a = k;
    while (a.depth > 1) a = a.parent();
    EXPECT_NE(a, hidden);
  }
  EXPECT_LT(rh.readAhead.size(), r.readAhead.size());
}

}  // namespace
}  // namespace ropecast
