// Tests of store/procedural_bricks: node ranges are conservative for the node and its descendants, bricks
// are the field point-sampled at the level's sample centers, borders equal the neighbors' interiors and
// replicate the volume edge, large sizes work without generating data, and concurrent reads agree.
#include "store/procedural_bricks.h"

#include <chrono>
#include <cmath>
#include <random>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "core/elapsed.h"
#include "core/error.h"

namespace ropecast {
namespace {

std::vector<uint8_t> readBrick(const ProceduralBricks& src, const NodeKey& key) {
  std::vector<uint8_t> brick(src.brickBytes());
  src.readBrick(key, std::as_writable_bytes(std::span(brick)));
  return brick;
}

// The brick as the docs of ProceduralBricks state it, restated independently of the implementation.
std::vector<uint8_t> expectedBrick(const ProceduralBricks& src, const NodeKey& key) {
  const OctreeLayout& l = src.info().layout;
  const uint32_t e = l.storedBrickEdge(), level = l.levelOfDepth(key.depth);
  const glm::u32vec3 dims = l.levelDims(level);
  std::vector<uint8_t> out(size_t(e) * e * e);
  for (uint32_t z = 0; z < e; ++z)
    for (uint32_t y = 0; y < e; ++y)
      for (uint32_t x = 0; x < e; ++x) {
        glm::dvec3 p;
        const glm::u32vec3 t(x, y, z);
        for (int a = 0; a < 3; ++a) {
          const int64_t g = int64_t(key.coord[a]) * l.brickSize + t[a] - int64_t(kBrickBorder);
          p[a] = (double(std::clamp<int64_t>(g, 0, dims[a] - 1)) + 0.5) * double(1u << level);
        }
        const double v = proceduralValue(src.field(), p);
        out[x + e * (y + size_t(e) * z)] = uint8_t(std::clamp(std::lround(v), 0l, 255l));
      }
  return out;
}

class ProceduralBricksAllKinds : public ::testing::TestWithParam<ProceduralKind> {};

TEST_P(ProceduralBricksAllKinds, RangesAreConservativeAndBricksAreThePointSampledField) {
  // 90^3 with 8-samples bricks: 12 bricks per axis at level 0, maxDepth 4, edges that do not divide evenly.
  const ProceduralBricks src({GetParam(), 90}, 8);
  const OctreeLayout& l = src.info().layout;
  ASSERT_EQ(l.maxDepth, 4u);
  std::mt19937 rng(7);
  int dataNodes = 0, constantNodes = 0;
  for (uint32_t depth = 0; depth <= l.maxDepth; ++depth) {
    const glm::u32vec3 n = l.insideNodes(depth);
    for (int trial = 0; trial < 40; ++trial) {
      const NodeKey key{depth, {rng() % n.x, rng() % n.y, rng() % n.z}};
      const NodeInfo info = src.node(key);
      ASSERT_NE(info.kind, NodeKind::Outside);
      const std::vector<uint8_t> expected = expectedBrick(src, key);
      if (info.kind == NodeKind::Data) {
        ++dataNodes;
        ASSERT_EQ(readBrick(src, key), expected) << "depth " << depth;
      } else {
        ++constantNodes;
        EXPECT_EQ(info.minValue, info.maxValue);
      }
      // Conservative for the node and for each ancestor (min/max cover all descendants).
      for (NodeKey k = key;; k = k.parent()) {
        const NodeInfo a = src.node(k);
        for (uint8_t v : expected) {
          ASSERT_GE(v, a.minValue) << "depth " << key.depth << " in ancestor at depth " << k.depth;
          ASSERT_LE(v, a.maxValue) << "depth " << key.depth << " in ancestor at depth " << k.depth;
        }
        if (k.depth == 0) break;
      }
    }
  }
  EXPECT_GT(dataNodes, 0);
  // Outside nodes report Outside and read as zeros.
  const NodeKey outside{l.maxDepth, {l.insideNodes(l.maxDepth).x, 0, 0}};
  EXPECT_EQ(src.node(outside).kind, NodeKind::Outside);
  const auto zeros = readBrick(src, outside);
  EXPECT_TRUE(std::all_of(zeros.begin(), zeros.end(), [](uint8_t v) { return v == 0; }));
}

INSTANTIATE_TEST_SUITE_P(Kinds, ProceduralBricksAllKinds,
                         ::testing::Values(ProceduralKind::Sphere, ProceduralKind::Menger,
                                           ProceduralKind::Noise, ProceduralKind::MarschnerLobb),
                         [](const auto& info) {
                           std::string name(proceduralKindName(info.param));
                           std::erase(name, '-');
                           return name;
                         });

TEST(ProceduralBricks, LevelZeroBricksHoldTheProceduralSamples) {
  const ProceduralBricks src({ProceduralKind::Noise, 40}, 16);
  const NodeKey key{src.info().layout.maxDepth, {1, 2, 0}};
  const auto brick = readBrick(src, key);
  const uint32_t e = src.info().layout.storedBrickEdge();
  for (uint32_t z = kBrickBorder; z < e - kBrickBorder; ++z)
    for (uint32_t y = kBrickBorder; y < e - kBrickBorder; ++y)
      for (uint32_t x = kBrickBorder; x < e - kBrickBorder; ++x) {
        const uint32_t i = 16 + x - kBrickBorder, j = 32 + y - kBrickBorder, k = z - kBrickBorder;
        if (j >= 40) continue;  // beyond the volume: edge replication, checked elsewhere
        ASSERT_EQ(brick[x + e * (y + e * z)], proceduralSample(src.field(), i, j, k));
      }
}

TEST(ProceduralBricks, BordersEqualNeighborsAndReplicateTheVolumeEdge) {
  const ProceduralBricks src({ProceduralKind::MarschnerLobb, 50}, 8);  // 7 bricks per axis, last one partial
  const OctreeLayout& l = src.info().layout;
  const uint32_t e = l.storedBrickEdge(), b = l.brickSize, border = kBrickBorder;
  for (uint32_t depth : {l.maxDepth, l.maxDepth - 1}) {
    const glm::u32vec3 n = l.insideNodes(depth);
    for (int axis = 0; axis < 3; ++axis) {
      for (uint32_t c = 0; c + 1 < n[axis]; ++c) {
        NodeKey a{depth, {1, 0, 1}}, nb{depth, {1, 0, 1}};
        a.coord[axis] = c;
        nb.coord[axis] = c + 1;
        const auto ba = readBrick(src, a), bb = readBrick(src, nb);
        // Texel ta of brick a and texel ta - B of its neighbor hold the same level sample.
        // Texels [B, B + 2*border) of brick a are texels [0, 2*border) of brick b.
        for (uint32_t ta = b; ta < e; ++ta)
          for (uint32_t u = 0; u < e; ++u)
            for (uint32_t w = 0; w < e; ++w) {
              glm::u32vec3 pa(0), pb(0);
              pa[axis] = ta;
              pb[axis] = ta - b;
              pa[(axis + 1) % 3] = pb[(axis + 1) % 3] = u;
              pa[(axis + 2) % 3] = pb[(axis + 2) % 3] = w;
              ASSERT_EQ(ba[pa.x + e * (pa.y + e * pa.z)], bb[pb.x + e * (pb.y + e * pb.z)])
                  << "depth " << depth << " axis " << axis << " c " << c;
            }
      }
    }
    // The last brick along x: texels past the level's last sample repeat it.
    const uint32_t dimX = l.levelDims(l.levelOfDepth(depth)).x;
    const NodeKey last{depth, {n.x - 1, 0, 0}};
    const auto bl = readBrick(src, last);
    const uint32_t lastTexel = dimX - 1 - (n.x - 1) * b + border;
    ASSERT_LT(lastTexel + 1, e);
    for (uint32_t x = lastTexel + 1; x < e; ++x)
      for (uint32_t y = 0; y < e; ++y)
        ASSERT_EQ(bl[x + e * (y + e * 3)], bl[lastTexel + e * (y + e * 3)]) << "x " << x;
    // And before the first sample (texels 0, 1) repeat sample 0.
    const auto bf = readBrick(src, {depth, {0, 1, 1}});
    for (uint32_t y = 0; y < e; ++y) {
      ASSERT_EQ(bf[0 + e * (y + e * 5)], bf[border + e * (y + e * 5)]);
      ASSERT_EQ(bf[1 + e * (y + e * 5)], bf[border + e * (y + e * 5)]);
    }
  }
}

TEST(ProceduralBricks, HugeSizesNeedNoGeneration) {
  const auto start = SteadyClock::now();
  const auto src = openProceduralBricks("procedural:sphere:65536");
  const OctreeLayout& l = src->info().layout;
  EXPECT_EQ(src->info().volume.dims, glm::u32vec3(65536));
  EXPECT_EQ(l.maxDepth, 11u);
  EXPECT_EQ(src->info().volume.description, "procedural:sphere:65536");
  // The root spans everything; a finest node at the corner is far outside the sphere: (nearly) zero. The
  // field's range() may widen bounds by one unit, so it need not report Constant.
  const NodeInfo root = src->node({0, {0, 0, 0}});
  EXPECT_EQ(root.minValue, 0);
  EXPECT_EQ(root.maxValue, 255);
  const NodeInfo corner = src->node({l.maxDepth, {0, 0, 0}});
  EXPECT_EQ(corner.minValue, 0);
  EXPECT_LE(corner.maxValue, 1);
  // A finest node on the isosurface (x = 0.5 * SIZE + 0.4 * SIZE) has data and reads quickly.
  const NodeKey onSurface{l.maxDepth, {uint32_t(0.9 * 65536 / 32), 1024, 1024}};
  const NodeInfo s = src->node(onSurface);
  EXPECT_EQ(s.kind, NodeKind::Data);
  EXPECT_LE(s.minValue, 128);
  EXPECT_GE(s.maxValue, 127);
  const auto brick = readBrick(*src, onSurface);
  for (uint8_t v : brick) {
    ASSERT_GE(v, s.minValue);
    ASSERT_LE(v, s.maxValue);
  }
  EXPECT_LT(secondsSince(start), 5.0);
}

TEST(ProceduralBricks, ConcurrentReadsAgree) {
  const ProceduralBricks src({ProceduralKind::Noise, 64}, 16);
  const OctreeLayout& l = src.info().layout;
  std::vector<NodeKey> keys;
  for (uint64_t i = 0; i < l.insideNodeCount(); ++i) keys.push_back(l.nodeAt(i));
  std::vector<std::vector<uint8_t>> a(keys.size()), b(keys.size());
  std::thread t([&] {
    for (size_t i = 0; i < keys.size(); ++i) a[i] = readBrick(src, keys[i]);
  });
  for (size_t i = keys.size(); i-- > 0;) b[i] = readBrick(src, keys[i]);
  t.join();
  EXPECT_EQ(a, b);
}

TEST(ProceduralBricks, BadSpecsAreNamed) {
  for (const std::string spec : {"procedural:cube:64", "procedural:sphere:x", "procedural:sphere:0"}) {
    try {
      openProceduralBricks(spec);
      ADD_FAILURE() << "expected an error for " << spec;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(spec.substr(11)), std::string::npos) << e.what();
    }
  }
  const ProceduralBricks src({ProceduralKind::Sphere, 32}, 8);
  std::vector<std::byte> wrong(17);
  EXPECT_THROW(src.readBrick({0, {0, 0, 0}}, wrong), Error);
}

}  // namespace
}  // namespace ropecast
