// The rays' usage and miss feedback (docs/RENDERING.md "Feedback"): the GLSL sets against the CPU twin
// (reference/feedback_twin.h) on random cuts and cameras, iso and DVR, both entry points and the DVR leaf
// batch, hits included; the request rule on a leaf near and far; a leaf behind an opaque isosurface; list
// overflow; a readback that never waits; and an image that feedback does not change.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <random>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/transfer_function.h"
#include "loader/refiner.h"
#include "reference/feedback_twin.h"
#include "render/feedback_buffer.h"
#include "render/raycast_pass.h"
#include "tests/render/testutil_gl.h"

namespace ropecast {
namespace {

using test::SceneSpec;

// Renders one frame with feedback and waits (here, in the test) for its readback.
FeedbackReadback renderWithFeedback(RaycastPass& pass, const test::GlScene& scene, RaycastFrame frame,
                                    const FeedbackBufferConfig& config = {}, uint32_t hitThreshold = 0) {
  FeedbackBuffer feedback(config);
  feedback.begin(uint32_t(scene.cut.leaves.size()), hitThreshold);
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

// A random cut over a 72 x 60 x 56 volume of brick size 8 (maxDepth 4): nodes of depth 2 split with
// probability 0.7, of depth 3 with 0.5; a tenth of the inside leaves Empty; 8-bit samples for odd seeds,
// 16-bit for even.
SceneSpec randomScene(uint64_t seed) {
  SceneSpec spec;
  spec.dims = {72, 60, 56};
  spec.spacing = {1.0, 0.9, 1.2};
  spec.brickSize = 8;
  spec.storedType = seed % 2 == 1 ? SampleType::UInt8 : SampleType::UInt16;
  spec.refine = [seed](const NodeKey& n) {
    return n.depth <= 1 || nodeHash(seed, n) % 10 < 11 - 2 * n.depth;
  };
  spec.emptyLeaf = [seed](const NodeKey& n) { return nodeHash(seed + 1, n) % 10 == 0; };
  const glm::dvec3 c(30.0 + 3.0 * double(seed), 27.0, 30.0);
  spec.value = [c](glm::dvec3 x) {
    const glm::dvec3 d = x - c;
    return 0.5 + 0.3 * std::sin(0.13 * d.x + 0.1 * d.z) * std::cos(0.11 * d.y) - 0.004 * glm::length(d);
  };
  return spec;
}

// The GPU's sets lie between the twin's sure and possible sets; where those agree they are equal.
void expectWithinBounds(const FeedbackReadback& gpu, const FeedbackBounds& cpu, const std::string& what) {
  EXPECT_EQ(gpu.usedDropped, 0u) << what;
  EXPECT_EQ(gpu.requestedDropped, 0u) << what;
  EXPECT_EQ(gpu.hitDropped, 0u) << what;
  const std::vector<uint32_t> used = sortedUnique(gpu.usedLeaves, "used");
  const std::vector<uint32_t> requested = sortedUnique(gpu.requestedLeaves, "requested");
  const std::vector<uint32_t> hits = sortedUnique(gpu.hitLeaves, "hit");
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
  EXPECT_TRUE(includes(hits, cpu.sure.hitLeaves))
      << what << ": hit on the CPU surely, not on the GPU: " << difference(cpu.sure.hitLeaves, hits);
  EXPECT_TRUE(includes(cpu.possible.hitLeaves, hits))
      << what << ": hit on the GPU, impossible on the CPU: " << difference(hits, cpu.possible.hitLeaves);
  std::printf(
      "%s: used %zu (cpu %zu..%zu), requested %zu (cpu %zu..%zu), hit %zu (cpu %zu..%zu), %zu uncertain "
      "rays\n",
      what.c_str(), used.size(), cpu.sure.usedLeaves.size(), cpu.possible.usedLeaves.size(), requested.size(),
      cpu.sure.requestedLeaves.size(), cpu.possible.requestedLeaves.size(), hits.size(),
      cpu.sure.hitLeaves.size(), cpu.possible.hitLeaves.size(), cpu.uncertainRays);
}

// How far a GPU may stray from the mirror before it can decide otherwise (reference/feedback_twin.h). Exact
// agreement is the rule but not guaranteed: a ray whose mirror opacity crosses the termination threshold by
// less than the GPU's error at the last sample of a leaf (0.9507 against ert 0.95, say) goes on into the
// next leaf on the GPU. Values: filtering with 8-bit weights (llvmpipe for 8-bit textures, most GPUs for all)
// is off by up to 3/512 of the largest difference between neighbouring texels, below 0.8 in these scenes
// (level 4): 5e-3. Opacity: per-sample errors of a few 1e-3 (that value error through the transfer
// function's slope of about 2.4) add up, relative to the transparency 1 - A ~ 0.05 left near termination,
// to a few 1e-3: 0.01. Sample positions and request distances: float against double, a few ulps: 1e-5.
const FeedbackTolerance kGpuTolerance{5e-3, 0.01, 1e-5};

void expectEqualSets(const FeedbackReadback& gpu, const FeedbackSets& cpu, const std::string& what) {
  const std::vector<uint32_t> used = sortedUnique(gpu.usedLeaves, "used");
  const std::vector<uint32_t> requested = sortedUnique(gpu.requestedLeaves, "requested");
  const std::vector<uint32_t> hits = sortedUnique(gpu.hitLeaves, "hit");
  EXPECT_EQ(hits, cpu.hitLeaves) << what << ": hit only on the GPU: " << difference(hits, cpu.hitLeaves)
                                 << "; only on the CPU: " << difference(cpu.hitLeaves, hits);
  EXPECT_EQ(used, cpu.usedLeaves) << what << ": used only on the GPU: " << difference(used, cpu.usedLeaves)
                                  << "; only on the CPU: " << difference(cpu.usedLeaves, used);
  EXPECT_EQ(requested, cpu.requestedLeaves)
      << what << ": requested only on the GPU: " << difference(requested, cpu.requestedLeaves)
      << "; only on the CPU: " << difference(cpu.requestedLeaves, requested);
}

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
  // Rays that make a leaf a hit: a few, so that small leaves reach it and large ones pass it.
  constexpr uint32_t kHitThreshold = 3;
  size_t stops = 0, solidLeaves = 0;
  for (uint64_t seed : {1u, 2u, 3u, 4u, 5u}) {
    SceneSpec spec = randomScene(seed);
    // Even seeds crop the volume: rays that start and end at the crop box's faces, inside leaves and on their
    // borders. The leaves wholly outside the box are empty, as the refiner culls them. The isosurface is
    // capped on the box's faces, in data leaves and in Solid ones (leaves wholly above the isovalue, as
    // FrameRenderer marks them; in the other modes they are empty leaves, the same for the GPU and the twin).
    std::optional<CropBox> crop;
    const double isoNormalized = seed % 2 == 0 ? 0.35 : 0.55;  // cropped: lower, for leaves wholly above it
    if (seed % 2 == 0) {
      spec.solidAbove = isoNormalized;
      crop = CropBox{glm::floor(0.2 * glm::dvec3(spec.dims)), glm::ceil(0.85 * glm::dvec3(spec.dims))};
      const OctreeLayout layout = OctreeLayout::forVolume(spec.dims, spec.brickSize);
      const WorldBox box{crop->lo * spec.spacing, crop->hi * spec.spacing};
      spec.emptyLeaf = [empty = spec.emptyLeaf, layout, box, spacing = spec.spacing](const NodeKey& n) {
        return empty(n) || !hasVolume(intersection(nodeWorldBox(layout, spacing, n), box));
      };
    }
    const test::GlScene scene = test::buildScene(spec);
    ASSERT_LT(scene.minLeafDepth, scene.maxLeafDepth);
    solidLeaves += scene.solidLeaves;
    const glm::dvec3 volumeMax = glm::dvec3(spec.dims) * spec.spacing;
    for (const CameraCase& cam : randomCameras(seed, volumeMax)) {
      // Iso at a step above a voxel too, where a leaf's end takes a sample (docs/RENDERING.md "Isosurface").
      for (auto [mode, step] :
           {std::pair{RenderMode::Iso, 0.5}, std::pair{RenderMode::Dvr, 0.5}, std::pair{RenderMode::Iso, 2.5},
            std::pair{RenderMode::Mip, 0.5}, std::pair{RenderMode::MinIp, 0.5},
            std::pair{RenderMode::Aip, 0.5}, std::pair{RenderMode::Slice, 0.5}}) {
        RaycastFrame frame;
        frame.camera = cam.camera;
        frame.width = 96;
        frame.height = 80;
        frame.params.mode = mode;
        frame.params.stepVoxels = step;
        frame.params.isoValue = isoNormalized * 65535;
        frame.params.ert = 0.95;
        if (crop) frame.params.crop = *crop;
        // A slice in front of the camera (through the volume's center from outside), turned by the seed.
        if (mode == RenderMode::Slice) {
          const glm::dvec3 forward = cameraFrame(cam.camera).forward;
          const double ahead = 0.2 * std::min({volumeMax.x, volumeMax.y, volumeMax.z});
          frame.params.clipPlane = {
              std::string(cam.name) == "inside" ? cam.camera.eye + ahead * forward : 0.5 * volumeMax,
              glm::normalize(forward + glm::dvec3(0.1 * double(seed), -0.3, 0.2))};
        }
        frame.tf = &tf;
        const std::vector<float> bounds = scene.leafBounds(mode);
        frame.leafMaxima = bounds;
        // A target at which level-1 leaves are fine enough beyond the volume's center and too coarse before
        // it.
        const double centerDistance = std::max(glm::length(cam.camera.eye - 0.5 * volumeMax), 10.0);
        frame.voxelsPerPixel =
            1.0 / feedbackVoxelPixels(1, centerDistance, spec.spacing, cam.camera.fovYDeg, frame.height);
        const CpuRenderInput input = test::cpuInputOf(frame);
        const FeedbackBounds cpu = mirrorFeedback(scene.index, scene.bricks, scene.info, input,
                                                  frame.voxelsPerPixel, kGpuTolerance, kHitThreshold);
        const FeedbackBounds exact = mirrorFeedback(scene.index, scene.bricks, scene.info, input,
                                                    frame.voxelsPerPixel, {}, kHitThreshold);
        ASSERT_EQ(exact.sure.usedLeaves, exact.possible.usedLeaves);
        ASSERT_EQ(exact.sure.requestedLeaves, exact.possible.requestedLeaves);
        ASSERT_EQ(exact.sure.hitLeaves, exact.possible.hitLeaves);
        stops += exact.sure.hitLeaves.size();
        for (auto [backend, leafBatch] :
             {std::pair{RenderBackend::Fragment, false}, std::pair{RenderBackend::Compute, false},
              std::pair{RenderBackend::Fragment, true}, std::pair{RenderBackend::Compute, true}}) {
          if (leafBatch && mode != RenderMode::Dvr) continue;
          frame.params.backend = backend;
          RaycastPass pass;
          pass.setDvrLeafBatch(leafBatch);
          const FeedbackReadback gpu = renderWithFeedback(pass, scene, frame, {}, kHitThreshold);
          const std::string what = "seed " + std::to_string(seed) + (crop ? " cropped " : " ") + cam.name +
                                   " " + std::string(renderModeName(mode)) + " step " + std::to_string(step) +
                                   (backend == RenderBackend::Fragment ? " fragment" : " compute") +
                                   (leafBatch ? " leaf batch" : "");
          expectWithinBounds(gpu, cpu, what);
          const std::vector<uint32_t> used = sortedUnique(gpu.usedLeaves, "used");
          const std::vector<uint32_t> requested = sortedUnique(gpu.requestedLeaves, "requested");
          const std::vector<uint32_t> hits = sortedUnique(gpu.hitLeaves, "hit");
          if (used != exact.sure.usedLeaves || requested != exact.sure.requestedLeaves ||
              hits != exact.sure.hitLeaves)
            std::printf(
                "%s: not exactly the mirror's (within the bounds): used only on the GPU: %s, only on the "
                "CPU: %s; requested only on the GPU: %s, only on the CPU: %s; hit only on the GPU: %s, only "
                "on the CPU: %s\n",
                what.c_str(), difference(used, exact.sure.usedLeaves).c_str(),
                difference(exact.sure.usedLeaves, used).c_str(),
                difference(requested, exact.sure.requestedLeaves).c_str(),
                difference(exact.sure.requestedLeaves, requested).c_str(),
                difference(hits, exact.sure.hitLeaves).c_str(),
                difference(exact.sure.hitLeaves, hits).c_str());
          EXPECT_FALSE(exact.sure.usedLeaves.empty()) << what;
        }
      }
    }
  }
  EXPECT_GT(stops, 0u) << "no leaf reached the hit threshold in any frame: the hits went untested";
  EXPECT_GT(solidLeaves, 0u) << "no Solid leaf: caps without a brick went untested";
}

// Eight leaves of level 1 (a 32^3 volume of brick size 8 cut at depth 1) of a constant value no isosurface
// crosses: every ray samples every leaf it crosses.
SceneSpec coarseScene() {
  SceneSpec spec;
  spec.dims = glm::u32vec3(32);
  spec.brickSize = 8;
  spec.refine = [](const NodeKey& n) { return n.depth == 0; };
  spec.value = [](glm::dvec3) { return 0.2; };
  return spec;
}

RaycastFrame frameLookingAlongX(double eyeX, double voxelsPerPixel) {
  RaycastFrame frame;
  frame.camera.eye = {eyeX, 16.3, 15.8};
  frame.camera.target = {16.0, 16.1, 16.2};
  frame.camera.up = {0, 0, 1};
  frame.camera.fovYDeg = 40.0;
  frame.width = frame.height = 64;
  frame.params.mode = RenderMode::Iso;
  frame.params.isoValue = 0.5 * 65535;
  frame.voxelsPerPixel = voxelsPerPixel;
  return frame;
}

TEST(Feedback, ACoarseLeafIsRequestedExactlyWhereTheRayWantsAFinerLevel) {
  const test::GlScene scene = test::buildScene(coarseScene());
  // pixels(1) = 2 / (2 d tan 20deg) 64 = 175.8 / d: with one voxel per pixel, wanted finer closer than 175.8.
  const double threshold = feedbackVoxelPixels(1, 1.0, glm::dvec3(1.0), 40.0, 64);
  ASSERT_NEAR(threshold, 175.8, 0.1);
  struct Case {
    double eyeX, voxelsPerPixel;
    bool requested;
  };
  // The eye 20 before the volume's +x face: entry distances 20 to 32 (< 175.8): the front leaves are
  // requested (one per ray: the first it samples), not the ones behind; 400 away (> 175.8), or with 0.05
  // voxels per pixel (threshold 8.8): nothing.
  for (Case c : {Case{52.0, 1.0, true}, Case{432.0, 1.0, false}, Case{52.0, 0.05, false}}) {
    for (RenderBackend backend : {RenderBackend::Fragment, RenderBackend::Compute}) {
      RaycastFrame frame = frameLookingAlongX(c.eyeX, c.voxelsPerPixel);
      frame.params.backend = backend;
      RaycastPass pass;
      const FeedbackReadback gpu = renderWithFeedback(pass, scene, frame);
      const FeedbackSets cpu =
          mirrorFeedback(scene.index, scene.bricks, scene.info, test::cpuInputOf(frame), c.voxelsPerPixel)
              .sure;
      const std::string what = "eye x " + std::to_string(c.eyeX) + ", " + std::to_string(c.voxelsPerPixel) +
                               " voxels per pixel" +
                               (backend == RenderBackend::Fragment ? " fragment" : " compute");
      expectEqualSets(gpu, cpu, what);
      EXPECT_FALSE(gpu.usedLeaves.empty()) << what;
      EXPECT_EQ(!gpu.requestedLeaves.empty(), c.requested) << what;
      for (uint32_t leaf : gpu.requestedLeaves)
        EXPECT_EQ(scene.cut.leaves[leaf].coord.x, 1u) << what << ": only the front leaves are first on a ray";
      if (c.requested) {
        // Used behind the front too, but requested there by no ray.
        bool behindUsed = false;
        for (uint32_t leaf : gpu.usedLeaves) behindUsed |= scene.cut.leaves[leaf].coord.x == 0;
        EXPECT_TRUE(behindUsed) << what;
      }
    }
  }

  // Full-resolution leaves (level 0) are never requested, however near.
  SceneSpec fine = coarseScene();
  fine.refine = nullptr;
  const test::GlScene fineScene = test::buildScene(fine);
  RaycastFrame frame = frameLookingAlongX(40.0, 4.0);
  RaycastPass pass;
  const FeedbackReadback gpu = renderWithFeedback(pass, fineScene, frame);
  EXPECT_FALSE(gpu.usedLeaves.empty());
  EXPECT_TRUE(gpu.requestedLeaves.empty());
}

// A wall: v rises from 0 at x = 27 to 1 at x = 17, through the isovalue 0.5 at x = 22. The eye at x = 52
// looks along -x: the surface (and, in DVR, full opacity before x = 21) lies in the front leaves (x in
// [16, 32)), the leaves x in [0, 16) behind it.
SceneSpec wallScene() {
  SceneSpec spec = coarseScene();
  spec.value = [](glm::dvec3 x) { return std::clamp(0.5 + 0.1 * (22.0 - x.x), 0.0, 1.0); };
  return spec;
}

// Transparent below 30000 of 65535, opaque white from 40000.
TfTable wallTf() {
  return TfTable::bake(
      TransferFunction({TfPoint{0, {1.0, 1.0, 1.0, 0.0}}, TfPoint{30000, {1.0, 1.0, 1.0, 0.0}},
                        TfPoint{40000, {1.0, 1.0, 1.0, 1.0}}, TfPoint{65535, {1.0, 1.0, 1.0, 1.0}}}),
      ValueMapping{}, 65535);
}

TEST(Feedback, ALeafBehindAnOpaqueSurfaceIsNeitherUsedNorRequested) {
  const test::GlScene scene = test::buildScene(wallScene());
  const TfTable tf = wallTf();
  for (RenderMode mode : {RenderMode::Iso, RenderMode::Dvr})
    for (RenderBackend backend : {RenderBackend::Fragment, RenderBackend::Compute}) {
      RaycastFrame frame = frameLookingAlongX(52.0, 1.0);
      frame.params.mode = mode;
      frame.params.backend = backend;
      frame.tf = &tf;
      RaycastPass pass;
      // Every leaf one ray stops in is a hit.
      const FeedbackReadback gpu = renderWithFeedback(pass, scene, frame, {}, 1);
      const std::string what =
          std::string(renderModeName(mode)) + (backend == RenderBackend::Fragment ? " fragment" : " compute");
      ASSERT_FALSE(gpu.usedLeaves.empty()) << what;
      EXPECT_FALSE(gpu.requestedLeaves.empty()) << what;
      EXPECT_FALSE(gpu.hitLeaves.empty()) << what;
      for (uint32_t leaf : gpu.usedLeaves)
        EXPECT_EQ(scene.cut.leaves[leaf].coord.x, 1u)
            << what << ": leaf " << leaf << " lies behind the surface";
      for (uint32_t leaf : gpu.requestedLeaves) EXPECT_EQ(scene.cut.leaves[leaf].coord.x, 1u) << what;
      for (uint32_t leaf : gpu.hitLeaves) EXPECT_EQ(scene.cut.leaves[leaf].coord.x, 1u) << what;
      // Every ray stopped at the surface.
      const FloatImage color = pass.readColor();
      for (uint32_t i = 0; i < frame.width * frame.height; ++i)
        ASSERT_GE(color.pixels[4 * i + 3], 0.99f) << what;
      expectEqualSets(
          gpu,
          mirrorFeedback(scene.index, scene.bricks, scene.info, test::cpuInputOf(frame), 1.0, {}, 1).sure,
          what);
    }
}

// A maximum intensity projection's rays stop in no leaf (no hit, whatever the threshold). Without the leaves'
// maxima they go through a wall and use the leaves behind it too; with them, the leaves whose largest value
// cannot raise a ray's maximum are skipped: the same image, and those leaves, hidden by a brighter one in
// front, are not used (MIP's counterpart of occlusion). A wall of 1 in the front leaves, values of at most
// 0.4 behind.
TEST(Feedback, MipSkipsTheLeavesItsMaximumHides) {
  SceneSpec spec = coarseScene();
  spec.value = [](glm::dvec3 x) { return x.x >= 20.0 ? 1.0 : 0.4 * x.x / 20.0; };
  const test::GlScene scene = test::buildScene(spec);
  const TfTable tf =
      TfTable::bake(TransferFunction({TfPoint{0, {1.0, 1.0, 1.0, 0.2}}, TfPoint{65535, {1, 1, 1, 1}}}),
                    ValueMapping{}, 65535);
  for (RenderBackend backend : {RenderBackend::Fragment, RenderBackend::Compute}) {
    RaycastFrame frame = frameLookingAlongX(52.0, 1.0);
    frame.params.mode = RenderMode::Mip;
    frame.params.backend = backend;
    frame.tf = &tf;
    RaycastPass pass;
    const FeedbackReadback all = renderWithFeedback(pass, scene, frame, {}, 1);
    const FloatImage color = pass.readColor(), depth = pass.readDepth();
    const std::vector<float> bounds = scene.leafBounds(RenderMode::Mip);
    frame.leafMaxima = bounds;
    const FeedbackReadback skipping = renderWithFeedback(pass, scene, frame, {}, 1);
    const std::string what = std::string("mip ") + std::string(renderBackendName(backend));
    EXPECT_EQ(test::maxAbsDifference(color, pass.readColor(), 4), 0.0) << what;
    EXPECT_EQ(test::maxAbsDifference(depth, pass.readDepth(), 1), 0.0) << what;
    std::set<uint32_t> columnsAll, columnsSkipping;
    for (uint32_t leaf : all.usedLeaves) columnsAll.insert(scene.cut.leaves[leaf].coord.x);
    for (uint32_t leaf : skipping.usedLeaves) columnsSkipping.insert(scene.cut.leaves[leaf].coord.x);
    EXPECT_EQ(columnsAll, (std::set<uint32_t>{0u, 1u})) << what;
    EXPECT_EQ(columnsSkipping, (std::set<uint32_t>{1u}))
        << what << ": the leaves behind the wall were sampled";
    EXPECT_TRUE(all.hitLeaves.empty()) << what;
    EXPECT_TRUE(skipping.hitLeaves.empty()) << what;
    // Every ray's maximum is the wall's 1, through the function's opaque white.
    for (uint32_t i = 0; i < frame.width * frame.height; ++i)
      ASSERT_EQ(color.pixels[4 * i + 3], 1.0f) << what;
    expectEqualSets(
        skipping,
        mirrorFeedback(scene.index, scene.bricks, scene.info, test::cpuInputOf(frame), 1.0, {}, 1).sure,
        what);
  }
}

TEST(Feedback, ListsHoldTheirCapacityAndCountTheRestAsDropped) {
  const SceneSpec spec = randomScene(2);  // 16-bit: the isovalue below is in its range (hits)
  const test::GlScene scene = test::buildScene(spec);
  RaycastFrame frame;
  frame.camera = orbitCamera(30, 20, 1.5, glm::dvec3(0), glm::dvec3(spec.dims) * spec.spacing);
  frame.width = frame.height = 64;
  frame.params.mode = RenderMode::Iso;
  frame.params.isoValue = 0.55 * 65535;
  frame.voxelsPerPixel = 2.0;
  for (RenderBackend backend : {RenderBackend::Fragment, RenderBackend::Compute}) {
    frame.params.backend = backend;
    RaycastPass pass;
    const FeedbackReadback all = renderWithFeedback(pass, scene, frame, {}, 2);
    const std::vector<uint32_t> used = sortedUnique(all.usedLeaves, "used");
    const std::vector<uint32_t> requested = sortedUnique(all.requestedLeaves, "requested");
    const std::vector<uint32_t> hits = sortedUnique(all.hitLeaves, "hit");
    ASSERT_GT(used.size(), 5u);
    ASSERT_GT(requested.size(), 2u);
    ASSERT_GT(hits.size(), 4u);
    const FeedbackReadback few = renderWithFeedback(pass, scene, frame, {5, 2, 3, 4}, 2);
    EXPECT_EQ(few.usedLeaves.size(), 5u);
    EXPECT_EQ(few.requestedLeaves.size(), 2u);
    EXPECT_EQ(few.hitLeaves.size(), 4u);
    EXPECT_EQ(few.usedDropped, used.size() - 5);
    EXPECT_EQ(few.requestedDropped, requested.size() - 2);
    EXPECT_EQ(few.hitDropped, hits.size() - 4);
    EXPECT_TRUE(includes(used, sortedUnique(few.usedLeaves, "used")));
    EXPECT_TRUE(includes(requested, sortedUnique(few.requestedLeaves, "requested")));
    EXPECT_TRUE(includes(hits, sortedUnique(few.hitLeaves, "hit")));
  }
}

TEST(Feedback, ReadbackNeverWaitsAndArrivesInFrameOrder) {
  const test::GlScene scene = test::buildScene(coarseScene());
  bool released = false;
  FeedbackBuffer feedback({16384, 4096, 3}, std::make_unique<test::HeldBackFences>(&released));
  RaycastPass pass;
  RaycastFrame frame = frameLookingAlongX(52.0, 1.0);
  frame.feedback = &feedback;
  // Five frames while no fence signals: nothing comes back, rendering goes on, and the two frames that
  // found the ring full are skipped.
  for (uint64_t f = 0; f < 5; ++f) {
    feedback.begin(uint32_t(scene.cut.leaves.size()));
    test::renderScene(pass, scene, frame);
    feedback.end(f);
    EXPECT_FALSE(feedback.poll()) << "frame " << f;
  }
  EXPECT_EQ(feedback.inFlight(), 3u);
  EXPECT_EQ(feedback.skippedReadbacks(), 2u);
  glFinish();  // the test's own wait, so that the released fences are true
  released = true;
  const std::vector<uint32_t> expectedUsed =
      mirrorFeedback(scene.index, scene.bricks, scene.info, test::cpuInputOf(frame), 1.0).sure.usedLeaves;
  for (uint64_t f = 0; f < 3; ++f) {
    const std::optional<FeedbackReadback> r = feedback.poll();
    ASSERT_TRUE(r) << "frame " << f;
    EXPECT_EQ(r->frame, f);
    EXPECT_EQ(sortedUnique(r->usedLeaves, "used"), expectedUsed) << "frame " << f;
  }
  EXPECT_FALSE(feedback.poll());
  EXPECT_EQ(feedback.inFlight(), 0u);

  // The readback sources wait nowhere: no glFinish, and glClientWaitSync only in the fence probe, with a zero
  // timeout.
  int waits = 0;
  for (const char* file :
       {"render/feedback_buffer.cpp", "render/occlusion_queries.cpp", "render/gl_fence.cpp"}) {
    std::ifstream in(std::string(ROPECAST_SOURCE_DIR) + "/" + file);
    ASSERT_TRUE(in) << file;
    const std::string source((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(source.find("glFinish"), std::string::npos) << file;
    EXPECT_EQ(source.find("glWaitSync"), std::string::npos) << file;
    EXPECT_EQ(source.find("glGetQueryObject"), std::string::npos) << file;
    const std::regex wait(R"(glClientWaitSync\(([^;]*)\))");
    for (auto it = std::sregex_iterator(source.begin(), source.end(), wait); it != std::sregex_iterator();
         ++it) {
      ++waits;
      EXPECT_TRUE(std::regex_search((*it)[1].str(), std::regex(R"(,\s*0\s*,\s*0\s*$)")))
          << file << ": " << (*it)[0];
    }
  }
  EXPECT_EQ(waits, 1);
}

TEST(Feedback, FeedbackLeavesTheImageBitIdentical) {
  const SceneSpec spec = randomScene(2);
  const test::GlScene scene = test::buildScene(spec);
  const TfTable tf = TfTable::bake(
      TransferFunction({TfPoint{20000, {0.8, 0.2, 0.1, 0.0}}, TfPoint{48000, {0.3, 0.5, 1.0, 0.6}}}),
      ValueMapping{}, 65535);
  for (RenderMode mode : {RenderMode::Iso, RenderMode::Dvr, RenderMode::Mip})
    for (auto [backend, leafBatch] :
         {std::pair{RenderBackend::Fragment, false}, std::pair{RenderBackend::Compute, false},
          std::pair{RenderBackend::Fragment, true}, std::pair{RenderBackend::Compute, true}}) {
      if (leafBatch && mode != RenderMode::Dvr) continue;
      RaycastFrame frame;
      frame.camera = orbitCamera(50, 30, 1.6, glm::dvec3(0), glm::dvec3(spec.dims) * spec.spacing);
      frame.width = 80;
      frame.height = 72;
      frame.params.mode = mode;
      frame.params.isoValue = 0.55 * 65535;
      frame.params.backend = backend;
      frame.tf = &tf;
      RaycastPass pass;
      pass.setDvrLeafBatch(leafBatch);
      test::renderScene(pass, scene, frame);
      const FloatImage color = pass.readColor(), depth = pass.readDepth(), stop = pass.readStopDepth();
      renderWithFeedback(pass, scene, frame);
      const std::string what = std::string(renderModeName(mode)) +
                               (backend == RenderBackend::Fragment ? " fragment" : " compute") +
                               (leafBatch ? " leaf batch" : "");
      const auto same = [](const FloatImage& a, const FloatImage& b) {
        return a.pixels.size() == b.pixels.size() &&
               std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)) == 0;
      };
      EXPECT_TRUE(same(color, pass.readColor())) << what;
      EXPECT_TRUE(same(depth, pass.readDepth())) << what;
      EXPECT_TRUE(same(stop, pass.readStopDepth())) << what;
    }
}

TEST(Feedback, RaycastPassRejectsAFeedbackBufferWithoutAFrame) {
  const test::GlScene scene = test::buildScene(coarseScene());
  FeedbackBuffer feedback;
  RaycastPass pass;
  RaycastFrame frame = frameLookingAlongX(52.0, 1.0);
  frame.feedback = &feedback;
  try {
    test::renderScene(pass, scene, frame);
    FAIL() << "rendered into a FeedbackBuffer without begin()";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("RaycastPass::render: the FeedbackBuffer has no frame begun"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(feedback.end(0), Error);
  feedback.begin(8);
  EXPECT_THROW(feedback.begin(8), Error);
}

}  // namespace
}  // namespace ropecast
