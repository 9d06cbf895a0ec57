// The GL ray caster against analytic images: a linear ramp's isosurface (a plane) and a constant volume's
// opacity, across brick borders and across leaves of different levels, from outside and inside the volume, on
// non-cubic volumes with anisotropic spacing; and the fragment and compute entry points against each other.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "core/error.h"
#include "core/transfer_function.h"
#include "render/multipass_pass.h"
#include "render/raycast_pass.h"
#include "tests/render/testutil_gl.h"

namespace ropecast {
namespace {

using test::SceneSpec;

constexpr double kInf = std::numeric_limits<double>::infinity();

// Splits the root and then a checkerboard of nodes, so the cut mixes two or three levels.
bool mixedLevels(const NodeKey& n) {
  return n.depth == 0 || (n.coord.x + n.coord.y + n.coord.z + n.depth) % 2 == 0;
}

glm::dvec3 phongIso(glm::dvec3 n, glm::dvec3 dir, const LightingParams& lp) {
  if (glm::dot(n, -dir) < 0.0) n = -n;
  const glm::dvec3 l = -dir, r = glm::reflect(-l, n);
  return lp.isoBaseColor * (lp.ambient + lp.diffuse * std::max(glm::dot(n, l), 0.0)) +
         glm::dvec3(lp.specular * std::pow(std::max(glm::dot(r, l), 0.0), lp.shininess));
}

struct PlaneCheck {
  int hits = 0, misses = 0, skipped = 0;
  // Hits whose shading is slightly off: where the crossing is found at the first sample of a finer leaf but
  // lies just before it, docs/RENDERING.md has the bisection and gradient read the finer brick, whose border
  // (2 texels) does not reach the whole gradient stencil there, so edge clamping bends the normal a little.
  // The CPU mirror does the same; only a few pixels along level changes are affected.
  int colorOutliers = 0;
};

// Renders the isosurface v = vIso of the ramp v(x) = dot(g, x) + c and checks every pixel whose analytic
// answer is clear (the plane crossing well inside the volume, or no crossing at all) against the plane.
PlaneCheck checkRampPlane(const SceneSpec& base, glm::dvec3 g, double c, double vIso, const Camera& camera,
                          RenderBackend backend, uint32_t size = 64) {
  SceneSpec spec = base;
  spec.value = [=](glm::dvec3 x) { return glm::dot(g, x) + c; };
  const test::GlScene scene = test::buildScene(spec);
  RaycastPass pass;
  RaycastFrame frame;
  frame.camera = camera;
  frame.width = frame.height = size;
  frame.params.mode = RenderMode::Iso;
  frame.params.isoValue = vIso * 65535.0;  // identity mapping of uint16 stored values
  frame.params.background = {0.1, 0.2, 0.3};
  frame.params.backend = backend;
  test::renderScene(pass, scene, frame);
  const FloatImage color = pass.readColor();
  const FloatImage depth = pass.readDepth();

  const glm::dvec3 volumeMax = glm::dvec3(spec.dims) * spec.spacing;
  const glm::dvec3 coarsestCell =
      std::ldexp(1.0, int(scene.info.layout.maxDepth - scene.minLeafDepth)) * spec.spacing;
  // Edge replication bends the field within a coarse cell of the faces: by at most this much in value, and
  // the gradient stencil reaches this far in space.
  const double bend = glm::dot(glm::abs(g), coarsestCell);
  const glm::dvec3 margin = 2.5 * coarsestCell;
  const double depthTolerance = 0.02 * std::max({coarsestCell.x, coarsestCell.y, coarsestCell.z});
  const glm::dvec3 forward = cameraFrame(camera).forward;
  PlaneCheck result;
  for (uint32_t py = 0; py < size; ++py)
    for (uint32_t px = 0; px < size; ++px) {
      const Ray ray = pixelRay(camera, size, size, px, py);
      double t0, t1;
      const bool inVolume = clipToBox(ray, volumeMax, t0, t1);
      const double slope = glm::dot(g, ray.dir);
      const double tPlane = slope != 0.0 ? (vIso - c - glm::dot(g, ray.origin)) / slope : kInf;
      const glm::dvec3 hit = ray.origin + tPlane * ray.dir;
      // f = v - vIso is linear along the ray: its extremes in the volume are at t0 and t1.
      const double f0 = glm::dot(g, ray.origin + t0 * ray.dir) + c - vIso;
      const double f1 = glm::dot(g, ray.origin + t1 * ray.dir) + c - vIso;
      const bool clearHit = inVolume && std::abs(f0) > bend && std::abs(f1) > bend && (f0 > 0) != (f1 > 0) &&
                            glm::all(glm::greaterThan(hit, margin)) &&
                            glm::all(glm::lessThan(hit, volumeMax - margin));
      const bool clearMiss =
          !inVolume || (std::abs(f0) > bend && std::abs(f1) > bend && (f0 > 0) == (f1 > 0));
      const std::string where = "pixel " + std::to_string(px) + "," + std::to_string(py);
      if (clearHit) {
        ++result.hits;
        const glm::dvec3 want = phongIso(-glm::normalize(g), ray.dir, frame.params.lighting);
        EXPECT_NEAR(depth.at(px, py, 0), tPlane * glm::dot(ray.dir, forward), depthTolerance) << where;
        double worst = 0.0;
        for (uint32_t ch = 0; ch < 3; ++ch)
          worst = std::max(worst, std::abs(color.at(px, py, ch) - want[ch]));
        EXPECT_LT(worst, 0.05) << where;
        if (worst > 4e-3) ++result.colorOutliers;
        EXPECT_EQ(color.at(px, py, 3), 1.0f) << where;
      } else if (clearMiss) {
        ++result.misses;
        EXPECT_EQ(depth.at(px, py, 0), std::numeric_limits<float>::infinity()) << where;
        EXPECT_NEAR(color.at(px, py, 0), 0.1, 1e-6) << where;
        EXPECT_EQ(color.at(px, py, 3), 0.0f) << where;
      } else {
        ++result.skipped;
      }
    }
  EXPECT_LE(result.colorOutliers, result.hits / 50 + 1);
  return result;
}

TEST(Raycast, RampIsosurfaceAcrossBricksAndLevels) {
  SceneSpec spec;
  spec.dims = glm::u32vec3(32);
  spec.brickSize = 8;
  spec.refine = mixedLevels;
  const Camera camera = orbitCamera(30, 20, 2.2, glm::dvec3(0), glm::dvec3(32));
  const glm::dvec3 g = glm::dvec3(0.012, 0.008, 0.01);  // v in [0.1, 1.0] over the volume
  for (RenderBackend backend : {RenderBackend::Fragment, RenderBackend::Compute}) {
    const PlaneCheck r = checkRampPlane(spec, g, 0.1, 0.1 + 0.015 * 16 * 2, camera, backend);
    EXPECT_GT(r.hits, 300);
    EXPECT_GT(r.misses, 300);
  }
}

TEST(Raycast, CameraInsideTheVolume) {
  SceneSpec spec;
  spec.dims = glm::u32vec3(32);
  spec.refine = mixedLevels;
  Camera camera;
  camera.eye = {10, 12, 14};
  camera.target = {30, 14, 16};
  camera.up = {0, 0, 1};
  camera.fovYDeg = 60;
  const glm::dvec3 g(0.02, 0.002, -0.003);  // plane about x = 22, ahead of the eye
  const PlaneCheck r =
      checkRampPlane(spec, g, 0.1, 0.1 + 0.02 * 22 + 0.002 * 14 - 0.003 * 14, camera, RenderBackend::Compute);
  EXPECT_GT(r.hits, 1500);
}

// The isosurface between a data leaf's last sample and an empty leaf after it, at a step of 4 voxels: the
// ramp v = 0.1 + 0.02 x crosses vIso at x = 13.75, inside the leaves of x in [8, 16); every leaf beyond is
// empty (its values, borders included, from x = 14 on, are above vIso). From an eye at x = 1.5 the samples of
// each ray fall at most near x = 13.5 in [8, 16) and next beyond 16: the crossing is only seen by the sample
// the leaf takes at its end (docs/RENDERING.md "Isosurface"); without it every ray would miss.
TEST(Raycast, ALongStepFindsTheCrossingBeforeAnEmptyLeaf) {
  SceneSpec spec;
  spec.dims = glm::u32vec3(32);
  spec.brickSize = 8;
  const double vIso = 0.1 + 0.02 * 13.75;
  spec.value = [](glm::dvec3 x) { return 0.1 + 0.02 * x.x; };
  spec.emptyLeaf = [](const NodeKey& k) { return k.depth == 2 && k.coord.x >= 2; };
  const test::GlScene scene = test::buildScene(spec);
  ASSERT_EQ(scene.minLeafDepth, 2u);
  for (RenderBackend backend : {RenderBackend::Fragment, RenderBackend::Compute, RenderBackend::Multipass}) {
    RaycastFrame frame;
    frame.camera.eye = {1.5, 16.2, 15.9};
    frame.camera.target = {30.0, 16.2, 15.9};
    frame.camera.up = {0, 0, 1};
    frame.camera.fovYDeg = 30.0;
    frame.width = frame.height = 32;
    frame.params.mode = RenderMode::Iso;
    frame.params.isoValue = vIso * 65535.0;
    frame.params.stepVoxels = 4.0;
    frame.params.backend = backend;
    FloatImage color, depth;
    if (backend == RenderBackend::Multipass) {
      frame.pool = scene.pool.get();
      frame.index = scene.indexTexture.get();
      frame.volume = scene.geometry;
      std::vector<MultipassLeaf> leaves;
      for (const CutLeaf& leaf : scene.cut.leaves)
        if (leaf.kind == LeafKind::Data) leaves.push_back({{leaf.depth, leaf.coord}, leaf.brickSlot});
      MultipassPass pass;
      pass.render(frame, std::move(leaves));
      color = pass.readColor();
      depth = pass.readDepth();
    } else {
      RaycastPass pass;
      test::renderScene(pass, scene, frame);
      color = pass.readColor();
      depth = pass.readDepth();
    }
    const glm::dvec3 forward = cameraFrame(frame.camera).forward;
    for (uint32_t py = 0; py < frame.height; ++py)
      for (uint32_t px = 0; px < frame.width; ++px) {
        const Ray ray = pixelRay(frame.camera, frame.width, frame.height, px, py);
        const double tPlane = (13.75 - ray.origin.x) / ray.dir.x;
        const std::string where = "pixel " + std::to_string(px) + "," + std::to_string(py) + " " +
                                  std::string(renderBackendName(backend));
        EXPECT_EQ(color.at(px, py, 3), 1.0f) << where;
        EXPECT_NEAR(depth.at(px, py, 0), tPlane * glm::dot(ray.dir, forward), 0.02) << where;
      }
  }
}

TEST(Raycast, NonCubicVolumeWithAnisotropicSpacing) {
  SceneSpec spec;
  spec.dims = {48, 32, 20};
  spec.spacing = {1.0, 0.5, 2.0};  // world box 48 x 16 x 40
  spec.refine = [](const NodeKey& n) { return n.depth < 2 || mixedLevels(n); };
  const Camera camera = orbitCamera(-120, -10, 2.0, glm::dvec3(0), glm::dvec3(48, 16, 40));
  const glm::dvec3 g(0.01, 0.02, 0.006);
  for (RenderBackend backend : {RenderBackend::Fragment, RenderBackend::Compute}) {
    const PlaneCheck r =
        checkRampPlane(spec, g, 0.1, 0.1 + 0.01 * 24 + 0.02 * 8 + 0.006 * 20, camera, backend);
    EXPECT_GT(r.hits, 200) << r.misses << " misses, " << r.skipped << " skipped";
  }
}

// A constant volume under a constant transfer function: no gradient, so each sample adds alpha' of the tf's
// color. At one level every ray takes exactly the samples t0 + k dt < t1 (up to one at the far end where
// float and double round differently): 1 - A = (1 - alpha')^N. Across levels the opacity-corrected samples
// sum to the path length within a few steps.
TEST(Raycast, ConstantVolumeOpacityAcrossBricksAndLevels) {
  for (const bool mixed : {false, true}) {
    SceneSpec spec;
    spec.dims = glm::u32vec3(32);
    spec.refine = mixed ? std::function<bool(const NodeKey&)>(mixedLevels) : nullptr;
    spec.value = [](glm::dvec3) { return 0.5; };
    const test::GlScene scene = test::buildScene(spec);
    const glm::dvec4 rgba(0.2, 0.6, 0.9, 0.02);
    const TfTable tf = TfTable::bake(TransferFunction({TfPoint{0.0, rgba}}), ValueMapping{}, 65535);
    RaycastPass pass;
    RaycastFrame frame;
    frame.camera = orbitCamera(20, 35, 2.0, glm::dvec3(0), glm::dvec3(32));
    frame.width = frame.height = 64;
    frame.params.mode = RenderMode::Dvr;
    frame.params.ert = 1.5;  // never terminate early
    frame.params.backend = RenderBackend::Compute;
    frame.tf = &tf;
    test::renderScene(pass, scene, frame);
    const FloatImage color = pass.readColor();

    const double dt0 = 0.5;  // step 0.5 at level 0, spacing 1
    const double perVoxel = -std::log(1.0 - rgba.a);
    int rays = 0, exact = 0;
    double sumError = 0.0;
    for (uint32_t py = 0; py < 64; ++py)
      for (uint32_t px = 0; px < 64; ++px) {
        const Ray ray = pixelRay(frame.camera, 64, 64, px, py);
        double t0, t1;
        const float a = color.at(px, py, 3);
        if (!clipToBox(ray, glm::dvec3(32), t0, t1)) {
          EXPECT_EQ(a, 0.0f);
          continue;
        }
        // The color is the tf's color times the opacity: unshaded, premultiplied.
        for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(color.at(px, py, ch), rgba[ch] * a, 1e-5);
        const double pathVoxels = -std::log(1.0 - double(a)) / perVoxel;  // sum of dt over the samples
        if (!mixed) {
          const double n = std::ceil((t1 - t0) / dt0);
          EXPECT_NEAR(pathVoxels, n * dt0, dt0 * 1.001) << px << "," << py;
          if (std::abs(pathVoxels - n * dt0) < 1e-2) ++exact;
        } else {
          EXPECT_NEAR(pathVoxels, t1 - t0, 4.0) << px << "," << py;  // a few coarse steps
          sumError += pathVoxels - (t1 - t0);
        }
        ++rays;
      }
    ASSERT_GT(rays, 1000);
    if (!mixed) {
      EXPECT_GT(exact, rays * 99 / 100);
    } else {
      EXPECT_LT(std::abs(sumError / rays), 0.75);  // no systematic gap or overlap at level changes
    }
  }
}

TEST(Raycast, FragmentAndComputeAgree) {
  SceneSpec spec;
  spec.dims = {30, 26, 20};
  spec.spacing = {1.0, 1.2, 0.9};
  spec.refine = mixedLevels;
  spec.value = [](glm::dvec3 x) {
    const glm::dvec3 d = x - glm::dvec3(15, 15, 9);
    return 0.5 + 0.4 * std::sin(0.35 * d.x) * std::cos(0.3 * d.y) * std::cos(0.25 * d.z);
  };
  spec.emptyLeaf = [](const NodeKey& k) { return k.depth == 2 && k.coord == glm::u32vec3(0, 0, 0); };
  const test::GlScene scene = test::buildScene(spec);
  const TfTable tf =
      TfTable::bake(TransferFunction({TfPoint{20000, {1, 0, 0, 0}}, TfPoint{40000, {0.9, 0.8, 0.1, 0.3}},
                                      TfPoint{60000, {0.2, 0.3, 1.0, 0.6}}}),
                    ValueMapping{}, 65535);
  for (GradientSource gradients : {GradientSource::Computed, GradientSource::Stored})
    for (RenderMode mode : {RenderMode::Iso, RenderMode::Dvr}) {
      if (mode == RenderMode::Iso && gradients == GradientSource::Stored) continue;  // DVR only
      RaycastFrame frame;
      frame.camera = orbitCamera(70, 15, 1.8, glm::dvec3(0), glm::dvec3(30, 31.2, 18));
      frame.width = 72;  // not a multiple of the tile or workgroup size
      frame.height = 70;
      frame.params.mode = mode;
      frame.params.gradients = gradients;
      frame.params.isoValue = 0.62 * 65535;
      frame.params.background = {0.3, 0.3, 0.3};
      frame.tf = &tf;
      RaycastPass pass;
      frame.params.backend = RenderBackend::Fragment;
      test::renderScene(pass, scene, frame);
      const FloatImage fragColor = pass.readColor(), fragDepth = pass.readDepth();
      frame.params.backend = RenderBackend::Compute;
      test::renderScene(pass, scene, frame);
      const FloatImage compColor = pass.readColor(), compDepth = pass.readDepth();
      // One program on llvmpipe; a GPU's compiler treats the two stages apart (multiply-adds fused
      // differently), which must stay below one step of an 8-bit image.
      EXPECT_LE(test::maxAbsDifference(fragColor, compColor, 4), test::onHardwareGpu() ? 1.0 / 255.0 : 1e-5);
      EXPECT_LE(test::maxAbsDifference(fragDepth, compDepth, 1), 1e-3);
      // Not a blank image: something was hit and something was missed.
      int covered = 0, empty = 0;
      for (uint32_t y = 0; y < frame.height; ++y)
        for (uint32_t x = 0; x < frame.width; ++x) (compColor.at(x, y, 3) > 0.0f ? covered : empty)++;
      EXPECT_GT(covered, 500) << (mode == RenderMode::Iso ? "iso" : "dvr");
      EXPECT_GT(empty, 200);
      EXPECT_GE(pass.lastRaycastMs(), 0.0);
    }
}

// Early ray termination stops compositing at the first sample that brings the opacity to ert or above.
TEST(Raycast, EarlyRayTerminationAndEmptyLeaves) {
  SceneSpec spec;
  spec.dims = glm::u32vec3(24);
  spec.value = [](glm::dvec3) { return 0.5; };
  // The far half (x >= 16 at full resolution) is empty: skipped, so those rays see less opacity.
  spec.emptyLeaf = [](const NodeKey& k) { return k.depth == 2 && k.coord.x >= 2; };
  const test::GlScene scene = test::buildScene(spec);
  const double alpha = 0.1;
  const TfTable tf =
      TfTable::bake(TransferFunction({TfPoint{0.0, {1.0, 1.0, 1.0, alpha}}}), ValueMapping{}, 65535);
  const double alphaStep = 1.0 - std::pow(1.0 - alpha, 0.5);  // dt = half a voxel
  RaycastPass pass;
  RaycastFrame frame;
  frame.camera.eye = {-30.0, 12.0, 12.0};  // looking down +x through the volume
  frame.camera.target = {12.0, 12.0, 12.0};
  frame.camera.fovYDeg = 20.0;
  frame.width = frame.height = 16;
  frame.params.mode = RenderMode::Dvr;
  frame.params.backend = RenderBackend::Compute;
  frame.tf = &tf;
  for (const double ert : {0.5, 0.75, 1.5}) {
    frame.params.ert = ert;
    test::renderScene(pass, scene, frame);
    const FloatImage color = pass.readColor();
    const float a = color.at(8, 8, 3);
    if (ert < 1.0) {
      EXPECT_GE(a, ert);
      EXPECT_LT(a, ert + (1.0 - ert) * alphaStep + 1e-6);
    } else {
      // No termination: samples t0 + k dt over the data (x in [0, 16)), none in the empty leaves beyond.
      const Ray ray = pixelRay(frame.camera, 16, 16, 8, 8);
      const double samples = std::ceil(16.0 / ray.dir.x / 0.5);
      EXPECT_NEAR(a, 1.0 - std::pow(1.0 - alphaStep, samples), 1e-5);
    }
  }
}

TEST(Raycast, AllEmptyGivesTheBackground) {
  SceneSpec spec;
  spec.dims = glm::u32vec3(16);
  spec.value = [](glm::dvec3) { return 1.0; };
  spec.emptyLeaf = [](const NodeKey&) { return true; };
  const test::GlScene scene = test::buildScene(spec);
  ASSERT_EQ(scene.dataLeaves, 0u);
  RaycastPass pass;
  RaycastFrame frame;
  frame.camera = orbitCamera(10, 10, 1.5, glm::dvec3(0), glm::dvec3(16));
  frame.width = frame.height = 16;
  frame.params.isoValue = 0.5 * 65535;
  frame.params.background = {0.25, 0.5, 0.75};
  test::renderScene(pass, scene, frame);
  const FloatImage color = pass.readColor(), depth = pass.readDepth();
  for (uint32_t y = 0; y < 16; ++y)
    for (uint32_t x = 0; x < 16; ++x) {
      EXPECT_EQ(color.at(x, y, 1), 0.5f);
      EXPECT_EQ(color.at(x, y, 3), 0.0f);
      EXPECT_EQ(depth.at(x, y, 0), std::numeric_limits<float>::infinity());
    }
}

TEST(Raycast, RejectsInconsistentInputs) {
  SceneSpec spec;
  spec.dims = glm::u32vec3(16);
  spec.value = [](glm::dvec3) { return 0.5; };
  const test::GlScene scene = test::buildScene(spec);
  RaycastPass pass;
  RaycastFrame frame;
  frame.width = frame.height = 8;
  frame.params.mode = RenderMode::Dvr;  // without a transfer function
  EXPECT_THROW(test::renderScene(pass, scene, frame), Error);
  frame.params.mode = RenderMode::Iso;
  frame.params.stepVoxels = 0.0;
  EXPECT_THROW(test::renderScene(pass, scene, frame), Error);
  frame.params.stepVoxels = 0.5;
  RaycastFrame wrongBricks = frame;
  wrongBricks.pool = scene.pool.get();
  wrongBricks.index = scene.indexTexture.get();
  wrongBricks.volume = scene.geometry;
  wrongBricks.volume.brickSize = 16;
  EXPECT_THROW(pass.render(wrongBricks), Error);
  // A camera without a view direction gives rays that are not finite, on which the traversal would spin.
  RaycastFrame noView = frame;
  noView.camera.target = noView.camera.eye;
  EXPECT_THROW(test::renderScene(pass, scene, noView), Error);
  noView.camera.eye = {-1e308, 0, 0};
  noView.camera.target = {1e308, 0, 0};
  EXPECT_THROW(test::renderScene(pass, scene, noView), Error);
  // Nor a volume without a box (a negative spacing): refused, not a ray cast that never ends.
  RaycastFrame noBox = frame;
  noBox.pool = scene.pool.get();
  noBox.index = scene.indexTexture.get();
  noBox.volume = scene.geometry;
  noBox.volume.spacing.y = -1.0;
  EXPECT_THROW(pass.render(noBox), Error);
  EXPECT_NO_THROW(test::renderScene(pass, scene, frame));
}

}  // namespace
}  // namespace ropecast
