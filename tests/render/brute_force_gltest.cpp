// The brute-force baseline of bench/render_vs_brute.sh (render/brute_force_pass) in each of its entry points:
// against the rope ray caster in the same shader stage on a cut of full-resolution leaves, the same image up
// to rounding (>= 35 dB, under 0.5% of the pixels off by more than 0.05), iso and DVR, so that the benchmark
// compares two renderers of the same picture; and its compute entry point against its fragment one, the same
// image as the ray caster's two entry points give.
#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/transfer_function.h"
#include "render/brute_force_pass.h"
#include "render/frame_renderer.h"
#include "store/procedural_bricks.h"
#include "tests/render/testutil_gl.h"

namespace ropecast {
namespace {

// A transfer function with opaque and translucent parts over the Marschner-Lobb values (stored 0..255).
TfTable bruteForceTestTf(const BrickSourceInfo& info) {
  return TfTable::bake(
      TransferFunction({TfPoint{40, {0.8, 0.3, 0.1, 0.0}}, TfPoint{140, {0.9, 0.8, 0.3, 0.1}},
                        TfPoint{255, {0.3, 0.6, 1.0, 0.6}}}),
      info.mapping, 255);
}

struct BruteForceVariant {
  RenderMode mode;
  GradientSource gradients;
  const char* name;
};
constexpr BruteForceVariant kBruteForceVariants[] = {
    {RenderMode::Iso, GradientSource::Computed, "iso"},
    {RenderMode::Dvr, GradientSource::Computed, "dvr computed gradients"},
    {RenderMode::Dvr, GradientSource::Stored, "dvr stored gradients"},
    {RenderMode::Mip, GradientSource::Computed, "mip"}};

class BruteForceStageTest : public ::testing::TestWithParam<RenderBackend> {};

TEST_P(BruteForceStageTest, MatchesTheRopeRayCasterAtFullResolution) {
  const RenderBackend stage = GetParam();
  GlContext& gl = test::sharedGlContext();
  // 48^3 in 16^3 bricks: 27 level-0 leaves.
  const auto source = openProceduralBricks("procedural:marschner-lobb:48", 16);
  const BrickSourceInfo& info = source->info();
  const TfTable tf = bruteForceTestTf(info);
  FrameRendererConfig config;
  config.storedGradients = true;  // DVR below runs with both gradient sources
  FrameRenderer ropes(gl.info(), *source, config);
  BruteForcePass brute(*source);
  EXPECT_EQ(brute.volumeBytes(), 48u * 48u * 48u);

  for (const BruteForceVariant& v : kBruteForceVariants) {
    for (double azimuth : {30.0, 200.0}) {
      FrameRequest request;
      request.camera = orbitCamera(azimuth, 25.0, 2.2, glm::dvec3(0.0), glm::dvec3(48.0));
      request.width = request.height = 96;
      request.params.mode = v.mode;
      request.params.gradients = v.gradients;
      request.params.isoValue = 127.5;
      request.params.background = {0.1, 0.1, 0.2};
      request.params.backend = stage;  // both renderers in the same shader stage
      if (azimuth == 200.0) {          // both renderers cut alike
        request.params.crop = {glm::dvec3(5, 0, 12), glm::dvec3(40, 48, 36)};
        request.params.clipPlane = {glm::dvec3(12, 12, 24), glm::normalize(glm::dvec3(0.7, 0.7, -0.2))};
      }
      request.tf = &tf;
      request.synchronous = true;
      request.voxelsPerPixel = 0.02;  // first a coarse cut, for contrast
      ropes.render(request);
      const FloatImage coarse = ropes.readColor();
      request.voxelsPerPixel = 64.0;  // a voxel may cover 1/64 pixel at most: full resolution everywhere
      ropes.render(request);

      BruteForceFrame frame;
      frame.camera = request.camera;
      frame.params = request.params;
      frame.tf = &tf;
      frame.width = request.width;
      frame.height = request.height;
      brute.render(frame);

      const FloatImage a = ropes.readColor(), b = brute.readColor();
      const double psnr = test::psnrDb(a, b, 4);
      size_t apart = 0;  // pixels with a channel off by more than 0.05
      for (size_t p = 0; p < a.pixels.size(); p += 4)
        for (size_t c = 0; c < 4; ++c)
          if (std::abs(a.pixels[p + c] - b.pixels[p + c]) > 0.05) {
            ++apart;
            break;
          }
      std::printf("brute force vs ropes (%s), %s az %.0f: %.1f dB, %zu pixels off by > 0.05\n",
                  std::string(renderBackendName(stage)).c_str(), v.name, azimuth, psnr, apart);
      // Rounding (sample positions in cube vs world coordinates) flips a few grazing isosurface crossings and
      // DVR samples at box boundaries: a handful of pixels, never a pattern.
      EXPECT_GE(psnr, 35.0) << v.name << " az " << azimuth;
      // Stored gradients differ within half a voxel of the volume's faces: the brute-force texture clamps
      // the stored differences there, where the pool's replicated brick borders give the differences of
      // clamped values (docs/RENDERING.md's); a face seen through DVR shows it as a thin outline.
      const size_t allowed = a.width * a.height / (v.gradients == GradientSource::Stored ? 100 : 200);
      EXPECT_LT(apart, allowed) << v.name << " az " << azimuth;
      // The comparison tells levels apart: the coarse cut's image is further from brute force.
      const double coarsePsnr = test::psnrDb(coarse, b, 4);
      std::printf("  coarse cut vs brute force: %.1f dB\n", coarsePsnr);
      EXPECT_LT(coarsePsnr, psnr - 3.0);
      // Not a blank picture: the comparison must see the volume.
      double covered = 0.0;
      for (size_t i = 3; i < a.pixels.size(); i += 4) covered += a.pixels[i] > 0.05 ? 1.0 : 0.0;
      EXPECT_GT(covered, 0.1 * a.width * a.height);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Stages, BruteForceStageTest,
                         ::testing::Values(RenderBackend::Fragment, RenderBackend::Compute),
                         [](const auto& info) { return std::string(renderBackendName(info.param)); });

// The two entry points run one castBrute (shaders/brute_force_common.glsl): the same color and depth, on an
// image that is not a multiple of the workgroup size, from outside the volume and from inside it.
TEST(BruteForce, ComputeEntryPointGivesTheFragmentImage) {
  test::sharedGlContext();
  const auto source = openProceduralBricks("procedural:marschner-lobb:48", 16);
  const TfTable tf = bruteForceTestTf(source->info());
  // A pass per stage: in one, the compute image would lie over the fragment one, and pixels it missed would
  // pass for its own.
  BruteForcePass fragment(*source), compute(*source);
  Camera inside;
  inside.eye = {30.0, 20.0, 26.0};
  inside.target = {5.0, 40.0, 10.0};
  for (const BruteForceVariant& v : kBruteForceVariants)
    for (const Camera& camera : {orbitCamera(70.0, 15.0, 1.8, glm::dvec3(0.0), glm::dvec3(48.0)), inside}) {
      BruteForceFrame frame;
      frame.camera = camera;
      frame.width = 75;
      frame.height = 66;
      frame.params.mode = v.mode;
      frame.params.gradients = v.gradients;
      frame.params.isoValue = 127.5;
      frame.params.background = {0.3, 0.3, 0.3};
      frame.tf = &tf;
      frame.params.backend = RenderBackend::Fragment;
      fragment.render(frame);
      const FloatImage fragColor = fragment.readColor(), fragDepth = fragment.readDepth();
      frame.params.backend = RenderBackend::Compute;
      compute.render(frame);
      const FloatImage compColor = compute.readColor(), compDepth = compute.readDepth();
      EXPECT_GE(compute.lastRaycastMs(), 0.0);
      const char* where = camera.eye == inside.eye ? "inside" : "outside";
      const double colorApart = test::maxAbsDifference(fragColor, compColor, 4);
      const double depthApart = test::maxAbsDifference(fragDepth, compDepth, 1);
      std::printf("brute force compute vs fragment, %s, %s: color %.3g, depth %.3g apart\n", v.name, where,
                  colorApart, depthApart);
      // One program on llvmpipe; a GPU's compiler treats the two stages apart (multiply-adds fused
      // differently), which must stay below one step of an 8-bit image.
      EXPECT_LE(colorApart, test::onHardwareGpu() ? 1.0 / 255.0 : 1e-5) << v.name << ", " << where;
      EXPECT_LE(depthApart, 1e-3) << v.name << ", " << where;
      // Not a blank image: something was hit (and, from outside, something missed).
      int covered = 0, empty = 0;
      for (uint32_t y = 0; y < frame.height; ++y)
        for (uint32_t x = 0; x < frame.width; ++x) (compColor.at(x, y, 3) > 0.0f ? covered : empty)++;
      EXPECT_GT(covered, 500) << v.name << ", " << where;
      if (camera.eye != inside.eye) {
        EXPECT_GT(empty, 200) << v.name;
      }
    }
}

TEST(BruteForce, RefusesAnEntryPointItDoesNotHave) {
  test::sharedGlContext();
  const auto source = openProceduralBricks("procedural:sphere:16", 16);
  BruteForcePass brute(*source);
  BruteForceFrame frame;
  frame.camera = orbitCamera(30.0, 20.0, 3.0, glm::dvec3(0.0), glm::dvec3(16.0));
  frame.width = frame.height = 8;
  for (RenderBackend backend : {RenderBackend::Auto, RenderBackend::Brute, RenderBackend::Multipass}) {
    frame.params.backend = backend;
    try {
      brute.render(frame);
      ADD_FAILURE() << renderBackendName(backend) << " was taken";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("params.backend"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace ropecast
