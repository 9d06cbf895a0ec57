// The occlusion queries (render/occlusion_queries.h) against what they should see: an opaque slab in front of
// a sphere hides the sphere's leaves and not its own; on a random scene each box's count of visible samples
// matches a CPU count from the ray caster's depth image; answers that are not available stay pending.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <epoxy/gl.h>
#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "loader/refiner.h"
#include "render/occlusion_queries.h"
#include "render/raycast_pass.h"
#include "tests/render/testutil_gl.h"

namespace ropecast {
namespace {

using test::SceneSpec;

constexpr uint32_t kSize = 96;

struct QueriedScene {
  test::GlScene scene;
  std::vector<QueryBox> boxes;  // the data leaves
};

QueriedScene buildQueried(const SceneSpec& spec) {
  QueriedScene q{test::buildScene(spec), {}};
  for (const CutLeaf& leaf : q.scene.cut.leaves) {
    if (leaf.kind != LeafKind::Data) continue;
    const NodeKey key{leaf.depth, leaf.coord};
    const WorldBox box = nodeWorldBox(q.scene.info.layout, q.scene.info.volume.spacing, key);
    q.boxes.push_back({key, {{box}, 1}});
  }
  return q;
}

RaycastFrame isoFrame(const Camera& camera, RenderBackend backend) {
  RaycastFrame frame;
  frame.camera = camera;
  frame.width = frame.height = kSize;
  frame.params.mode = RenderMode::Iso;
  frame.params.isoValue = 0.5 * 65535.0;  // identity mapping of uint16 stored values
  frame.params.backend = backend;
  return frame;
}

// Casts the scene as one tile, issues the queries after it, and returns the answers once the GPU finished.
std::vector<QueryAnswer> castAndQuery(RaycastPass& pass, const QueriedScene& q, const RaycastFrame& frame,
                                      std::span<const QueryBox> boxes) {
  OcclusionQueries queries;
  TileSchedule schedule;
  schedule.tiles = {{0, 0, kSize, kSize}};
  schedule.afterFirstTile = [&] {
    const DepthRange depth =
        windowDepthRange(frame.camera, glm::dvec3(q.scene.geometry.dims) * q.scene.geometry.spacing);
    queries.issue(boxes, frame.camera, frame.width, frame.height, depth, 7);
  };
  test::renderScene(pass, q.scene, frame, schedule);
  glFinish();
  std::vector<QueryAnswer> answers = queries.collect();
  EXPECT_EQ(queries.pendingCount(), 0u) << "glFinish leaves every query answered";
  for (const QueryAnswer& a : answers) EXPECT_EQ(a.issuedFrame, 7u);
  return answers;
}

class OcclusionQueriesTest : public ::testing::TestWithParam<RenderBackend> {};

TEST_P(OcclusionQueriesTest, SlabHidesTheSphereBehindIt) {
  test::sharedGlContext();
  // 64^3 voxels; an opaque slab z in [8, 12] over the whole x, y extent, a sphere around z = 40 behind it.
  SceneSpec spec;
  spec.dims = glm::u32vec3(64);
  spec.brickSize = 8;
  spec.value = [](glm::dvec3 p) {
    const bool slab = p.z >= 8.0 && p.z <= 12.0;
    const bool sphere = glm::length(p - glm::dvec3(32.0, 32.0, 40.0)) <= 14.0;
    return slab || sphere ? 1.0 : 0.0;
  };
  const QueriedScene q = buildQueried(spec);
  Camera camera;
  camera.eye = {32.0, 32.0, -60.0};
  camera.target = {32.0, 32.0, 32.0};
  camera.up = {0.0, 1.0, 0.0};
  RaycastPass pass;
  const std::vector<QueryAnswer> answers = castAndQuery(pass, q, isoFrame(camera, GetParam()), q.boxes);
  ASSERT_EQ(answers.size(), q.boxes.size());

  int slabLeaves = 0, sphereLeaves = 0;
  for (size_t i = 0; i < answers.size(); ++i) {
    ASSERT_EQ(answers[i].key, q.boxes[i].key);
    const WorldBox& box = q.boxes[i].parts.boxes[0];
    // The view covers x and y in about [7, 57] at the slab: the leaves at the volume's side show a sliver.
    const bool inView = box.lo.x >= 8.0 && box.hi.x <= 56.0 && box.lo.y >= 8.0 && box.hi.y <= 56.0;
    if (inView && box.lo.z <= 8.0 && box.hi.z > 8.0) {  // holds the slab's front face: seen
      ++slabLeaves;
      EXPECT_GE(answers[i].samplesPassed, 4u) << "slab leaf at z " << box.lo.z;
    } else if (box.lo.z >= 16.0) {  // the sphere, behind the slab
      ++sphereLeaves;
      EXPECT_LT(answers[i].samplesPassed, 4u) << "sphere leaf at z " << box.lo.z;
    }
  }
  EXPECT_GT(slabLeaves, 10);
  EXPECT_GT(sphereLeaves, 10);
}

// World depth of a window depth of shaders/window_depth.glsl (1 = +inf).
double worldDepth(double window, DepthRange range) {
  if (window >= 1.0) return std::numeric_limits<double>::infinity();
  const double n = range.nearDepth, f = range.farDepth, ndc = 2.0 * window - 1.0;
  return 2.0 * f * n / ((f + n) - ndc * (f - n));
}

// Samples of `box` whose pixel-center ray enters it before the ray stopped (the stop depths, world units).
uint64_t cpuVisibleSamples(const WorldBox& box, const Camera& camera, const FloatImage& stopDepth) {
  const CameraFrame f = cameraFrame(camera);
  uint64_t count = 0;
  for (uint32_t y = 0; y < stopDepth.height; ++y)
    for (uint32_t x = 0; x < stopDepth.width; ++x) {
      const Ray ray = pixelRay(camera, stopDepth.width, stopDepth.height, x, y);
      double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
      for (int a = 0; a < 3; ++a) {
        const double ta = (box.lo[a] - ray.origin[a]) / ray.dir[a],
                     tb = (box.hi[a] - ray.origin[a]) / ray.dir[a];
        t0 = std::max(t0, std::min(ta, tb));
        t1 = std::min(t1, std::max(ta, tb));
      }
      if (t0 >= t1) continue;
      const double entryDepth = t0 * glm::dot(ray.dir, f.forward);
      if (entryDepth < double(stopDepth.at(x, y, 0))) ++count;
    }
  return count;
}

TEST_P(OcclusionQueriesTest, CountsMatchTheDepthImageOnARandomScene) {
  test::sharedGlContext();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<glm::dvec4> blobs;  // center, radius
  for (int i = 0; i < 12; ++i)
    blobs.push_back(
        {64.0 * uniform(rng), 64.0 * uniform(rng), 64.0 * uniform(rng), 4.0 + 8.0 * uniform(rng)});
  SceneSpec spec;
  spec.dims = glm::u32vec3(64);
  spec.brickSize = 8;
  spec.value = [&](glm::dvec3 p) {
    for (const glm::dvec4& b : blobs)
      if (glm::length(p - glm::dvec3(b)) <= b.w) return 1.0;
    return 0.0;
  };
  const QueriedScene q = buildQueried(spec);
  const Camera camera = orbitCamera(35.0, 25.0, 2.2, glm::dvec3(0.0), glm::dvec3(64.0));
  RaycastPass pass;
  const RaycastFrame frame = isoFrame(camera, GetParam());
  const std::vector<QueryAnswer> answers = castAndQuery(pass, q, frame, q.boxes);
  ASSERT_EQ(answers.size(), q.boxes.size());
  // The stop depths the queries were tested against (the fragment entry point cast the whole image before the
  // callback; the compute one copied it), as world depths.
  FloatImage depth = pass.readStopDepth();
  const DepthRange range = windowDepthRange(camera, glm::dvec3(64.0));
  for (float& d : depth.pixels) d = float(worldDepth(d, range));

  int occluded = 0, visible = 0, disagreements = 0;
  for (size_t i = 0; i < answers.size(); ++i) {
    const uint64_t cpu = cpuVisibleSamples(q.boxes[i].parts.boxes[0], camera, depth);
    const uint64_t gl = answers[i].samplesPassed;
    // Rasterization and ray tests differ only on pixels whose center lies on a box edge or whose stop depth
    // equals the box's entry depth: a few per box.
    const double tolerance = 2.0 + 0.03 * double(std::max(cpu, gl));
    if (std::abs(double(cpu) - double(gl)) > tolerance) {
      ++disagreements;
      ADD_FAILURE() << "box " << i << ": GL " << gl << " samples, CPU " << cpu;
    }
    (cpu >= 4 ? visible : occluded)++;
  }
  EXPECT_EQ(disagreements, 0);
  EXPECT_GT(occluded, 20) << "the scene should hide part of its leaves";
  EXPECT_GT(visible, 20);

  // A query of several boxes (a node's data parts) counts the samples of all of them: the sum of their own
  // queries, exactly, as the same fragments pass the same depth test.
  std::vector<QueryBox> groups;
  std::vector<uint64_t> sums;
  for (size_t i = 0; i < q.boxes.size();) {
    QueryBox& group = groups.emplace_back();
    group.key = q.boxes[i].key;
    uint64_t sum = 0;
    NodeDataParts& parts = group.parts;
    for (; parts.count < 1 + groups.size() % parts.boxes.size() && i < q.boxes.size(); ++i) {
      parts.boxes[parts.count++] = q.boxes[i].parts.boxes[0];
      sum += answers[i].samplesPassed;
    }
    sums.push_back(sum);
  }
  const std::vector<QueryAnswer> grouped = castAndQuery(pass, q, frame, groups);
  ASSERT_EQ(grouped.size(), groups.size());
  for (size_t g = 0; g < groups.size(); ++g)
    EXPECT_EQ(grouped[g].samplesPassed, sums[g]) << "a query of " << groups[g].parts.count << " boxes";
}

TEST_P(OcclusionQueriesTest, TiledScheduleCastsTheSameImage) {
  test::sharedGlContext();
  SceneSpec spec;
  spec.dims = glm::u32vec3(32);
  spec.value = [](glm::dvec3 p) { return glm::length(p - glm::dvec3(16.0)) <= 11.0 ? 1.0 : 0.0; };
  const test::GlScene scene = test::buildScene(spec);
  const RaycastFrame frame =
      isoFrame(orbitCamera(30.0, 20.0, 2.5, glm::dvec3(0.0), glm::dvec3(32.0)), GetParam());
  RaycastPass pass;
  test::renderScene(pass, scene, frame);
  const FloatImage whole = pass.readColor();
  // Odd tile sizes, the query tile in the middle: each pixel cast once, by the same rays.
  TileSchedule schedule;
  schedule.tiles = {{37, 21, 30, 45},
                    {0, 0, kSize, 21},
                    {0, 21, 37, kSize - 21},
                    {67, 21, kSize - 67, kSize - 21},
                    {37, 66, 30, kSize - 66}};
  int calls = 0;
  schedule.afterFirstTile = [&] { ++calls; };
  test::renderScene(pass, scene, frame, schedule);
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(test::maxAbsDifference(whole, pass.readColor(), 4), 0.0);
}

INSTANTIATE_TEST_SUITE_P(Backends, OcclusionQueriesTest,
                         ::testing::Values(RenderBackend::Fragment, RenderBackend::Compute),
                         [](const auto& info) { return std::string(renderBackendName(info.param)); });

TEST(OcclusionQueries, AnswersNotAvailableStayPending) {
  test::sharedGlContext();
  SceneSpec spec;
  spec.dims = glm::u32vec3(32);
  spec.value = [](glm::dvec3 p) { return glm::length(p - glm::dvec3(16.0)) <= 10.0 ? 1.0 : 0.0; };
  const QueriedScene q = buildQueried(spec);
  const Camera camera = orbitCamera(20.0, 10.0, 2.5, glm::dvec3(0.0), glm::dvec3(32.0));
  bool released = false;
  OcclusionQueries queries;
  queries.setFenceProbe(std::make_unique<test::HeldBackFences>(&released));
  RaycastPass pass;
  RaycastFrame frame = isoFrame(camera, RenderBackend::Fragment);
  TileSchedule schedule;
  schedule.afterFirstTile = [&] {
    queries.issue(q.boxes, camera, kSize, kSize, windowDepthRange(camera, glm::dvec3(32.0)), 1);
  };
  schedule.tiles = {{0, 0, kSize, kSize}};
  test::renderScene(pass, q.scene, frame, schedule);
  for (int f = 0; f < 3; ++f) {  // later frames go on while the answers are held back
    EXPECT_TRUE(queries.collect().empty());
    EXPECT_EQ(queries.pendingCount(), q.boxes.size());
    test::renderScene(pass, q.scene, frame);
  }
  released = true;
  EXPECT_EQ(queries.collect().size(), q.boxes.size());
  EXPECT_EQ(queries.pendingCount(), 0u);
}

}  // namespace
}  // namespace ropecast
