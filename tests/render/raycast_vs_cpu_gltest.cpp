// The GL ray caster against its CPU mirror (reference/cpu_raycaster renderMirror: the same cut, the same
// bricks, the same sampling in double) at >= 45 dB PSNR, for iso, DVR, MIP, MinIP, AIP and slices, through
// both entry points, whole, cut by a crop box and a clip plane, and with the isosurface's caps on the cuts;
// and the isosurface of a sphere against its analytic silhouette.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <optional>
#include <utility>
#include <vector>

#include "core/transfer_function.h"
#include "reference/cpu_raycaster.h"
#include "render/raycast_pass.h"
#include "tests/render/testutil_gl.h"

namespace ropecast {
namespace {

using test::SceneSpec;

FloatImage colorOf(const CpuImage& img) {
  return {img.width, img.height, 4, img.rgba};
}
FloatImage depthOf(const CpuImage& img) {
  return {img.width, img.height, 1, img.depth};
}

// Fraction of pixels where both have a finite depth that differ by more than `tolerance`, and of pixels where
// exactly one is finite.
struct DepthAgreement {
  double farApart = 0.0, coverageMismatch = 0.0;
};
DepthAgreement compareDepth(const FloatImage& a, const FloatImage& b, double tolerance) {
  size_t apart = 0, mismatch = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    const bool fa = std::isfinite(a.pixels[i]), fb = std::isfinite(b.pixels[i]);
    if (fa != fb)
      ++mismatch;
    else if (fa && std::abs(a.pixels[i] - b.pixels[i]) > tolerance)
      ++apart;
  }
  const double n = double(a.pixels.size());
  return {double(apart) / n, double(mismatch) / n};
}

// The world points the pixels of a depth image hit, where it is finite. Depth is along the camera axis: the
// hit lies at t = depth / dot(dir, forward) on the pixel's ray.
std::vector<glm::dvec3> hitPoints(const FloatImage& depth, const RaycastFrame& frame) {
  const glm::dvec3 forward = cameraFrame(frame.camera).forward;
  std::vector<glm::dvec3> hits;
  for (uint32_t py = 0; py < frame.height; ++py)
    for (uint32_t px = 0; px < frame.width; ++px) {
      const float d = depth.pixels[size_t(py) * frame.width + px];
      if (!std::isfinite(d)) continue;
      const Ray ray = pixelRay(frame.camera, frame.width, frame.height, px, py);
      hits.push_back(ray.origin + ray.dir * (double(d) / glm::dot(ray.dir, forward)));
    }
  return hits;
}

// A non-cubic 16-bit volume of anisotropic spacing whose waves cross the isovalue 0.6 many times, in bricks
// of 8; the caller picks the cut (SceneSpec::refine).
SceneSpec wavyScene() {
  SceneSpec spec;
  spec.dims = {36, 30, 26};
  spec.spacing = {1.0, 0.8, 1.1};
  spec.brickSize = 8;
  spec.storedType = SampleType::UInt16;
  spec.value = [](glm::dvec3 x) {
    const glm::dvec3 d = x - glm::dvec3(18, 12, 14);
    return 0.5 + 0.35 * std::sin(0.31 * d.x + 0.2 * d.z) * std::cos(0.27 * d.y) - 0.004 * glm::length(d);
  };
  return spec;
}

// For a minimum intensity projection: opaque where the waves are low, fading out at their crests.
TfTable wavyMinTf() {
  return TfTable::bake(
      TransferFunction({TfPoint{0, {0.1, 0.2, 0.9, 1.0}}, TfPoint{30000, {0.9, 0.7, 0.2, 0.6}},
                        TfPoint{60000, {1.0, 1.0, 1.0, 0.0}}}),
      ValueMapping{}, 65535);
}

// A transfer function that shows the waves' crests half transparent.
TfTable wavyTf() {
  return TfTable::bake(
      TransferFunction({TfPoint{20000, {0.8, 0.2, 0.1, 0.0}}, TfPoint{36000, {0.9, 0.7, 0.2, 0.08}},
                        TfPoint{52000, {0.3, 0.5, 1.0, 0.5}}}),
      ValueMapping{}, 65535);
}

TEST(RaycastVsCpu, MatchesTheMirrorAbove45Db) {
  SceneSpec spec = wavyScene();
  spec.refine = [](const NodeKey& n) {
    return n.depth < 2 || (n.coord.x * 3 + n.coord.y + n.coord.z * 5) % 3 != 0;
  };
  // Some inside leaves empty (as refinement makes leaves the TF or isovalue cannot see): skipped, not
  // sampled.
  spec.emptyLeaf = [](const NodeKey& k) { return k.depth == 3 && (k.coord.x + k.coord.y) % 5 == 0; };
  const test::GlScene scene = test::buildScene(spec);
  ASSERT_LT(scene.minLeafDepth, scene.maxLeafDepth);
  const TfTable tf = wavyTf(), minTf = wavyMinTf();

  struct Variant {
    RenderMode mode;
    GradientSource gradients;
    double step = 0.5;
  };
  // Iso at a step above a voxel too, where a leaf's end takes a sample (docs/RENDERING.md "Isosurface").
  for (Variant v :
       {Variant{RenderMode::Iso, GradientSource::Computed},
        Variant{RenderMode::Iso, GradientSource::Computed, 2.5},
        Variant{RenderMode::Dvr, GradientSource::Computed}, Variant{RenderMode::Dvr, GradientSource::Stored},
        Variant{RenderMode::Mip, GradientSource::Computed},
        Variant{RenderMode::MinIp, GradientSource::Computed},
        Variant{RenderMode::Aip, GradientSource::Computed},
        Variant{RenderMode::Slice, GradientSource::Computed}}) {
    const RenderMode mode = v.mode;
    std::optional<FloatImage> plainWalk;  // DVR: the image of the walk without leaf batches
    for (auto [backend, leafBatch] :
         {std::pair{RenderBackend::Fragment, false}, std::pair{RenderBackend::Compute, false},
          std::pair{RenderBackend::Fragment, true}, std::pair{RenderBackend::Compute, true}}) {
      if (leafBatch && mode != RenderMode::Dvr) continue;  // the leaf batch is a form of the DVR walk only
      RaycastFrame frame;
      frame.camera = orbitCamera(35, 25, 1.9, glm::dvec3(0), glm::dvec3(36, 24, 28.6));
      frame.width = frame.height = 80;
      frame.params.mode = mode;
      frame.params.isoValue = 0.6 * 65535;
      frame.params.background = {0.05, 0.1, 0.2};
      frame.params.backend = backend;
      frame.params.gradients = v.gradients;
      frame.params.stepVoxels = v.step;
      frame.tf = mode == RenderMode::MinIp ? &minTf : &tf;
      // A slice through the center facing the camera, oblique to the axes and the leaves.
      if (mode == RenderMode::Slice)
        frame.params.clipPlane = {glm::dvec3(18, 12, 14.3), glm::normalize(glm::dvec3(0.7, 0.5, 0.5))};
      // The projections skip the leaves that cannot change them.
      const std::vector<float> bounds = scene.leafBounds(mode);
      frame.leafMaxima = bounds;
      RaycastPass pass;
      pass.setDvrLeafBatch(leafBatch);
      test::renderScene(pass, scene, frame);
      const FloatImage glColor = pass.readColor(), glDepth = pass.readDepth();
      if (!leafBatch && backend == RenderBackend::Fragment) plainWalk = glColor;
      if (leafBatch) {  // the same samples in the same order as the plain walk
        ASSERT_TRUE(plainWalk);
        EXPECT_GE(test::psnrDb(glColor, *plainWalk, 4), 90.0) << "leaf batch vs plain walk";
      }

      const CpuImage cpu = renderMirror(scene.index, scene.bricks, scene.info, test::cpuInputOf(frame));

      const std::string what =
          std::string(mode != RenderMode::Dvr                 ? renderModeName(mode)
                      : v.gradients == GradientSource::Stored ? "dvr stored gradients"
                                                              : "dvr computed gradients") +
          " step " + std::to_string(v.step) +
          (backend == RenderBackend::Fragment ? " fragment" : " compute") + (leafBatch ? " leaf batch" : "");
      const double psnr = test::psnrDb(glColor, colorOf(cpu), 3);
      std::printf("%s: PSNR %.1f dB vs the CPU mirror\n", what.c_str(), psnr);
      EXPECT_GE(psnr, 45.0) << what;
      // A mean or a slice's one sample has no threshold to flip: on llvmpipe the images agree to rounding (a
      // leaf corner's sample left out shows at 75 dB).
      if ((mode == RenderMode::Aip || mode == RenderMode::Slice) && !test::onHardwareGpu())
        EXPECT_GE(psnr, 100.0) << what;
      // Hardware filtering weights are fixed point (8 fractional bits on NVIDIA), so a grazing ray's sample
      // near the isovalue may land on the other side and a silhouette pixel flip; the coverage check below
      // bounds how many.
      EXPECT_GE(test::psnrDb(glColor, colorOf(cpu), 4), test::onHardwareGpu() ? 38.0 : 45.0)
          << what << " (with alpha)";
      const DepthAgreement d = compareDepth(glDepth, depthOf(cpu), 0.05);
      EXPECT_LE(d.farApart, 0.01) << what;
      EXPECT_LE(d.coverageMismatch, 0.01) << what;
      // The image is not trivially the background.
      int covered = 0;
      for (uint32_t i = 0; i < frame.width * frame.height; ++i) covered += glColor.pixels[i * 4 + 3] > 0.0f;
      EXPECT_GT(covered, 1000) << what;
    }
  }
}

// --iso-color, --material and --shading off reach the shaders as the mirror applies them, and change the
// image; unlit DVR takes no gradient, so stored gradients are not asked for.
TEST(RaycastVsCpu, LightingMatchesTheMirror) {
  SceneSpec spec = wavyScene();
  spec.refine = [](const NodeKey& n) { return n.depth < 2 || (n.coord.x + n.coord.y) % 2 == 0; };
  const test::GlScene scene = test::buildScene(spec);
  const TfTable tf = wavyTf();
  LightingParams material;
  material.isoBaseColor = {0.2, 0.5, 0.9};
  material.ambient = 0.3;
  material.diffuse = 0.5;
  material.specular = 0.6;
  material.shininess = 8.0;
  LightingParams unlit;
  unlit.dvrShading = false;
  struct Case {
    const char* name;
    RenderMode mode;
    LightingParams lighting;
  };
  RenderParams unlitParams;
  unlitParams.mode = RenderMode::Dvr;
  unlitParams.gradients = GradientSource::Stored;
  unlitParams.lighting = unlit;
  EXPECT_FALSE(usesStoredGradients(unlitParams));
  for (const Case& c : {Case{"iso, a material", RenderMode::Iso, material},
                        Case{"dvr, a material", RenderMode::Dvr, material},
                        Case{"dvr, no shading", RenderMode::Dvr, unlit}}) {
    RaycastFrame frame;
    frame.camera = orbitCamera(35, 25, 1.9, glm::dvec3(0), glm::dvec3(36, 24, 28.6));
    frame.width = frame.height = 80;
    frame.params.mode = c.mode;
    frame.params.isoValue = 0.6 * 65535;
    frame.tf = &tf;
    RaycastPass pass;
    test::renderScene(pass, scene, frame);
    const FloatImage lit = pass.readColor();
    frame.params.lighting = c.lighting;
    test::renderScene(pass, scene, frame);
    const FloatImage glColor = pass.readColor();
    const CpuImage cpu = renderMirror(scene.index, scene.bricks, scene.info, test::cpuInputOf(frame));
    EXPECT_GE(test::psnrDb(glColor, colorOf(cpu), 4), test::onHardwareGpu() ? 38.0 : 45.0) << c.name;
    EXPECT_LT(test::psnrDb(glColor, lit, 3), 35.0) << c.name << ": the lighting changed nothing";
  }
}

// With --crop and --clip-plane the rays sample only inside the crop box and on the plane's kept side (with
// --slab, within its slab; a slice's, on the plane): the GL image is the mirror's, every hit lies there, and
// the cut took something away.
TEST(RaycastVsCpu, ACropBoxAndAClipPlaneMatchTheMirrorAndHitsOnlyWhereTheyKeep) {
  SceneSpec spec = wavyScene();
  spec.refine = [](const NodeKey& n) { return n.depth < 2 || (n.coord.x + n.coord.y + n.coord.z) % 2 == 0; };
  const test::GlScene scene = test::buildScene(spec);
  const TfTable tf = wavyTf(), minTf = wavyMinTf();
  CropBox crop;
  crop.lo = {7, 0, 5};  // voxels 7..29, 0..17, 5..25
  crop.hi = {30, 18, 26};
  // Through the volume's center, oblique, keeping the side away from the camera's azimuth.
  const ClipPlane plane{glm::dvec3(18, 12, 14.3), glm::normalize(glm::dvec3(-1.0, -0.6, 0.3))};
  struct Cut {
    const char* name;
    bool crop, plane;
    double slab = 0.0;  // --slab about the plane
  };
  for (const Cut cut : {Cut{"crop", true, false}, Cut{"plane", false, true},
                        Cut{"crop and plane", true, true}, Cut{"slab", false, true, 7.0}})
    for (RenderMode mode : {RenderMode::Iso, RenderMode::Dvr, RenderMode::Mip, RenderMode::MinIp,
                            RenderMode::Aip, RenderMode::Slice}) {
      if (mode == RenderMode::Slice && (!cut.plane || cut.slab > 0.0)) continue;  // a slice: a plane, no slab
      for (RenderBackend backend : {RenderBackend::Fragment, RenderBackend::Compute}) {
        RaycastFrame frame;
        frame.camera = orbitCamera(35, 25, 1.9, glm::dvec3(0), glm::dvec3(36, 24, 28.6));
        frame.width = frame.height = 80;
        frame.params.mode = mode;
        frame.params.isoValue = 0.6 * 65535;
        frame.params.backend = backend;
        frame.tf = mode == RenderMode::MinIp ? &minTf : &tf;
        const std::vector<float> bounds = scene.leafBounds(mode);
        frame.leafMaxima = bounds;
        RaycastPass pass;
        test::renderScene(pass, scene, frame);
        const FloatImage whole = pass.readColor();
        if (cut.crop) frame.params.crop = crop;
        if (cut.plane) frame.params.clipPlane = plane;
        frame.params.clipPlane.slab = cut.slab;
        test::renderScene(pass, scene, frame);
        const FloatImage glColor = pass.readColor(), glDepth = pass.readDepth();

        const CpuImage cpu = renderMirror(scene.index, scene.bricks, scene.info, test::cpuInputOf(frame));
        const std::string what = std::string(cut.name) + " " + std::string(renderModeName(mode)) +
                                 (backend == RenderBackend::Fragment ? " fragment" : " compute");
        const WorldBox box = cut.crop ? WorldBox{crop.lo * spec.spacing, crop.hi * spec.spacing}
                                      : WorldBox{glm::dvec3(0.0), glm::dvec3(spec.dims) * spec.spacing};
        EXPECT_GE(test::psnrDb(glColor, colorOf(cpu), 4), test::onHardwareGpu() ? 38.0 : 45.0) << what;
        const DepthAgreement d = compareDepth(glDepth, depthOf(cpu), 0.05);
        EXPECT_LE(d.farApart, 0.01) << what;
        EXPECT_LE(d.coverageMismatch, 0.01) << what;
        EXPECT_LT(test::psnrDb(glColor, whole, 4), 30.0) << what << ": the crop changed nothing";

        const std::vector<glm::dvec3> hits = hitPoints(glDepth, frame);
        int outside = 0;
        for (const glm::dvec3& hit : hits)
          outside += glm::any(glm::lessThan(hit, box.lo - 0.05)) ||
                     glm::any(glm::greaterThan(hit, box.hi + 0.05)) ||
                     (cut.plane && glm::dot(plane.normal, hit - plane.point) < -0.05 - 0.5 * cut.slab) ||
                     (cut.slab > 0.0 && glm::dot(plane.normal, hit - plane.point) > 0.05 + 0.5 * cut.slab) ||
                     (mode == RenderMode::Slice && glm::dot(plane.normal, hit - plane.point) > 0.05);
        EXPECT_GT(hits.size(), 300u) << what;
        EXPECT_EQ(outside, 0) << what;
      }
    }
}

// Isosurface caps (docs/RENDERING.md "Caps"): where the crop box or the clip plane cuts a ball, the rays that
// enter inside it stop on the cut, shaded with its normal; in the ball's middle from Solid leaves, which have
// no brick. Fragment and compute images are the mirror's; the caps lie on the cuts; the image equals the one
// of the same cut with bricks in place of the Solid leaves; and without caps the ball is open.
TEST(RaycastVsCpu, CapsCloseTheSurfaceOnTheCutsAsTheMirrorDoes) {
  SceneSpec spec;
  spec.dims = {40, 36, 32};
  spec.spacing = {1.0, 0.9, 1.1};
  spec.brickSize = 8;
  const glm::dvec3 center = glm::dvec3(20, 18, 16) * spec.spacing;
  spec.value = [center](glm::dvec3 x) { return 0.9 - 0.3 * glm::length(x - center) / 16.0; };
  const double iso = 0.6;
  spec.solidAbove = iso;
  const test::GlScene scene = test::buildScene(spec);
  spec.solidAbove.reset();
  const test::GlScene bricksOnly = test::buildScene(spec);
  ASSERT_GT(scene.solidLeaves, 2u);
  ASSERT_EQ(bricksOnly.solidLeaves, 0u);

  CropBox crop;
  crop.lo = {4, 0, 3};
  crop.hi = {40, 18, 26};  // the upper y face through the middle, facing the camera
  const ClipPlane plane{center, glm::normalize(glm::dvec3(-1.0, -0.6, 0.3))};
  for (const bool usePlane : {false, true})
    for (RenderBackend backend : {RenderBackend::Fragment, RenderBackend::Compute}) {
      const std::string what = std::string(usePlane ? "plane" : "crop") +
                               (backend == RenderBackend::Fragment ? " fragment" : " compute");
      RaycastFrame frame;
      frame.camera = orbitCamera(35, 25, 1.9, glm::dvec3(0), glm::dvec3(spec.dims) * spec.spacing);
      frame.width = frame.height = 80;
      frame.params.isoValue = iso * 65535;
      frame.params.backend = backend;
      if (usePlane)
        frame.params.clipPlane = plane;
      else
        frame.params.crop = crop;
      RaycastPass pass;
      test::renderScene(pass, scene, frame);
      const FloatImage glColor = pass.readColor(), glDepth = pass.readDepth();
      test::renderScene(pass, bricksOnly, frame);
      const FloatImage bricksColor = pass.readColor();
      frame.params.isoCaps = false;
      test::renderScene(pass, scene, frame);
      const FloatImage openColor = pass.readColor();
      frame.params.isoCaps = true;

      const CpuImage cpu = renderMirror(scene.index, scene.bricks, scene.info, test::cpuInputOf(frame));
      EXPECT_GE(test::psnrDb(glColor, colorOf(cpu), 4), test::onHardwareGpu() ? 38.0 : 45.0) << what;
      const DepthAgreement d = compareDepth(glDepth, depthOf(cpu), 0.05);
      EXPECT_LE(d.farApart, 0.01) << what;
      EXPECT_LE(d.coverageMismatch, 0.01) << what;
      EXPECT_GE(test::psnrDb(glColor, bricksColor, 4), 45.0) << what << ": Solid leaves against their bricks";
      EXPECT_LT(test::psnrDb(glColor, openColor, 4), 30.0) << what << ": the caps changed nothing";

      // The caps: many hits on the cut, none of them outside the ball.
      int onCut = 0;
      for (const glm::dvec3& hit : hitPoints(glDepth, frame)) {
        const double offCut = usePlane ? std::abs(glm::dot(plane.normal, hit - plane.point))
                                       : std::abs(hit.y - crop.hi.y * spec.spacing.y);
        if (offCut > 0.05) continue;
        ++onCut;
        EXPECT_LE(glm::length(hit - center), 16.0 * 1.05)
            << what << " at " << hit.x << "," << hit.y << "," << hit.z;
      }
      EXPECT_GT(onCut, 300) << what;
    }
}

// A sphere of radius r as the isosurface v = 0.5 of v = 0.5 + k (r - |x - c|): its silhouette covers exactly
// the pixels whose ray passes within r of c. The covered pixel count must match within 1%.
TEST(RaycastVsCpu, SphereSilhouetteArea) {
  SceneSpec spec;
  spec.dims = glm::u32vec3(40);
  spec.brickSize = 8;
  const glm::dvec3 center(20.0, 20.0, 20.0);
  const double radius = 13.0;
  spec.value = [=](glm::dvec3 x) { return 0.5 + 0.02 * (radius - glm::length(x - center)); };
  spec.refine = [](const NodeKey& n) { return n.depth < 2 || (n.coord.x + n.coord.y + n.coord.z) % 2 == 0; };
  const test::GlScene scene = test::buildScene(spec);
  for (RenderBackend backend : {RenderBackend::Fragment, RenderBackend::Compute}) {
    RaycastFrame frame;
    frame.camera = orbitCamera(40, 30, 1.9, glm::dvec3(0), glm::dvec3(40));
    frame.width = frame.height = 128;
    frame.params.mode = RenderMode::Iso;
    frame.params.isoValue = 0.5 * 65535;
    frame.params.backend = backend;
    RaycastPass pass;
    test::renderScene(pass, scene, frame);
    const FloatImage color = pass.readColor();
    int covered = 0, analytic = 0;
    for (uint32_t py = 0; py < frame.height; ++py)
      for (uint32_t px = 0; px < frame.width; ++px) {
        covered += color.at(px, py, 3) > 0.5f;
        const Ray ray = pixelRay(frame.camera, frame.width, frame.height, px, py);
        const glm::dvec3 toCenter = center - ray.origin;
        const double along = glm::dot(toCenter, ray.dir);
        analytic += glm::length(toCenter - along * ray.dir) < radius;
      }
    ASSERT_GT(analytic, 3000);
    std::printf("silhouette: %d pixels covered, %d analytic\n", covered, analytic);
    EXPECT_NEAR(double(covered), double(analytic), 0.01 * analytic)
        << (backend == RenderBackend::Fragment ? "fragment" : "compute");
  }
}

}  // namespace
}  // namespace ropecast
