// The isosurface at brick borders with a step of two voxels (docs/RENDERING.md "Isosurface"): the sphere cut
// into bricks of 8 against the same sphere in one brick of 64, which has no brick border to cross and draws
// what the brute-force pass draws. With the step larger than about a voxel, the sample before a crossing may
// lie in the previous leaf, farther from the hit's brick than its replicated border reaches; refining and
// shading there through the hit's brick read clamped texels (about 39.5 dB here, wrong normals along the
// sphere's outline). The refinement stays within one brick, for each backend that walks leaves. The small
// bricks also take a sample at each leaf's end, so they find grazing crossings that one brick steps over:
// they differ from it there, and are at least as close as it is to the image of a fine step.
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <string>

#include "render/frame_renderer.h"
#include "store/procedural_bricks.h"
#include "testutil_gl.h"

namespace ropecast {
namespace {

using test::psnrDb;
using test::sharedGlContext;

// The sphere rendered with bricks of `brickSize`, synchronously (the whole cut at full resolution).
FloatImage renderSphere(uint32_t brickSize, RenderBackend backend, double stepVoxels) {
  const std::unique_ptr<ProceduralBricks> source = openProceduralBricks("procedural:sphere:64", brickSize);
  const BrickSourceInfo& info = source->info();
  FrameRendererConfig config;
  config.gpuBudgetBytes = 64ull << 20;
  FrameRenderer renderer(sharedGlContext().info(), *source, config);

  FrameRequest request;
  request.width = 256;
  request.height = 256;
  request.synchronous = true;
  request.params.mode = RenderMode::Iso;
  request.params.backend = backend;
  request.params.stepVoxels = stepVoxels;
  const double lo = info.volume.valueMin.value_or(info.mapping.toData(0));
  const double hi = info.volume.valueMax.value_or(info.mapping.toData(storedMaxOf(info.storedType)));
  request.params.isoValue = 0.5 * (lo + hi);
  request.camera.eye = {32.0, -40.0, 40.0};
  request.camera.target = {32.0, 32.0, 32.0};
  const FrameStats stats = renderer.render(request);
  EXPECT_EQ(stats.backend, backend);
  return renderer.readColor();
}

struct BorderCase {
  RenderBackend backend;
  double stepVoxels;
  // Below what refining within one brick reaches, above what reading clamped texels gives.
  double minDb;
};

std::string backendName(RenderBackend b) {
  return b == RenderBackend::Fragment ? "fragment" : b == RenderBackend::Compute ? "compute" : "multipass";
}

class IsoBrickBorderTest : public ::testing::TestWithParam<BorderCase> {};

TEST_P(IsoBrickBorderTest, SmallBricksMatchOneBrick) {
  const BorderCase& c = GetParam();
  const FloatImage oneBrick = renderSphere(64, RenderBackend::Fragment, c.stepVoxels);
  const FloatImage bricks = renderSphere(8, c.backend, c.stepVoxels);
  static const FloatImage fineStep = renderSphere(64, RenderBackend::Fragment, 0.125);
  const double db = psnrDb(oneBrick, bricks);
  const double oneBrickToFine = psnrDb(fineStep, oneBrick), bricksToFine = psnrDb(fineStep, bricks);
  std::printf("  %s, step %.1f: %.1f dB; against step 0.125: one brick %.1f dB, bricks %.1f dB\n",
              backendName(c.backend).c_str(), c.stepVoxels, db, oneBrickToFine, bricksToFine);
  EXPECT_GE(db, c.minDb) << backendName(c.backend) << ", step " << c.stepVoxels;
  EXPECT_GE(bricksToFine, oneBrickToFine - 0.05) << backendName(c.backend) << ", step " << c.stepVoxels;
}

INSTANTIATE_TEST_SUITE_P(IsoBrickBorder, IsoBrickBorderTest,
                         ::testing::Values(BorderCase{RenderBackend::Fragment, 2.0, 45.0},
                                           BorderCase{RenderBackend::Compute, 2.0, 45.0},
                                           BorderCase{RenderBackend::Multipass, 2.0, 45.0},
                                           BorderCase{RenderBackend::Fragment, 0.5, 90.0}));

}  // namespace
}  // namespace ropecast
