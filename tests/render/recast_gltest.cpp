// FrameRequest::recastChangesOnly: a frame on the last drawn view casts only the pixels whose rays meet a
// leaf that changed, and its image is exactly what casting the whole image of its cut gives (isosurface and
// DVR, fragment and compute entry points, occlusion queries and feedback on); progressive frames so cast
// fewer pixels, and the view converges to the image the whole frames converge to.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <span>
#include <string>

#include "core/error.h"
#include "core/transfer_function.h"
#include "index/rope_index.h"
#include "render/frame_renderer.h"
#include "store/procedural_bricks.h"
#include "testutil_gl.h"

namespace ropecast {
namespace {

constexpr uint32_t kRecastImageSize = 96;

FrameRequest recastViewRequest(const BrickSourceInfo& info, RenderMode mode, RenderBackend backend) {
  FrameRequest request;
  request.width = request.height = kRecastImageSize;
  request.params.mode = mode;
  request.params.backend = backend;
  request.params.isoValue = 140.0;
  request.params.gradients = GradientSource::Computed;
  request.camera = orbitCamera(35.0, 25.0, 1.6, glm::dvec3(0.0), glm::dvec3(info.volume.dims), 40.0);
  return request;
}

// Casts the whole image of the renderer's last cut, with its pool, through a pass of its own.
class WholeCast {
 public:
  WholeCast() : index_(kRopeTexelComponents, test::sharedGlContext().info().maxTextureBufferTexels) {}
  FloatImage color(const FrameRenderer& renderer, const BrickSource& source, const FrameRequest& request) {
    builder_.build(renderer.lastCut(), rope_);
    index_.upload(std::span<const uint32_t>(reinterpret_cast<const uint32_t*>(rope_.texels.data()),
                                            rope_.texels.size() * kRopeTexelComponents));
    RaycastFrame frame;
    frame.pool = &renderer.pool();
    frame.index = &index_;
    frame.camera = request.camera;
    frame.volume = VolumeGeometry::of(source.info());
    frame.params = request.params;
    frame.tf = request.tf;
    frame.width = request.width;
    frame.height = request.height;
    pass_.render(frame);
    return pass_.readColor();
  }

 private:
  RaycastPass pass_;
  IndexTexture index_;
  RopeIndexBuilder builder_;
  RopeIndex rope_;
};

struct RecastRun {
  FloatImage color;
  bool converged = false;
  uint32_t frames = 0;
  // Drawn frames that cast some pixels but fewer than the image has (a frame whose cut holds no brick, as a
  // cold start's first, casts none and is not one).
  uint32_t partialFrames = 0;
};

// From a cold cache to convergence; with `check`, every drawn frame's image is compared with a whole cast.
RecastRun convergeFromCold(const BrickSource& source, FrameRequest request, uint64_t gpuBudgetBytes,
                           bool recast, WholeCast* check) {
  FrameRendererConfig config;
  config.gpuBudgetBytes = gpuBudgetBytes;
  // A few nodes' bricks a frame: the cut changes in a few places at a time, whenever the reads come in.
  config.uploadBudgetBytes = 96 * source.brickBytes();
  FrameRenderer renderer(test::sharedGlContext().info(), source, config);
  request.recastChangesOnly = recast;
  request.keepConvergedImage = true;
  RecastRun run;
  for (; run.frames < 200 && !run.converged; ++run.frames) {
    const FrameStats stats = renderer.render(request);
    run.converged = stats.converged;
    if (!stats.drawn) continue;
    run.partialFrames +=
        stats.fragments > 0 && stats.fragments < uint64_t(kRecastImageSize) * kRecastImageSize;
    if (!check) continue;
    const FloatImage drawn = renderer.readColor();
    const FloatImage whole = check->color(renderer, source, request);
    EXPECT_EQ(drawn.pixels, whole.pixels)
        << "frame " << stats.frame << " (" << stats.fragments << " pixels cast) differs from a whole cast by "
        << test::maxAbsDifference(drawn, whole, 4);
  }
  run.color = renderer.readColor();
  return run;
}

class RecastTest : public ::testing::TestWithParam<std::tuple<RenderBackend, RenderMode>> {};

TEST_P(RecastTest, ProgressiveFramesCastLessAndDrawWhatAWholeCastDraws) {
  const auto [backend, mode] = GetParam();
  const ProceduralBricks source({ProceduralKind::Noise, 96}, 8);
  std::optional<TfTable> tf;
  FrameRequest request = recastViewRequest(source.info(), mode, backend);
  if (mode == RenderMode::Dvr) {
    tf = TfTable::bake(TransferFunction::fromSpec("ct-soft", tfDataRangeFor(source.info())),
                       source.info().mapping, 255);
    request.tf = &*tf;
  }
  // A pool smaller than the view wants, whose slots the answers free for finer bricks.
  const uint64_t tightBudget = 24ull << 20;
  const RecastRun whole = convergeFromCold(source, request, tightBudget, false, nullptr);
  WholeCast check;
  const RecastRun recast = convergeFromCold(source, request, tightBudget, true, &check);
  ASSERT_TRUE(whole.converged);
  ASSERT_TRUE(recast.converged) << "not converged after " << recast.frames << " frames";
  // How many frames each run takes depends on the reads against the frames: the runs are compared by
  // their images, not by frames or pixels.
  EXPECT_GT(recast.partialFrames, 0u);
  EXPECT_EQ(whole.partialFrames, 0u) << "a frame cast in part without FrameRequest::recastChangesOnly";
  EXPECT_GE(test::psnrDb(recast.color, whole.color), 40.0);
}

INSTANTIATE_TEST_SUITE_P(BackendsAndModes, RecastTest,
                         ::testing::Combine(::testing::Values(RenderBackend::Fragment,
                                                              RenderBackend::Compute),
                                            ::testing::Values(RenderMode::Iso, RenderMode::Dvr)));

// A frame that draws the converged image again casts nothing; one on another view casts it whole.
TEST(Recast, AStillConvergedViewCastsNothingAndAnotherViewCastsAll) {
  const ProceduralBricks source({ProceduralKind::Noise, 96}, 8);
  FrameRenderer renderer(test::sharedGlContext().info(), source, FrameRendererConfig{});
  FrameRequest request = recastViewRequest(source.info(), RenderMode::Iso, RenderBackend::Fragment);
  request.recastChangesOnly = true;
  FrameStats stats;
  for (uint32_t frame = 0; frame < 200 && !stats.converged; ++frame) stats = renderer.render(request);
  ASSERT_TRUE(stats.converged);
  const FloatImage converged = renderer.readColor();
  stats = renderer.render(request);
  EXPECT_TRUE(stats.drawn);
  EXPECT_EQ(stats.fragments, 0u);
  EXPECT_EQ(renderer.readColor().pixels, converged.pixels);

  request.camera = orbitCamera(50.0, 25.0, 1.6, glm::dvec3(0.0), glm::dvec3(source.info().volume.dims), 40.0);
  EXPECT_EQ(renderer.render(request).fragments, uint64_t(kRecastImageSize) * kRecastImageSize);
  // The warm-up draw leaves other pixels in the targets: the next frame casts them all.
  renderer.prepare(request);
  EXPECT_EQ(renderer.render(request).fragments, uint64_t(kRecastImageSize) * kRecastImageSize);
}

// The RaycastPass tests below: a 48x48 frame of a 32^3 scene, cast in two tiles with a callback after the
// first (which puts the compute entry point's stop depths of the first tile into the depth attachment, so
// only those are compared).
constexpr uint32_t kPassImageSize = 48;
constexpr size_t kFirstTilePixels = size_t(kPassImageSize) * (kPassImageSize / 2);

RaycastFrame passFrame(RenderBackend backend, RenderMode mode) {
  RaycastFrame frame;
  frame.width = frame.height = kPassImageSize;
  frame.params.mode = mode;
  frame.params.isoValue = 0.5 * 65535.0;
  frame.params.backend = backend;
  frame.camera = orbitCamera(30.0, 20.0, 1.8, glm::dvec3(0.0), glm::dvec3(32.0));
  return frame;
}

TileSchedule twoTiles() {
  TileSchedule schedule;
  schedule.tiles = {{0, 0, kPassImageSize, kPassImageSize / 2},
                    {0, kPassImageSize / 2, kPassImageSize, kPassImageSize / 2}};
  schedule.afterFirstTile = [] {};
  return schedule;
}

// RaycastPass with TileSchedule::castOnly: the rectangles' pixels are those of a whole cast of the new frame,
// the others those of the render before (its stop depth too: the queries after the first tile test against
// it); a partial cast over an image of another size, or drawn by the other entry point, is refused.
TEST(Recast, APartialCastDrawsItsRectanglesAndKeepsTheRest) {
  test::SceneSpec spec;
  spec.dims = glm::u32vec3(32);
  spec.value = [](glm::dvec3 x) { return 0.5 + 0.4 * std::sin(0.3 * x.x) * std::cos(0.2 * x.y + 0.1 * x.z); };
  const test::GlScene scene = test::buildScene(spec);
  for (const RenderBackend backend : {RenderBackend::Fragment, RenderBackend::Compute}) {
    SCOPED_TRACE(backend == RenderBackend::Fragment ? "fragment" : "compute");
    const RaycastFrame before = passFrame(backend, RenderMode::Iso);
    RaycastFrame after = before;
    after.camera = orbitCamera(40.0, 25.0, 1.8, glm::dvec3(0.0), glm::dvec3(32.0));
    const TileSchedule whole = twoTiles();
    RaycastPass wholePass, partialPass;
    test::renderScene(wholePass, scene, before, whole);
    const FloatImage oldColor = wholePass.readColor(), oldStop = wholePass.readStopDepth();
    test::renderScene(wholePass, scene, after, whole);
    const FloatImage newColor = wholePass.readColor(), newStop = wholePass.readStopDepth();

    test::renderScene(partialPass, scene, before, whole);
    const PixelRect a{0, 0, 16, 32}, b{20, 30, 28, 18};  // each across both tiles
    TileSchedule schedule = whole;
    schedule.castOnly = std::vector<PixelRect>{a, b};
    test::renderScene(partialPass, scene, after, schedule);
    EXPECT_EQ(partialPass.lastPixelsCast(), uint64_t(16 * 32 + 28 * 18));
    const FloatImage color = partialPass.readColor(), stop = partialPass.readStopDepth();
    const auto inside = [](const PixelRect& r, uint32_t x, uint32_t y) {
      return x >= r.x && x < r.x + r.width && y >= r.y && y < r.y + r.height;
    };
    uint32_t wrong = 0;
    for (uint32_t y = 0; y < kPassImageSize; ++y)
      for (uint32_t x = 0; x < kPassImageSize; ++x) {
        const bool cast = inside(a, x, y) || inside(b, x, y);
        const size_t i = size_t(y) * kPassImageSize + x;
        for (uint32_t c = 0; c < 4; ++c)
          wrong += color.pixels[i * 4 + c] != (cast ? newColor : oldColor).pixels[i * 4 + c];
        if (backend == RenderBackend::Fragment || i < kFirstTilePixels)
          wrong += stop.pixels[i] != (cast ? newStop : oldStop).pixels[i];
      }
    EXPECT_EQ(wrong, 0u);

    RaycastFrame smaller = after;
    smaller.width = 40;
    EXPECT_THROW(test::renderScene(partialPass, scene, smaller, schedule), Error);
    RaycastFrame other = after;
    other.params.backend =
        backend == RenderBackend::Fragment ? RenderBackend::Compute : RenderBackend::Fragment;
    test::renderScene(partialPass, scene, after);
    EXPECT_THROW(test::renderScene(partialPass, scene, other, schedule), Error);
  }
}

TEST(Recast, ACutWithNothingToSampleWritesWhatMissingRaysWrite) {
  // Every leaf empty, at two levels: the rays walk the cut and sample nothing.
  test::SceneSpec spec;
  spec.dims = glm::u32vec3(32);
  spec.value = [](glm::dvec3 x) { return 0.5 + 0.4 * std::sin(0.3 * x.x) * std::cos(0.2 * x.y); };
  spec.refine = [](const NodeKey& k) { return k.depth == 0 || (k.depth == 1 && k.coord.x == 0); };
  spec.emptyLeaf = [](const NodeKey&) { return true; };
  const test::GlScene empty = test::buildScene(spec);
  ASSERT_EQ(empty.dataLeaves, 0u);
  spec.refine = {};
  spec.emptyLeaf = {};
  const test::GlScene full = test::buildScene(spec);
  const TfTable tf =
      TfTable::bake(TransferFunction({TfPoint{0, {1, 0, 0, 0}}, TfPoint{65535, {0.9, 0.8, 0.1, 0.6}}}),
                    ValueMapping{}, 65535);
  for (const RenderBackend backend : {RenderBackend::Fragment, RenderBackend::Compute})
    for (const RenderMode mode : {RenderMode::Iso, RenderMode::Dvr}) {
      SCOPED_TRACE(std::string(backend == RenderBackend::Fragment ? "fragment" : "compute") +
                   (mode == RenderMode::Iso ? ", iso" : ", dvr"));
      RaycastFrame frame = passFrame(backend, mode);
      frame.params.background = {0.2, 0.4, 0.6};
      frame.tf = &tf;
      const TileSchedule cast = twoTiles();
      RaycastPass castPass, missPass;
      test::renderScene(castPass, empty, frame, cast);
      // The other pass last drew an image with data, which the misses must replace everywhere.
      test::renderScene(missPass, full, frame, cast);
      TileSchedule misses = cast;
      bool calledBack = false;
      misses.afterFirstTile = [&] { calledBack = true; };
      misses.nothingToSample = true;
      test::renderScene(missPass, empty, frame, misses);
      EXPECT_TRUE(calledBack);
      EXPECT_EQ(missPass.lastPixelsCast(), 0u);
      EXPECT_EQ(missPass.readColor().pixels, castPass.readColor().pixels);
      EXPECT_EQ(missPass.readDepth().pixels, castPass.readDepth().pixels);
      const FloatImage stop = missPass.readStopDepth(), castStop = castPass.readStopDepth();
      const size_t compared = backend == RenderBackend::Fragment ? stop.pixels.size() : kFirstTilePixels;
      EXPECT_TRUE(std::equal(stop.pixels.begin(), stop.pixels.begin() + compared, castStop.pixels.begin()));
      // A frame cast in part after it keeps the misses' stop depths (compute: the pass's own copy of them).
      TileSchedule partial = cast;
      partial.castOnly = std::vector<PixelRect>{{0, 0, 16, 16}};
      test::renderScene(missPass, empty, frame, partial);
      test::renderScene(castPass, empty, frame, partial);
      const FloatImage keptStop = missPass.readStopDepth(), castKeptStop = castPass.readStopDepth();
      EXPECT_TRUE(std::equal(keptStop.pixels.begin(), keptStop.pixels.begin() + compared,
                             castKeptStop.pixels.begin()));
      EXPECT_EQ(missPass.readColor().pixels, castPass.readColor().pixels);
    }
}

}  // namespace
}  // namespace ropecast
