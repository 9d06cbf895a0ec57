// Property tests of the stackless traversal: for random cuts and thousands of rays of each kind, ropeNextLeaf
// hands out exactly the leaves a brute-force clip of every leaf box finds, front to back, none twice,
// chained.
//
// "Visited" for the brute force: a leaf counts when the ray's interval in its box, clipped to [tStart, tEnd],
// has positive length in float (hi > lo), with each plane's t computed by the same rounding formula
// (plane - origin) * (1/dir) the traversal uses, and with half-open boxes on axes where dir is 0 (closed at
// the root's top face). With that one formula the positive intervals partition the ray, so the comparison is
// exact: same leaves, same order, bit-identical tEnter/tExit. An extra double-precision check keeps both
// honest: the middle of every reported interval that is not tiny lies in its box.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string_view>
#include <vector>

#include <glm/common.hpp>
#include <glm/vector_relational.hpp>

#include "index/cut.h"
#include "index/random_cut.h"
#include "index/rope_index.h"
#include "index/rope_traversal.h"

namespace ropecast {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

struct Ray {
  glm::vec3 origin;
  glm::vec3 dir;
  float tStart;
  float tEnd;
};

struct Hit {
  uint32_t leaf;
  float tEnter;
  float tExit;
};

std::vector<Hit> bruteForce(const Cut& cut, const Ray& ray) {
  glm::vec3 inv;
  for (int a = 0; a < 3; ++a) {
    inv[a] = 1.0f / ray.dir[a];
    if (!std::isfinite(inv[a])) inv[a] = 0.0f;
  }
  std::vector<Hit> hits;
  for (uint32_t i = 0; i < cut.leaves.size(); ++i) {
    const CutLeaf& leaf = cut.leaves[i];
    const float size = std::ldexp(1.0f, -int(leaf.depth));
    float lo = ray.tStart, hi = ray.tEnd;
    bool inside = true;
    for (int a = 0; a < 3; ++a) {
      const float boxMin = float(leaf.coord[a]) * size, boxMax = boxMin + size;
      const float o = ray.origin[a];
      if (inv[a] == 0.0f) {
        inside = inside && ((boxMin <= o && o < boxMax) || (boxMax == 1.0f && o == 1.0f));
        continue;
      }
      const float t0 = (boxMin - o) * inv[a], t1 = (boxMax - o) * inv[a];
      lo = std::max(lo, inv[a] > 0 ? t0 : t1);
      hi = std::min(hi, inv[a] > 0 ? t1 : t0);
    }
    if (inside && hi > lo) hits.push_back({i, lo, hi});
  }
  std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) { return a.tEnter < b.tEnter; });
  return hits;
}

std::vector<RopeLeaf> traverse(const RopeIndex& index, const Ray& ray) {
  std::vector<RopeLeaf> leaves;
  RopeCursor cursor;
  if (!ropeBegin(cursor, index, ray.origin, ray.dir, ray.tStart, ray.tEnd)) return leaves;
  RopeLeaf leaf;
  while (ropeNextLeaf(cursor, index, leaf)) {
    leaves.push_back(leaf);
    if (leaves.size() > 100000) break;  // a loop: fail below rather than hang
  }
  return leaves;
}

// Compares one ray; returns false (with a gtest failure naming the ray) on the first difference.
bool checkRay(const Cut& cut, const RopeIndex& index, const Ray& ray, const char* kind) {
  const std::vector<Hit> expected = bruteForce(cut, ray);
  const std::vector<RopeLeaf> got = traverse(index, ray);
  auto where = [&] {
    return testing::Message() << kind << " ray origin (" << ray.origin.x << "," << ray.origin.y << ","
                              << ray.origin.z << ") dir (" << ray.dir.x << "," << ray.dir.y << ","
                              << ray.dir.z << ") t [" << ray.tStart << "," << ray.tEnd << "]";
  };
  if (got.size() != expected.size()) {
    ADD_FAILURE() << where() << ": traversal visits " << got.size() << " leaves, brute force "
                  << expected.size();
    return false;
  }
  for (size_t i = 0; i < got.size(); ++i) {
    const RopeLeaf& g = got[i];
    const Hit& e = expected[i];
    const CutLeaf& leaf = cut.leaves[e.leaf];
    const float size = std::ldexp(1.0f, -int(leaf.depth));
    const bool same = g.leafIndex == e.leaf && g.tEnter == e.tEnter && g.tExit == e.tExit &&
                      g.depth == leaf.depth && g.boxSize == size &&
                      g.boxMin == glm::vec3(leaf.coord) * size &&
                      g.kind == (leaf.kind == LeafKind::Data ? kRopeTagDataLeaf : kRopeTagEmptyLeaf) &&
                      (leaf.kind == LeafKind::Empty || g.brickSlot == leaf.brickSlot);
    if (!same) {
      ADD_FAILURE() << where() << ": step " << i << " visits leaf " << g.leafIndex << " [" << g.tEnter << ","
                    << g.tExit << ") depth " << g.depth << ", brute force leaf " << e.leaf << " [" << e.tEnter
                    << "," << e.tExit << ")";
      return false;
    }
    if (!(g.tExit > g.tEnter) || (i > 0 && got[i - 1].tExit != g.tEnter)) {
      ADD_FAILURE() << where() << ": step " << i << " breaks the [tEnter, tExit) chain";
      return false;
    }
    // Geometry in double: the middle of a non-tiny interval lies in the box.
    const double tMid = 0.5 * (double(g.tEnter) + double(g.tExit));
    if (double(g.tExit) - double(g.tEnter) > 1e-4 * (1.0 + std::abs(tMid)) && std::isfinite(tMid)) {
      for (int a = 0; a < 3; ++a) {
        const double p = double(ray.origin[a]) + tMid * double(ray.dir[a]);
        if (p < double(g.boxMin[a]) - 1e-5 || p > double(g.boxMin[a]) + double(g.boxSize) + 1e-5) {
          ADD_FAILURE() << where() << ": step " << i << " middle point axis " << a << " = " << p
                        << " outside its box";
          return false;
        }
      }
    }
  }
  return true;
}

// Ray generators, one per kind the traversal must survive.
struct RayMaker {
  std::mt19937_64 rng;
  uint32_t maxDepth;

  float uniform(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); }
  glm::vec3 uniform3(float lo, float hi) { return {uniform(lo, hi), uniform(lo, hi), uniform(lo, hi)}; }
  glm::vec3 direction() {
    std::normal_distribution<float> n;
    glm::vec3 d(n(rng), n(rng), n(rng));
    return d * uniform(0.2f, 5.0f);  // not normalized on purpose
  }
  // A coordinate on the grid of some depth <= maxDepth: exactly on faces and edges of the leaves.
  float gridCoord() {
    const uint32_t depth = std::uniform_int_distribution<uint32_t>(0, maxDepth)(rng);
    const uint32_t k = std::uniform_int_distribution<uint32_t>(0, 1u << depth)(rng);
    return std::ldexp(float(k), -int(depth));
  }
  glm::vec3 gridPoint() { return {gridCoord(), gridCoord(), gridCoord()}; }

  Ray outsideIn() {  // from outside, aimed at a point in the cube
    const glm::vec3 o = uniform3(-1.0f, 2.0f), target = uniform3(0.0f, 1.0f);
    return {o, (target - o) * uniform(0.3f, 3.0f), 0.0f, kInf};
  }
  Ray startsInside() { return {uniform3(0.0f, 1.0f), direction(), 0.0f, kInf}; }
  Ray endsInside() {  // tEnd inside the cube, tStart before it
    const glm::vec3 o = uniform3(-0.5f, 1.5f), target = uniform3(0.0f, 1.0f);
    return {o, target - o, uniform(-1.0f, 0.2f), uniform(0.3f, 1.0f)};
  }
  Ray axisParallel() {  // one or two components exactly 0; the fixed coordinates often exactly on faces
    Ray r = startsInside();
    r.origin = uniform3(-0.2f, 1.2f);
    r.tStart = -kInf;
    const uint32_t zeros = std::uniform_int_distribution<uint32_t>(1, 2)(rng);
    const uint32_t first = std::uniform_int_distribution<uint32_t>(0, 2)(rng);
    for (uint32_t k = 0; k < zeros; ++k) {
      const uint32_t a = (first + k) % 3;
      r.dir[a] = rng() % 2 ? 0.0f : -0.0f;
      if (rng() % 2) r.origin[a] = gridCoord();
    }
    return r;
  }
  Ray throughEdges() {  // from one grid point to another: crosses faces exactly at edges and corners
    const glm::vec3 a = gridPoint(), b = gridPoint();
    if (a == b) return startsInside();
    return {a, b - a, uniform(-3.0f, 0.0f), rng() % 2 ? kInf : 1.0f};
  }
  Ray grazingFace() {  // lies in a face plane of the grid, or of the root cube
    Ray r = throughEdges();
    const uint32_t a = std::uniform_int_distribution<uint32_t>(0, 2)(rng);
    r.dir[a] = 0.0f;
    if (rng() % 4 == 0) r.origin[a] = rng() % 2 ? 0.0f : 1.0f;
    return r;
  }
  Ray misses() {  // outside and pointing away, or parallel outside a face
    Ray r = startsInside();
    r.origin = uniform3(1.5f, 3.0f);
    r.dir = glm::abs(direction());
    if (rng() % 2) r.dir.x = 0.0f;
    return r;
  }
};

struct Case {
  const char* name;
  Ray (RayMaker::*make)();
};
const Case kRayKinds[] = {
    {"outside-in", &RayMaker::outsideIn},
    {"inside", &RayMaker::startsInside},
    {"ends-inside", &RayMaker::endsInside},
    {"axis-parallel", &RayMaker::axisParallel},
    {"through-edges", &RayMaker::throughEdges},
    {"grazing-face", &RayMaker::grazingFace},
    {"misses", &RayMaker::misses},
};

// Runs `raysPerKind` rays of every kind; returns the number of leaves visited in all.
size_t runRays(const Cut& cut, uint32_t maxDepth, uint64_t seed, int raysPerKind) {
  const RopeIndex index = buildRopeIndex(cut);
  RayMaker maker{std::mt19937_64(seed), maxDepth};
  size_t visited = 0;
  for (const Case& kind : kRayKinds) {
    int raysThatHit = 0;
    for (int i = 0; i < raysPerKind; ++i) {
      const Ray ray = (maker.*kind.make)();
      if (!checkRay(cut, index, ray, kind.name)) return visited;
      const size_t hits = bruteForce(cut, ray).size();
      visited += hits;
      raysThatHit += hits > 0;
    }
    // Each generator makes the rays it claims to: the misses miss, the others mostly hit.
    if (std::string_view(kind.name) == "misses")
      EXPECT_EQ(raysThatHit, 0);
    else
      EXPECT_GT(raysThatHit, raysPerKind / 2) << kind.name;
  }
  return visited;
}

TEST(RopeTraversal, RandomCutsMatchBruteForce) {
  size_t visited = 0;
  for (uint64_t seed = 1; seed <= 24; ++seed) {
    RandomCutParams params;
    params.seed = seed;
    params.targetLeaves = std::array<uint32_t, 6>{1, 8, 60, 300, 800, 1500}[seed % 6];
    params.maxDepth = 1 + uint32_t(seed % 8);
    params.emptyFraction = seed % 3 == 0 ? 0.0f : 0.4f;
    const Cut cut = makeRandomCut(params);
    SCOPED_TRACE(testing::Message() << "cut seed " << seed << ", " << cut.leaves.size() << " leaves");
    visited += runRays(cut, params.maxDepth, seed * 7919, 1000);
    if (HasFailure()) return;
  }
  EXPECT_GT(visited, 300000u);  // the rays really cross many leaves
}

// Leaves down to depth 20 beside depth-1 neighbors: ropes to much coarser nodes, and boxes 2^-20 wide where
// an epsilon-based point location would fail.
TEST(RopeTraversal, DeepCutsMatchBruteForce) {
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    std::mt19937_64 rng(seed);
    std::vector<CutLeaf> deep;
    const uint32_t maxDepth = seed <= 3 ? 12 : kCutMaxDepth;
    // A few deep leaves near one corner (so they share ancestors), one elsewhere.
    for (int i = 0; i < 4; ++i) {
      CutLeaf leaf;
      leaf.depth = maxDepth - uint32_t(i % 2);
      const uint32_t side = 1u << leaf.depth;
      const uint32_t near = (side / 2) + uint32_t(rng() % 3);
      leaf.coord = glm::u32vec3(near, near - uint32_t(rng() % 2), near + uint32_t(i));
      leaf.kind = LeafKind::Data;
      leaf.brickSlot = uint32_t(i);
      deep.push_back(leaf);
    }
    // Drop duplicates/overlaps of the random picks before completing.
    std::vector<CutLeaf> distinct;
    for (const CutLeaf& leaf : deep) {
      bool overlaps = false;
      for (const CutLeaf& other : distinct) {
        const uint32_t d = std::min(leaf.depth, other.depth);
        overlaps = overlaps || (leaf.coord >> (leaf.depth - d)) == (other.coord >> (other.depth - d));
      }
      if (!overlaps) distinct.push_back(leaf);
    }
    const Cut cut = completeCut(distinct);
    SCOPED_TRACE(testing::Message() << "deep cut seed " << seed << ", " << cut.leaves.size() << " leaves");
    EXPECT_GT(cut.leaves.size(), 7u * (maxDepth - 1));
    runRays(cut, maxDepth, seed, 600);
    // Rays aimed at the deep corner cross the tiny leaves.
    const RopeIndex index = buildRopeIndex(cut);
    RayMaker maker{std::mt19937_64(seed + 100), maxDepth};
    const glm::vec3 corner = glm::vec3(distinct[0].coord) * std::ldexp(1.0f, -int(distinct[0].depth));
    for (int i = 0; i < 500 && !HasFailure(); ++i) {
      const glm::vec3 o = maker.uniform3(-1.0f, 2.0f);
      const glm::vec3 jitter = maker.uniform3(-1.0f, 1.0f) * std::ldexp(1.0f, -int(maxDepth) + 2);
      checkRay(cut, index, {o, corner + jitter - o, -kInf, kInf}, "deep-corner");
    }
    if (HasFailure()) return;
  }
}

TEST(RopeTraversal, SingleLeafRootAndMisses) {
  const Cut cut = completeCut({});
  const RopeIndex index = buildRopeIndex(cut);
  RopeCursor cursor;
  RopeLeaf leaf;
  ASSERT_TRUE(ropeBegin(cursor, index, {-1.0f, 0.5f, 0.5f}, {1.0f, 0.0f, 0.0f}, 0.0f, kInf));
  ASSERT_TRUE(ropeNextLeaf(cursor, index, leaf));
  EXPECT_EQ(leaf.tEnter, 1.0f);
  EXPECT_EQ(leaf.tExit, 2.0f);
  EXPECT_EQ(leaf.depth, 0u);
  EXPECT_EQ(leaf.kind, kRopeTagEmptyLeaf);
  EXPECT_FALSE(ropeNextLeaf(cursor, index, leaf));
  EXPECT_FALSE(ropeNextLeaf(cursor, index, leaf));  // stays done
  // Misses: pointing away, parallel outside, touching only an edge, interval ending before the cube.
  EXPECT_FALSE(ropeBegin(cursor, index, {-1.0f, 0.5f, 0.5f}, {-1.0f, 0.0f, 0.0f}, 0.0f, kInf));
  EXPECT_FALSE(ropeBegin(cursor, index, {-1.0f, 1.5f, 0.5f}, {1.0f, 0.0f, 0.0f}, 0.0f, kInf));
  EXPECT_FALSE(ropeBegin(cursor, index, {-1.0f, 0.0f, 1.0f}, {1.0f, 1.0f, -1.0f}, 0.0f, kInf));
  EXPECT_FALSE(ropeBegin(cursor, index, {-1.0f, 0.5f, 0.5f}, {1.0f, 0.0f, 0.0f}, 0.0f, 0.5f));
}

// A ray along the shared face x = 0.5 of two leaves goes to the high side (half-open boxes), and a ray
// through the center point of 8 leaves visits only the two it really crosses.
TEST(RopeTraversal, SharedFacesAndCorners) {
  std::vector<CutLeaf> leaves;
  for (uint32_t octant = 0; octant < 8; ++octant)
    leaves.push_back({1, {octant & 1u, (octant >> 1) & 1u, (octant >> 2) & 1u}, LeafKind::Data, octant});
  const Cut cut{leaves};
  const RopeIndex index = buildRopeIndex(cut);
  auto visits = [&](glm::vec3 o, glm::vec3 d) {
    std::vector<uint32_t> slots;
    for (const RopeLeaf& leaf : traverse(index, {o, d, -kInf, kInf})) slots.push_back(leaf.brickSlot);
    return slots;
  };
  EXPECT_EQ(visits({0.5f, 0.25f, -1.0f}, {0.0f, 0.0f, 1.0f}), (std::vector<uint32_t>{1, 5}));
  EXPECT_EQ(visits({0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}), (std::vector<uint32_t>{0, 7}));
  EXPECT_EQ(visits({1.0f, 1.0f, 1.0f}, {-1.0f, -1.0f, -1.0f}), (std::vector<uint32_t>{7, 0}));
  EXPECT_EQ(visits({1.0f, 0.75f, 0.75f}, {0.0f, 0.0f, -1.0f}), (std::vector<uint32_t>{7, 3}));  // top face
}

// The property test can fail: cutting one rope ends the rays that cross that face early.
TEST(RopeTraversal, BrokenRopeIsDetected) {
  RandomCutParams params;
  params.targetLeaves = 300;
  params.maxDepth = 5;
  const Cut cut = makeRandomCut(params);
  RopeIndex index = buildRopeIndex(cut);
  const uint32_t node = index.leafNodeTexel[0];
  const uint32_t block = index.texels[node][kRopeNodePointer];
  for (uint32_t face = 0; face < kRopeFaceCount; ++face)
    index.texels[ropeFaceTexel(block, face)][ropeFaceComponent(face)] = kRopeNull;
  const float size = std::ldexp(1.0f, -int(cut.leaves[0].depth));
  const glm::vec3 center = (glm::vec3(cut.leaves[0].coord) + 0.5f) * size;
  int mismatches = 0;
  for (int axis = 0; axis < 3; ++axis) {
    glm::vec3 dir(0.1f, 0.2f, 0.3f);
    dir[axis] = 1.0f;
    const Ray ray{center - 2.0f * dir, dir, -kInf, kInf};
    const std::vector<Hit> expected = bruteForce(cut, ray);
    const std::vector<RopeLeaf> got = traverse(index, ray);
    mismatches += got.size() != expected.size();
  }
  EXPECT_GT(mismatches, 0);
}

}  // namespace
}  // namespace ropecast
