// The multi-pass block renderer (render/multipass_pass.h) against the single-pass ray caster on the same cut:
// one FrameRenderer renders a synchronous frame with the fragment entry point, then the same request with
// --backend multipass (the same cut, the same pool slots), for every mode, procedural sphere, Menger sponge
// and noise (the CT-like one), from outside the volume and from inside it, and with rays along the faces two
// boxes share. Both take the same samples of the same global grid in the same order, so the images agree far
// above the 40 dB asked (identical here); what could differ sits on block silhouettes, where a pixel's
// coverage by the rasterized box and its ray's clip to the box disagree by rounding, which MultipassPass
// prevents by rasterizing each box slightly larger.
#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "core/transfer_function.h"
#include "render/frame_renderer.h"
#include "store/procedural_bricks.h"
#include "testutil_gl.h"

namespace ropecast {
namespace {

using test::psnrDb;
using test::sharedGlContext;

struct MultipassCase {
  std::string volume;  // procedural spec
  RenderMode mode = RenderMode::Iso;
  bool inside = false;  // the eye inside the volume box
  // The eye on the planes of brick faces (the volume's middle planes), an odd image size: the middle row's
  // and column's rays run along faces two boxes share, and only one of them may draw each.
  bool facePlanes = false;
  // --crop (voxels 7..39, 3..49, 9..44) and --clip-plane (oblique, through the volume's center): the leaves
  // they cut are drawn in part.
  bool cropped = false;
  // The cuts pass through the isosurface's inside, where leaves wholly inside it are Solid: caps drawn
  // without bricks, each such leaf a pass of its own. The test asks that there are some.
  bool solid = false;
};

std::string multipassCaseName(const MultipassCase& c) {
  return c.volume + " " + std::string(renderModeName(c.mode)) + (c.inside ? " inside" : " outside") +
         (c.facePlanes ? " face planes" : "") + (c.cropped ? " cropped" : "");
}

class MultipassTest : public ::testing::TestWithParam<MultipassCase> {};

TEST_P(MultipassTest, MatchesTheSinglePassOnTheSameCut) {
  const MultipassCase& c = GetParam();
  GlContext& gl = sharedGlContext();
  const std::unique_ptr<ProceduralBricks> source = openProceduralBricks(c.volume, 8);
  const BrickSourceInfo& info = source->info();

  FrameRendererConfig config;
  config.gpuBudgetBytes = 32ull << 20;
  config.storedGradients = c.mode == RenderMode::Dvr;
  FrameRenderer renderer(gl.info(), *source, config);

  FrameRequest request;
  request.width = 80;
  request.height = 64;
  request.synchronous = true;
  request.params.mode = c.mode;
  request.params.gradients = GradientSource::Stored;
  const double lo = info.volume.valueMin.value_or(info.mapping.toData(0));
  const double hi = info.volume.valueMax.value_or(info.mapping.toData(storedMaxOf(info.storedType)));
  request.params.isoValue = 0.5 * (lo + hi);
  request.params.background = {0.1, 0.2, 0.3};
  if (c.cropped) {
    request.params.crop = {glm::dvec3(7, 3, 9), glm::dvec3(40, 50, 45)};
    request.params.clipPlane = {0.5 * info.volume.worldMax(), glm::normalize(glm::dvec3(-1.0, 0.4, -0.5))};
  } else if (c.mode == RenderMode::Slice) {
    // Through the center, facing the camera's side, oblique to the leaves.
    request.params.clipPlane = {0.5 * info.volume.worldMax(), glm::normalize(glm::dvec3(0.6, 0.5, 0.6))};
  }
  std::optional<TfTable> tf;
  if (c.mode == RenderMode::MinIp) {
    // Opaque over the whole range: a ray's smallest value shows wherever it lies.
    tf = TfTable::bake(
        TransferFunction({TfPoint{lo, {0.0, 0.0, 0.0, 1.0}}, TfPoint{hi, {1.0, 1.0, 1.0, 1.0}}}),
        info.mapping, storedMaxOf(info.storedType));
    request.tf = &*tf;
  } else if (usesTransferFunction(c.mode)) {
    const std::string preset = showsOneValue(c.mode) ? "gray" : "ct-soft";
    tf = TfTable::bake(TransferFunction::fromSpec(preset, tfDataRangeFor(info)), info.mapping,
                       storedMaxOf(info.storedType));
    request.tf = &*tf;
  }
  const glm::dvec3 boxMax = glm::dvec3(info.volume.dims) * info.volume.spacing;
  request.camera = c.inside ? orbitCamera(35.0, 25.0, 0.35, glm::dvec3(0.0), boxMax, 60.0)
                            : orbitCamera(35.0, 25.0, 1.6, glm::dvec3(0.0), boxMax, 40.0);
  if (c.facePlanes) {
    request.width = request.height = 81;
    request.camera = orbitCamera(0.0, 0.0, 1.6, glm::dvec3(0.0), boxMax, 40.0);
  }

  request.params.backend = RenderBackend::Fragment;
  const FrameStats single = renderer.render(request);
  const FloatImage singleColor = renderer.readColor();
  const FloatImage singleDepth = renderer.readDepth();
  const std::vector<CutLeaf> singleCut = renderer.lastCut().leaves;

  request.params.backend = RenderBackend::Multipass;
  renderer.prepare(request);
  const FrameStats multi = renderer.render(request);
  const FloatImage multiColor = renderer.readColor();
  const FloatImage multiDepth = renderer.readDepth();

  // The same cut, drawn one data or solid leaf per pass.
  ASSERT_EQ(renderer.lastCut().leaves.size(), singleCut.size());
  uint64_t dataLeaves = 0, solidLeaves = 0;
  for (size_t i = 0; i < singleCut.size(); ++i) {
    EXPECT_EQ(renderer.lastCut().leaves[i].coord, singleCut[i].coord);
    EXPECT_EQ(renderer.lastCut().leaves[i].kind, singleCut[i].kind);
    dataLeaves += singleCut[i].kind == LeafKind::Data;
    solidLeaves += singleCut[i].kind == LeafKind::Solid;
  }
  EXPECT_EQ(single.backend, RenderBackend::Fragment);
  EXPECT_EQ(multi.backend, RenderBackend::Multipass);
  EXPECT_EQ(multi.stage, RenderBackend::Fragment);  // its blocks are drawn
  EXPECT_EQ(single.drawCalls, 1u);
  EXPECT_EQ(multi.drawCalls, dataLeaves + solidLeaves);
  EXPECT_EQ(multi.glDrawCalls, 2 * (dataLeaves + solidLeaves) + 1);
  EXPECT_EQ(single.leavesSolid, solidLeaves);
  EXPECT_GT(dataLeaves, 20u);
  if (c.solid) EXPECT_GT(solidLeaves, 0u) << multipassCaseName(c);

  // Color (with the background under it) and coverage.
  const double colorDb = psnrDb(singleColor, multiColor, 4);
  EXPECT_GE(colorDb, 40.0) << multipassCaseName(c);
  // Depth: the same hits and last opaque samples, compared where both have one.
  uint64_t both = 0, differ = 0, coverageDiffers = 0;
  for (size_t i = 0; i < singleDepth.pixels.size(); ++i) {
    const float a = singleDepth.pixels[i], b = multiDepth.pixels[i];
    if (std::isinf(a) != std::isinf(b)) ++coverageDiffers;
    if (std::isinf(a) || std::isinf(b)) continue;
    ++both;
    if (std::abs(a - b) > 1e-3f * std::max(1.0f, std::abs(a))) ++differ;
  }
  EXPECT_GT(both, 0u) << multipassCaseName(c);
  if (c.facePlanes) {
    // The middle row and column inside the volume's silhouette: a ray drawn twice is far brighter.
    float worst = 0.0f;
    const uint32_t middle = request.width / 2;
    for (uint32_t i = 0; i < request.width; ++i)
      for (const uint32_t pixel : {middle * request.width + i, i * request.width + middle})
        for (uint32_t ch = 0; ch < 3; ++ch)
          worst = std::max(worst,
                           std::abs(singleColor.pixels[4 * pixel + ch] - multiColor.pixels[4 * pixel + ch]));
    EXPECT_LE(worst, 2.0f / 255.0f) << multipassCaseName(c);
  }
  EXPECT_LE(differ + coverageDiffers, singleDepth.pixels.size() / 100) << multipassCaseName(c);
  std::printf(
      "  %s: %llu data leaves, %llu solid, color %.1f dB, depth: %llu of %llu differ, %llu differ in "
      "coverage\n",
      multipassCaseName(c).c_str(), (unsigned long long)dataLeaves, (unsigned long long)solidLeaves, colorDb,
      (unsigned long long)differ, (unsigned long long)both, (unsigned long long)coverageDiffers);
}

INSTANTIATE_TEST_SUITE_P(
    Multipass, MultipassTest,
    ::testing::Values(MultipassCase{"procedural:sphere:64", RenderMode::Iso, false},
                      MultipassCase{"procedural:sphere:64", RenderMode::Dvr, false},
                      MultipassCase{"procedural:menger:54", RenderMode::Iso, false},
                      MultipassCase{"procedural:menger:54", RenderMode::Dvr, false},
                      MultipassCase{"procedural:noise:48", RenderMode::Iso, false},
                      MultipassCase{"procedural:noise:48", RenderMode::Dvr, false},
                      MultipassCase{"procedural:sphere:64", RenderMode::Iso, true},
                      MultipassCase{"procedural:noise:48", RenderMode::Dvr, true},
                      MultipassCase{"procedural:noise:48", RenderMode::Dvr, false, true},
                      MultipassCase{"procedural:menger:54", RenderMode::Iso, false, false, true},
                      MultipassCase{"procedural:sphere:64", RenderMode::Iso, false, false, true, true},
                      MultipassCase{"procedural:noise:48", RenderMode::Dvr, true, false, true},
                      MultipassCase{"procedural:menger:54", RenderMode::Mip, false},
                      MultipassCase{"procedural:noise:48", RenderMode::Mip, false},
                      MultipassCase{"procedural:sphere:64", RenderMode::Mip, false, false, true},
                      MultipassCase{"procedural:noise:48", RenderMode::MinIp, false},
                      MultipassCase{"procedural:sphere:64", RenderMode::MinIp, false, false, true},
                      MultipassCase{"procedural:noise:48", RenderMode::Aip, false},
                      MultipassCase{"procedural:sphere:64", RenderMode::Aip, true},
                      MultipassCase{"procedural:noise:48", RenderMode::Aip, false, false, true},
                      MultipassCase{"procedural:noise:48", RenderMode::Slice, false},
                      MultipassCase{"procedural:sphere:64", RenderMode::Slice, true},
                      MultipassCase{"procedural:marschner-lobb:48", RenderMode::Slice, false, false, true}),
    [](const ::testing::TestParamInfo<MultipassCase>& info) {
      std::string name = multipassCaseName(info.param).substr(std::string("procedural:").size());
      for (char& ch : name)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
      return name;
    });

}  // namespace
}  // namespace ropecast
