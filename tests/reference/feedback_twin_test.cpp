// Tests of reference/feedback_twin (CPU tier, no GL): the mirror's traces leave its image unchanged and end
// where the mirror ended; with zero tolerance the sure and possible sets agree; a sphere's isosurface hides
// the leaves behind it; a coarse cut is requested near the eye and not far from it; pixels(L) is the formula
// of docs/RENDERING.md "Feedback".
#include "reference/feedback_twin.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "index/cut.h"
#include "index/rope_index.h"
#include "store/procedural_bricks.h"

namespace ropecast {
namespace {

// A cut of Data leaves over the inside nodes where `isLeaf` says (always at the finest depth), completed with
// Empty leaves.
Cut cutWhere(const OctreeLayout& layout, const std::function<bool(const NodeKey&)>& isLeaf) {
  std::vector<CutLeaf> leaves;
  uint32_t slot = 0;
  std::function<void(const NodeKey&)> visit = [&](const NodeKey& k) {
    if (!layout.isInside(k)) return;
    if (k.depth == layout.maxDepth || isLeaf(k)) {
      leaves.push_back({k.depth, k.coord, LeafKind::Data, slot++});
      return;
    }
    for (uint32_t o = 0; o < 8; ++o) visit(k.child(o));
  };
  visit({0, {0, 0, 0}});
  return completeCut(leaves);
}

// Data leaves at depth `depth`.
Cut cutAtDepth(const OctreeLayout& layout, uint32_t depth) {
  return cutWhere(layout, [depth](const NodeKey& k) { return k.depth == depth; });
}

CpuRenderInput sphereInput(double distance, uint32_t size) {
  CpuRenderInput in;
  in.camera = orbitCamera(30.0, 20.0, distance, glm::dvec3(0.0), glm::dvec3(64.0), 30.0);
  in.width = in.height = size;
  in.params.mode = RenderMode::Iso;
  in.params.isoValue = 127.5;
  return in;
}

TEST(FeedbackTwin, VoxelPixelsIsTheProjectedSizeOfOneVoxel) {
  // 2^2 voxels of max spacing 2 at distance 50 under a 60 degree field of view, 100 pixels high.
  const double expected = 4.0 * 2.0 / (2.0 * 50.0 * std::tan(std::numbers::pi / 6.0)) * 100.0;
  EXPECT_NEAR(feedbackVoxelPixels(2, 50.0, {1.0, 2.0, 0.5}, 60.0, 100), expected, 1e-12);
  // The distance is clamped below at half the smallest spacing.
  EXPECT_EQ(feedbackVoxelPixels(1, 0.0, {1.0, 2.0, 0.5}, 60.0, 100),
            feedbackVoxelPixels(1, 0.25, {1.0, 2.0, 0.5}, 60.0, 100));
}

// At a step of 2.5 voxels, leaves whose last sample lies more than a texel before their end take one more
// sample there (docs/RENDERING.md "Isosurface"), which may be the one that ends the ray.
TEST(FeedbackTwin, TracesLeaveTheImageUnchangedAndEndWhereTheMirrorEnded) {
  const ProceduralBricks src({ProceduralKind::Sphere, 64}, 16);
  const Cut cut = cutAtDepth(src.info().layout, 1);
  const RopeIndex index = buildRopeIndex(cut);
  const BricksBySlot bricks = readCutBricks(cut, src);
  for (const double step : {0.5, 2.5}) {
    CpuRenderInput in = sphereInput(2.0, 48);
    in.params.stepVoxels = step;
    const CpuImage plain = renderMirror(index, bricks, src.info(), in);
    std::vector<MirrorRayTrace> traces;
    const CpuImage traced = renderMirror(index, bricks, src.info(), in, &traces);
    ASSERT_EQ(plain.rgba.size(), traced.rgba.size());
    EXPECT_EQ(std::memcmp(plain.rgba.data(), traced.rgba.data(), plain.rgba.size() * sizeof(float)), 0);
    ASSERT_EQ(traces.size(), size_t(48) * 48);
    size_t hits = 0, leafEndSamples = 0, endsAtLeafEnd = 0;
    for (size_t i = 0; i < traces.size(); ++i) {
      const MirrorRayTrace& t = traces[i];
      const bool hit = plain.rgba[4 * i + 3] > 0.5f;
      EXPECT_EQ(t.endLeaf < t.leaves.size(), hit) << "pixel " << i;
      if (!hit) continue;
      ++hits;
      endsAtLeafEnd += t.leaves[t.endLeaf].samples[t.endSample].atLeafEnd;
      // The end sample is the first whose side of the isosurface differs from the previous sample's, among
      // those the mirror took.
      std::vector<MirrorSample> samples;
      for (size_t v = 0; v <= t.endLeaf; ++v) {
        const auto& leafSamples = t.leaves[v].samples;
        const size_t count = v == t.endLeaf ? t.endSample + 1 : leafSamples.size();
        for (size_t j = 0; j < count; ++j) {
          if (leafSamples[j].atLeafEnd) {
            EXPECT_EQ(j + 1, leafSamples.size()) << "pixel " << i << ": the leaf's end sample comes last";
          }
          if (leafSamples[j].atLeafEnd && !leafSamples[j].leafEndTaken) continue;
          leafEndSamples += leafSamples[j].atLeafEnd;
          samples.push_back(leafSamples[j]);
        }
      }
      ASSERT_GE(samples.size(), 2u);
      for (size_t j = 1; j + 1 < samples.size(); ++j)
        EXPECT_EQ(samples[j].f >= 0.0, samples[0].f >= 0.0) << "pixel " << i;
      EXPECT_NE(samples.back().f >= 0.0, samples[0].f >= 0.0) << "pixel " << i;
    }
    EXPECT_GT(hits, 500u);
    if (step > 1.0) {
      EXPECT_GT(leafEndSamples, 0u);
      EXPECT_GT(endsAtLeafEnd, 0u);  // some rays find the surface only at a leaf's end
    } else {
      EXPECT_EQ(leafEndSamples, 0u);
    }
  }
}

// Data leaves at random depths (the same for a seed).
Cut randomCut(const OctreeLayout& layout, uint32_t seed) {
  return cutWhere(layout, [seed](const NodeKey& k) {
    const uint32_t h = (k.coord.x * 73856093u) ^ (k.coord.y * 19349663u) ^ (k.coord.z * 83492791u) ^
                       (k.depth * 2654435761u) ^ (seed * 40503u);
    return k.depth > 0 && h % 3 == 0;
  });
}

bool isSubset(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b) {
  return std::includes(b.begin(), b.end(), a.begin(), a.end());
}

// At steps above a voxel, leaves take samples at their ends, and within the tolerance of a texel the shader
// may decide otherwise: the bounds must still hold the mirror's own sets, on cuts of mixed levels from
// several cameras.
TEST(FeedbackTwin, BoundsHoldTheExactSetsWithSamplesAtLeafEnds) {
  const ProceduralBricks src({ProceduralKind::Sphere, 64}, 8);
  const FeedbackTolerance tol{1e-4, 1e-4, 1e-3};  // generous, so that many decisions are open
  size_t uncertain = 0;
  for (uint32_t seed : {1u, 2u, 3u}) {
    const Cut cut = randomCut(src.info().layout, seed);
    const RopeIndex index = buildRopeIndex(cut);
    const BricksBySlot bricks = readCutBricks(cut, src);
    for (const double step : {1.7, 2.5, 4.0}) {
      CpuRenderInput in = sphereInput(1.3 + 0.4 * seed, 40);
      in.camera = orbitCamera(30.0 + 50.0 * seed, 20.0 - 15.0 * seed, 1.3 + 0.4 * seed, glm::dvec3(0.0),
                              glm::dvec3(64.0), 30.0);
      in.params.stepVoxels = step;
      const FeedbackBounds exact = mirrorFeedback(index, bricks, src.info(), in, 1.0);
      const FeedbackBounds bounds = mirrorFeedback(index, bricks, src.info(), in, 1.0, tol);
      const std::string what = "seed " + std::to_string(seed) + ", step " + std::to_string(step);
      EXPECT_EQ(exact.sure.usedLeaves, exact.possible.usedLeaves) << what;
      EXPECT_TRUE(isSubset(bounds.sure.usedLeaves, exact.sure.usedLeaves)) << what;
      EXPECT_TRUE(isSubset(exact.sure.usedLeaves, bounds.possible.usedLeaves)) << what;
      EXPECT_TRUE(isSubset(bounds.sure.requestedLeaves, exact.sure.requestedLeaves)) << what;
      EXPECT_TRUE(isSubset(exact.sure.requestedLeaves, bounds.possible.requestedLeaves)) << what;
      EXPECT_FALSE(exact.sure.usedLeaves.empty()) << what;
      uncertain += bounds.uncertainRays;
    }
  }
  EXPECT_GT(uncertain, 0u);  // the tolerance left decisions open
}

// Hand-made traces of one ray over three leaves of level 0 of the sphere, on the grid t = 10 + 5k: the first
// [10, 29) with samples at 10, 15, 20 and 25, the second [29, 29.8) crossed between two grid samples, the
// third [29.8, 60) with the crossing at its first sample, 30.
struct HandTrace {
  ProceduralBricks src{{ProceduralKind::Sphere, 64}, 16};
  CpuRenderInput input = sphereInput(2.0, 8);
  MirrorRayTrace trace;

  HandTrace() {
    trace.entered = true;
    trace.t0 = 10.0;
    trace.t1 = 100.0;
    const double bounds[4] = {10.0, 29.0, 29.8, 60.0};
    const double kBegin[3] = {0.0, 4.0, 4.0};
    for (uint32_t i = 0; i < 3; ++i) {
      MirrorLeafVisit& l = trace.leaves.emplace_back();
      l.leafIndex = i;
      l.depth = src.info().layout.maxDepth;
      l.tEnter = bounds[i];
      l.tExit = bounds[i + 1];
      l.firstLeaf = i == 0;
      l.dt = 5.0;
      l.kBegin = kBegin[i];
    }
    trace.leaves[0].samples = {grid(10.0, -0.3), grid(15.0, -0.3), grid(20.0, -0.3), grid(25.0, -0.3)};
    trace.leaves[2].samples = {grid(30.0, 0.1)};
    trace.endLeaf = 2;
    trace.endSample = 0;
  }
  static MirrorSample grid(double t, double f) { return {t, f}; }
  static MirrorSample leafEnd(double t, double f, bool taken, double gapTexels) {
    return {.t = t, .f = f, .atLeafEnd = true, .leafEndTaken = taken, .leafEndGapTexels = gapTexels};
  }
  FeedbackBounds bounds(const FeedbackTolerance& tol) const {
    return feedbackOfTraces({trace}, src.info(), input, 1e-6, tol);
  }
};

TEST(FeedbackTwin, ALeafSampledOnlyAtItsEndWithinRoundingOfATexelMayBeUsed) {
  HandTrace h;
  // The second leaf takes only the sample at its end, which the mirror took 1.00001 texels from the previous
  // sample: the shader may not take it.
  h.trace.leaves[1].samples = {HandTrace::leafEnd(29.8, -0.2, true, 1.00001)};
  const FeedbackBounds exact = h.bounds({});
  EXPECT_EQ(exact.sure.usedLeaves, (std::vector<uint32_t>{0, 1, 2}));
  const FeedbackBounds loose = h.bounds({0.0, 0.0, 1e-3});
  EXPECT_EQ(loose.sure.usedLeaves, (std::vector<uint32_t>{0}));
  EXPECT_EQ(loose.possible.usedLeaves, (std::vector<uint32_t>{0, 1, 2}));
}

TEST(FeedbackTwin, AnOpenLeafEndDecisionLeavesTheNextLeafsEndOpen) {
  HandTrace h;
  // The first leaf's end sample is not taken by the mirror, 0.99999 texels from its last sample: a shader
  // that takes it measures the second leaf from there, where the mirror (measuring from 25) took nothing.
  h.trace.leaves[0].samples.push_back(HandTrace::leafEnd(29.0, -0.3, false, 0.99999));
  const FeedbackBounds exact = h.bounds({});
  EXPECT_EQ(exact.sure.usedLeaves, (std::vector<uint32_t>{0, 2}));
  const FeedbackBounds loose = h.bounds({0.0, 0.0, 1e-3});
  EXPECT_EQ(loose.sure.usedLeaves, (std::vector<uint32_t>{0}));
  EXPECT_EQ(loose.possible.usedLeaves, (std::vector<uint32_t>{0, 1, 2}));
}

TEST(FeedbackTwin, TheSphereHidesTheLeavesBehindItAndNearLeavesAreRequested) {
  const ProceduralBricks src({ProceduralKind::Sphere, 64}, 16);
  const Cut cut = cutAtDepth(src.info().layout, 1);  // level 1: 8 leaves
  const RopeIndex index = buildRopeIndex(cut);
  const BricksBySlot bricks = readCutBricks(cut, src);
  const CpuRenderInput near = sphereInput(1.2, 48);
  // One level-1 voxel at distance ~70 covers 2 / (2 70 tan 15deg) 48 = 2.6 pixels.
  const FeedbackBounds wanted = mirrorFeedback(index, bricks, src.info(), near, 1.0);
  EXPECT_EQ(wanted.sure.usedLeaves, wanted.possible.usedLeaves);
  EXPECT_EQ(wanted.sure.requestedLeaves, wanted.possible.requestedLeaves);
  EXPECT_EQ(wanted.uncertainRays, 0u);
  // The leaf farthest from the eye (the octant at the far corner) lies behind the sphere for every ray.
  const glm::dvec3 eye = near.camera.eye;
  const glm::u32vec3 far(eye.x < 32 ? 1 : 0, eye.y < 32 ? 1 : 0, eye.z < 32 ? 1 : 0);
  uint32_t farLeaf = 0;
  for (uint32_t i = 0; i < cut.leaves.size(); ++i)
    if (cut.leaves[i].depth == 1 && cut.leaves[i].coord == far) farLeaf = i;
  EXPECT_FALSE(std::binary_search(wanted.sure.usedLeaves.begin(), wanted.sure.usedLeaves.end(), farLeaf));
  EXPECT_FALSE(wanted.sure.requestedLeaves.empty());
  EXPECT_TRUE(std::includes(wanted.sure.usedLeaves.begin(), wanted.sure.usedLeaves.end(),
                            wanted.sure.requestedLeaves.begin(), wanted.sure.requestedLeaves.end()));
  // A tenth of a voxel per pixel is met everywhere: nothing requested, the same leaves used.
  const FeedbackBounds enough = mirrorFeedback(index, bricks, src.info(), near, 0.1);
  EXPECT_TRUE(enough.sure.requestedLeaves.empty());
  EXPECT_EQ(enough.sure.usedLeaves, wanted.sure.usedLeaves);
  // Level 0 is never requested.
  const Cut fine = cutAtDepth(src.info().layout, src.info().layout.maxDepth);
  EXPECT_TRUE(mirrorFeedback(buildRopeIndex(fine), readCutBricks(fine, src), src.info(), near, 100.0)
                  .possible.requestedLeaves.empty());
}

}  // namespace
}  // namespace ropecast
