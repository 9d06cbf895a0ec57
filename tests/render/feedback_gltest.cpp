// The rays' usage and miss feedback (docs/RENDERING.md "Feedback"): the GLSL sets against the CPU twin
// (reference/feedback_twin.h) on random cuts and cameras, iso and DVR, both entry points and the DVR leaf
// batch; the request rule on a leaf near and far; a leaf behind an opaque isosurface; list overflow; a
// readback that never waits; and an image that feedback does not change.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <random>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include "core/transfer_function.h"
#include "reference/feedback_twin.h"
#include "render/feedback_buffer.h"
#include "render/raycast_pass.h"
#include "tests/render/testutil_gl.h"

namespace ropecast {
namespace {

using test::SceneSpec;

// Renders one frame with feedback and waits (here, in the test) for its readback.
FeedbackReadback renderWithFeedback(RaycastPass& pass, const test::GlScene& scene, RaycastFrame frame,
                                    const FeedbackBufferConfig& config = {}) {
  FeedbackBuffer feedback(config);
  feedback.begin(uint32_t(scene.cut.leaves.size()));
  frame.feedback = &feedback;
  test::renderScene(pass, scene, frame);
  feedback.end(7);
  glFinish();
  std::optional<FeedbackReadback> r = feedback.poll();
  if (!r) throw std::runtime_error("no readback after glFinish");
  EXPECT_EQ(r->frame, 7u);
  return std::move(*r);
}

std::vector<uint32_t> sortedUnique(std::vector<uint32_t> v, const char* what) {
  std::sort(v.begin(), v.end());
  EXPECT_EQ(std::adjacent_find(v.begin(), v.end()), v.end()) << what << " lists a leaf twice";
  return v;
}

bool includes(const std::vector<uint32_t>& big, const std::vector<uint32_t>& small) {
  return std::includes(big.begin(), big.end(), small.begin(), small.end());
}

std::string difference(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b) {
  std::vector<uint32_t> d;
  std::set_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(d));
  std::ostringstream s;
  for (size_t i = 0; i < d.size() && i < 12; ++i) s << d[i] << ' ';
  if (d.size() > 12) s << "... (" << d.size() << ")";
  return s.str();
}

uint64_t mix(uint64_t x) {
  x ^= x >> 33;
  x *= 0xff51afd7ed558ccdULL;
  x ^= x >> 33;
  x *= 0xc4ceb9fe1a85ec53ULL;
  return x ^ (x >> 33);
}
uint64_t nodeHash(uint64_t seed, const NodeKey& n) {
  return mix(seed ^ mix(n.depth + 64 * (n.coord.x + 4096ull * (n.coord.y + 4096ull * n.coord.z))));
}

// A random cut over a 40 x 34 x 30 volume of brick size 8 (maxDepth 3): nodes split with probability 0.6,
// a tenth of the inside leaves Empty.
SceneSpec randomScene(uint64_t seed) {
  SceneSpec spec;
  spec.dims = {40, 34, 30};
  spec.spacing = {1.0, 0.9, 1.2};
  spec.brickSize = 8;
  spec.storedType = SampleType::UInt16;
  spec.refine = [seed](const NodeKey& n) { return n.depth == 0 || nodeHash(seed, n) % 10 < 6; };
  spec.emptyLeaf = [seed](const NodeKey& n) { return nodeHash(seed + 1, n) % 10 == 0; };
  const glm::dvec3 c(18.0 + double(seed % 5), 15.0, 16.0);
  spec.value = [c](glm::dvec3 x) {
    const glm::dvec3 d = x - c;
    return 0.5 + 0.3 * std::sin(0.23 * d.x + 0.17 * d.z) * std::cos(0.21 * d.y) - 0.006 * glm::length(d);
  };
  return spec;
}

// The GPU's sets lie between the twin's sure and possible sets; where those agree they are equal.
void expectWithinBounds(const FeedbackReadback& gpu, const FeedbackBounds& cpu, const std::string& what) {
  EXPECT_EQ(gpu.usedDropped, 0u) << what;
  EXPECT_EQ(gpu.requestedDropped, 0u) << what;
  const std::vector<uint32_t> used = sortedUnique(gpu.usedLeaves, "used");
  const std::vector<uint32_t> requested = sortedUnique(gpu.requestedLeaves, "requested");
  EXPECT_TRUE(includes(used, cpu.sure.usedLeaves))
      << what << ": used on the CPU surely, not on the GPU: " << difference(cpu.sure.usedLeaves, used);
  EXPECT_TRUE(includes(cpu.possible.usedLeaves, used))
      << what << ": used on the GPU, impossible on the CPU: " << difference(used, cpu.possible.usedLeaves);
  EXPECT_TRUE(includes(requested, cpu.sure.requestedLeaves))
      << what
      << ": requested on the CPU surely, not on the GPU: " << difference(cpu.sure.requestedLeaves, requested);
  EXPECT_TRUE(includes(cpu.possible.requestedLeaves, requested))
      << what << ": requested on the GPU, impossible on the CPU: "
      << difference(requested, cpu.possible.requestedLeaves);
  std::printf("%s: used %zu (cpu %zu..%zu), requested %zu (cpu %zu..%zu), %zu uncertain rays\n", what.c_str(),
              used.size(), cpu.sure.usedLeaves.size(), cpu.possible.usedLeaves.size(), requested.size(),
              cpu.sure.requestedLeaves.size(), cpu.possible.requestedLeaves.size(), cpu.uncertainRays);
}

// Exact first: the twin's own decisions.
const FeedbackTolerance kGpuTolerance{};

struct CameraCase {
  Camera camera;
  const char* name;
};

std::vector<CameraCase> randomCameras(uint64_t seed, glm::dvec3 volumeMax) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  CameraCase outside{orbitCamera(360.0 * u(rng), -60.0 + 120.0 * u(rng), 1.3 + u(rng), glm::dvec3(0),
                                 volumeMax, 35.0 + 20.0 * u(rng)),
                     "outside"};
  CameraCase inside{{}, "inside"};
  inside.camera.eye = volumeMax * glm::dvec3(0.2 + 0.6 * u(rng), 0.2 + 0.6 * u(rng), 0.2 + 0.6 * u(rng));
  const double az = 6.2831853 * u(rng), el = -1.0 + 2.0 * u(rng);
  inside.camera.target =
      inside.camera.eye + glm::dvec3(std::cos(az) * std::cos(el), std::sin(az) * std::cos(el), std::sin(el));
  inside.camera.up = defaultUp(inside.camera.target - inside.camera.eye);
  inside.camera.fovYDeg = 50.0 + 20.0 * u(rng);
  return {outside, inside};
}

TEST(Feedback, GlslSetsMatchTheCpuTwinOnRandomCutsAndCameras) {
  const TfTable tf = TfTable::bake(
      TransferFunction({TfPoint{20000, {0.8, 0.2, 0.1, 0.0}}, TfPoint{34000, {0.9, 0.7, 0.2, 0.1}},
                        TfPoint{48000, {0.3, 0.5, 1.0, 0.6}}}),
      ValueMapping{}, 65535);
  for (uint64_t seed : {1u, 2u, 3u}) {
    const SceneSpec spec = randomScene(seed);
    const test::GlScene scene = test::buildScene(spec);
    ASSERT_LT(scene.minLeafDepth, scene.maxLeafDepth);
    const glm::dvec3 volumeMax = glm::dvec3(spec.dims) * spec.spacing;
    for (const CameraCase& cam : randomCameras(seed, volumeMax)) {
      for (RenderMode mode : {RenderMode::Iso, RenderMode::Dvr}) {
        RaycastFrame frame;
        frame.camera = cam.camera;
        frame.width = 72;
        frame.height = 64;
        frame.params.mode = mode;
        frame.params.isoValue = 0.55 * 65535;
        frame.params.ert = 0.95;
        frame.tf = &tf;
        // A target at which some leaves are fine enough and others are not.
        frame.voxelsPerPixel = seed == 1 ? 0.3 : seed == 2 ? 0.6 : 1.2;
        CpuRenderInput input;
        input.camera = frame.camera;
        input.width = frame.width;
        input.height = frame.height;
        input.params = frame.params;
        input.tf = &tf;
        const FeedbackBounds cpu =
            mirrorFeedback(scene.index, scene.bricks, scene.info, input, frame.voxelsPerPixel, kGpuTolerance);
        for (auto [backend, leafBatch] :
             {std::pair{RenderBackend::Fragment, false}, std::pair{RenderBackend::Compute, false},
              std::pair{RenderBackend::Fragment, true}, std::pair{RenderBackend::Compute, true}}) {
          if (leafBatch && mode != RenderMode::Dvr) continue;
          frame.params.backend = backend;
          RaycastPass pass;
          pass.setDvrLeafBatch(leafBatch);
          const FeedbackReadback gpu = renderWithFeedback(pass, scene, frame);
          const std::string what = "seed " + std::to_string(seed) + " " + cam.name +
                                   (mode == RenderMode::Iso ? " iso" : " dvr") +
                                   (backend == RenderBackend::Fragment ? " fragment" : " compute") +
                                   (leafBatch ? " leaf batch" : "");
          expectWithinBounds(gpu, cpu, what);
          EXPECT_FALSE(cpu.sure.usedLeaves.empty()) << what;
        }
      }
    }
  }
}

}  // namespace
}  // namespace ropecast
