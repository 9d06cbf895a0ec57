// Tests of reference/cpu_raycaster (CPU tier, no GL): the sphere's isosurface silhouette against the analytic
// area, mirror vs reference on a level-0 cut, DVR of a constant volume against 1 - (1 - a)^n, a linear ramp's
// isosurface depth across brick borders and leaves of different levels, misses and errors.
#include "reference/cpu_raycaster.h"

#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <numbers>
#include <string>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "core/error.h"
#include "index/cut.h"
#include "index/rope_index.h"
#include "store/procedural_bricks.h"

namespace ropecast {
namespace {

// A BrickSource over a function of level-0 position (sample i at i + 0.5), point sampled at each level's
// sample centers like ProceduralBricks, with exact min/max from the generated bricks (small volumes only).
class FunctionBricks : public BrickSource {
 public:
  FunctionBricks(glm::u32vec3 dims, uint32_t brickSize, SampleType storedType, glm::dvec3 spacing,
                 std::function<double(glm::dvec3)> f)
      : f_(std::move(f)) {
    info_.layout = OctreeLayout::forVolume(dims, brickSize);
    info_.volume.dims = dims;
    info_.volume.spacing = spacing;
    info_.volume.type = storedType;
    info_.storedType = storedType;
    info_.mapping = {1.0, 0.0};
  }
  const BrickSourceInfo& info() const override { return info_; }
  NodeInfo node(const NodeKey& key) const override {
    if (!info_.layout.isInside(key)) return {};
    std::vector<std::byte> b(brickBytes());
    readBrick(key, b);
    NodeInfo n{NodeKind::Data, 65535, 0};
    for (size_t i = 0; i < info_.layout.storedBrickSamples(); ++i) {
      const uint16_t v = stored(b, i);
      n.minValue = std::min(n.minValue, v);
      n.maxValue = std::max(n.maxValue, v);
    }
    return n;
  }
  void readBrick(const NodeKey& key, std::span<std::byte> out) const override {
    const OctreeLayout& l = info_.layout;
    const uint32_t e = l.storedBrickEdge(), level = l.levelOfDepth(key.depth);
    const glm::u32vec3 dims = l.levelDims(level);
    const double maxStored = info_.storedType == SampleType::UInt8 ? 255.0 : 65535.0;
    size_t i = 0;
    for (uint32_t z = 0; z < e; ++z)
      for (uint32_t y = 0; y < e; ++y)
        for (uint32_t x = 0; x < e; ++x, ++i) {
          glm::dvec3 p;
          const glm::u32vec3 t(x, y, z);
          for (int a = 0; a < 3; ++a) {
            const int64_t g = int64_t(key.coord[a]) * l.brickSize + t[a] - int64_t(kBrickBorder);
            p[a] = (double(std::clamp<int64_t>(g, 0, dims[a] - 1)) + 0.5) * double(1u << level);
          }
          const auto v = uint16_t(std::clamp(std::round(f_(p)), 0.0, maxStored));
          if (info_.storedType == SampleType::UInt8)
            out[i] = std::byte(v);
          else
            std::memcpy(&out[2 * i], &v, 2);
        }
  }

 private:
  uint16_t stored(const std::vector<std::byte>& b, size_t i) const {
    if (info_.storedType == SampleType::UInt8) return uint16_t(b[i]);
    uint16_t v;
    std::memcpy(&v, &b[2 * i], 2);
    return v;
  }
  std::function<double(glm::dvec3)> f_;
  BrickSourceInfo info_;
};

// A cut of Data leaves over the inside nodes; leaves at depth maxDepth - levelOf(node) (0 = all level 0), the
// rest completed with Empty leaves.
Cut cutOfLevels(const OctreeLayout& layout, const std::function<uint32_t(const NodeKey&)>& levelOf) {
  std::vector<CutLeaf> leaves;
  uint32_t slot = 0;
  std::function<void(const NodeKey&)> visit = [&](const NodeKey& k) {
    if (!layout.isInside(k)) return;
    if (k.depth == layout.maxDepth || layout.levelOfDepth(k.depth) <= levelOf(k)) {
      leaves.push_back({k.depth, k.coord, LeafKind::Data, slot++});
      return;
    }
    for (uint32_t o = 0; o < 8; ++o) visit(k.child(o));
  };
  visit({0, {0, 0, 0}});
  return completeCut(leaves);
}

Cut level0Cut(const OctreeLayout& layout) {
  return cutOfLevels(layout, [](const NodeKey&) { return 0u; });
}

CpuImage renderMirrorOfCut(const BrickSource& src, const Cut& cut, const CpuRenderInput& in) {
  return renderMirror(buildRopeIndex(cut), readCutBricks(cut, src), src.info(), in);
}

double psnr(const CpuImage& a, const CpuImage& b) {
  double se = 0.0;
  size_t n = 0;
  for (size_t i = 0; i < a.rgba.size(); ++i) {
    if (i % 4 == 3) continue;
    const double d = double(a.rgba[i]) - double(b.rgba[i]);
    se += d * d;
    ++n;
  }
  return se == 0.0 ? std::numeric_limits<double>::infinity() : 10.0 * std::log10(double(n) / se);
}

size_t hitPixels(const CpuImage& img) {
  size_t hits = 0;
  for (size_t i = 3; i < img.rgba.size(); i += 4) hits += img.rgba[i] > 0.5f;
  return hits;
}

CpuRenderInput isoInput(const BrickSource& src, double az, double el, double dist, uint32_t size,
                        double iso) {
  CpuRenderInput in;
  const glm::dvec3 box = glm::dvec3(src.info().volume.dims) * src.info().volume.spacing;
  in.camera = orbitCamera(az, el, dist, glm::dvec3(0.0), box, 30.0);
  in.width = in.height = size;
  in.params.mode = RenderMode::Iso;
  in.params.isoValue = iso;
  in.params.background = {0.1, 0.2, 0.3};
  return in;
}

// Pixels covered by a sphere of radius r whose center is on the optical axis at distance d: a circle of
// radius tan(asin(r / d)) on the image plane at unit distance, with pixels 2 tan(fov/2) / H wide.
double analyticSphereArea(double r, double d, double fovYDeg, uint32_t height) {
  const double pixel = 2.0 * std::tan(fovYDeg * std::numbers::pi / 360.0) / height;
  const double rImage = std::tan(std::asin(r / d)) / pixel;
  return std::numbers::pi * rImage * rImage;
}

TEST(CpuRaycaster, SphereSilhouetteHasTheAnalyticArea) {
  const ProceduralBricks src({ProceduralKind::Sphere, 64}, 16);
  const ReferenceRenderer reference(src);
  for (const auto& [az, el] : {std::pair{30.0, 20.0}, std::pair{-100.0, 65.0}}) {
    const CpuRenderInput in = isoInput(src, az, el, 2.0, 128, 127.5);
    const double d = glm::length(in.camera.eye - in.camera.target);
    const double expected = analyticSphereArea(0.4 * 64, d, in.camera.fovYDeg, in.height);
    const double ref = double(hitPixels(reference.render(in)));
    EXPECT_NEAR(ref / expected, 1.0, 0.01) << "reference, az " << az << " el " << el;
    const double level0 = double(hitPixels(renderMirrorOfCut(src, level0Cut(src.info().layout), in)));
    EXPECT_NEAR(level0 / expected, 1.0, 0.01) << "mirror, level-0 cut, az " << az;
    const Cut level1 = cutOfLevels(src.info().layout, [](const NodeKey&) { return 1u; });
    const double coarse = double(hitPixels(renderMirrorOfCut(src, level1, in)));
    EXPECT_NEAR(coarse / expected, 1.0, 0.01) << "mirror, level-1 cut, az " << az;
  }
}

TEST(CpuRaycaster, IsoDepthOfTheSphereFrontIsTheAnalyticDistance) {
  const ProceduralBricks src({ProceduralKind::Sphere, 64}, 16);
  CpuRenderInput in = isoInput(src, 10.0, 15.0, 2.0, 65, 127.5);  // odd size: a pixel on the optical axis
  const CpuImage img = ReferenceRenderer(src).render(in);
  const double d = glm::length(in.camera.eye - in.camera.target);
  EXPECT_NEAR(img.depth[32 * 65 + 32], d - 0.4 * 64, 0.1);
  // Misses: background, alpha 0, depth +inf.
  const glm::vec4 corner = img.pixel(0, 0);
  EXPECT_EQ(corner, glm::vec4(0.1f, 0.2f, 0.3f, 0.0f));
  EXPECT_TRUE(std::isinf(img.depth[0]));
}

TEST(CpuRaycaster, MirrorOnALevel0CutMatchesTheReference) {
  const ProceduralBricks src({ProceduralKind::Noise, 40}, 16);
  const ReferenceRenderer reference(src);
  const Cut cut = level0Cut(src.info().layout);
  const TfTable tf =
      TfTable::bake(TransferFunction::preset("linear", tfDataRangeFor(src.info())), src.info().mapping, 255);
  const TfTable gray =
      TfTable::bake(TransferFunction::preset("gray", tfDataRangeFor(src.info())), src.info().mapping, 255);
  // From the +x+y+z side rays enter the volume where the cube does not begin, so both start at the same
  // sample.
  for (const auto& [az, el] : {std::pair{40.0, 30.0}, std::pair{-130.0, -20.0}}) {
    for (RenderMode mode : {RenderMode::Iso, RenderMode::Dvr, RenderMode::Mip}) {
      CpuRenderInput in = isoInput(src, az, el, 2.2, 64, 100.0);
      in.params.mode = mode;
      in.tf = mode == RenderMode::Mip ? &gray : &tf;
      const CpuImage a = renderMirrorOfCut(src, cut, in), b = reference.render(in);
      EXPECT_GE(psnr(a, b), az > 0 ? 60.0 : 45.0) << "az " << az << " mode " << int(mode);
      EXPECT_GT(hitPixels(b), 500u);
    }
  }
}

TEST(CpuRaycaster, MirrorOnAMixedCutStaysCloseToTheReference) {
  const ProceduralBricks src({ProceduralKind::Sphere, 64}, 8);
  const Cut mixed = cutOfLevels(src.info().layout,
                                [](const NodeKey& k) { return (k.coord.x + k.coord.y + k.coord.z) % 3; });
  const TfTable tf =
      TfTable::bake(TransferFunction::preset("linear", tfDataRangeFor(src.info())), src.info().mapping, 255);
  for (RenderMode mode : {RenderMode::Iso, RenderMode::Dvr, RenderMode::Mip}) {
    CpuRenderInput in = isoInput(src, 25.0, 35.0, 2.0, 96, 127.5);
    in.params.mode = mode;
    in.tf = &tf;
    const double p = psnr(renderMirrorOfCut(src, mixed, in), ReferenceRenderer(src).render(in));
    EXPECT_GE(p, 30.0) << "mode " << int(mode);
  }
}

TEST(CpuRaycaster, AFlatRegionAtTheIsovalueHasNoSurface) {
  // f = v - iso is 0 everywhere: no sign change, so no hit (docs/RENDERING.md), in the reference and the
  // mirror.
  const FunctionBricks src({40, 24, 32}, 8, SampleType::UInt8, glm::dvec3(1.0),
                           [](glm::dvec3) { return 100.0; });
  CpuRenderInput in;
  in.camera = orbitCamera(35.0, 25.0, 2.0, glm::dvec3(0.0), glm::dvec3(40, 24, 32), 35.0);
  in.width = in.height = 48;
  in.params.mode = RenderMode::Iso;
  in.params.isoValue = 100.0;
  for (const CpuImage& image :
       {ReferenceRenderer(src).render(in), renderMirrorOfCut(src, level0Cut(src.info().layout), in)})
    for (float depth : image.depth) ASSERT_TRUE(std::isinf(depth));
}

TEST(CpuRaycaster, DvrOfAConstantVolumeHasTheAnalyticOpacityAndDepth) {
  // Constant 100 in a 40 x 24 x 32 volume with anisotropic spacing; TF: a = 0.03 per voxel, color c
  // everywhere.
  const glm::dvec3 spacing(1.0, 1.5, 0.75);
  const FunctionBricks src({40, 24, 32}, 8, SampleType::UInt8, spacing, [](glm::dvec3) { return 100.0; });
  const auto tf = TransferFunction({{0.0, {0.2, 0.6, 0.9, 0.03}}});
  const TfTable table = TfTable::bake(tf, src.info().mapping, 255);
  const glm::dvec3 box = glm::dvec3(40, 24, 32) * spacing;
  CpuRenderInput in;
  in.camera = orbitCamera(35.0, 25.0, 2.0, glm::dvec3(0.0), box, 35.0);
  in.width = in.height = 64;
  in.params.mode = RenderMode::Dvr;
  in.params.ert = 2.0;  // no early termination
  in.params.background = {1.0, 0.5, 0.0};
  in.tf = &table;
  const double minS = 0.75;
  const Cut level1 = cutOfLevels(src.info().layout, [](const NodeKey&) { return 1u; });
  const auto reference = ReferenceRenderer(src).render(in);
  const auto mirror0 = renderMirrorOfCut(src, level0Cut(src.info().layout), in);
  const auto mirror1 = renderMirrorOfCut(src, level1, in);
  int checked = 0, droppedEntrySamples = 0;
  for (uint32_t y = 0; y < in.height; ++y)
    for (uint32_t x = 0; x < in.width; ++x) {
      const Ray ray = pixelRay(in.camera, in.width, in.height, x, y);
      double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
      for (int a = 0; a < 3; ++a) {
        double tn = -ray.origin[a] / ray.dir[a], tf = (box[a] - ray.origin[a]) / ray.dir[a];
        if (tn > tf) std::swap(tn, tf);
        t0 = std::max(t0, tn);
        t1 = std::min(t1, tf);
      }
      for (const auto& [img, levelScale] :
           {std::pair{&reference, 1.0}, std::pair{&mirror0, 1.0}, std::pair{&mirror1, 2.0}}) {
        const glm::vec4 px = img->pixel(x, y);
        if (!(t0 < t1)) {
          EXPECT_EQ(px.a, 0.0f);
          continue;
        }
        const double dt = 0.5 * levelScale * minS;
        const double steps = (t1 - t0) / dt;
        if (steps - std::floor(steps) < 0.01 || steps - std::floor(steps) > 0.99)
          continue;  // ambiguous count
        const double n = std::ceil(steps);
        const auto expectedRgba = [&](double samples) {
          const double alpha = 1.0 - std::pow(1.0 - 0.03, samples * dt / minS);
          return glm::dvec4(alpha * glm::dvec3(0.2, 0.6, 0.9) + (1.0 - alpha) * in.params.background, alpha);
        };
        const auto matches = [&](double samples) {
          const glm::dvec4 e = expectedRgba(samples);
          return std::abs(px.r - e.r) < 1e-5 && std::abs(px.g - e.g) < 1e-5 && std::abs(px.b - e.b) < 1e-5 &&
                 std::abs(px.a - e.a) < 1e-5;
        };
        // The mirror traverses in float like the GPU: where the ray enters the volume on a node face (every
        // face of a volume whose dims are multiples of the brick size), the entry point may round into the
        // empty node outside, and the sample at the entry is then not taken (docs/RENDERING.md, rule 3, in
        // float).
        const bool isMirror = img != &reference;
        if (isMirror && !matches(n) && matches(n - 1)) {
          ++droppedEntrySamples;
          continue;
        }
        ASSERT_TRUE(matches(n)) << x << "," << y << " image " << (img == &reference ? "reference" : "mirror")
                                << " level scale " << levelScale << " n " << n << " alpha " << px.a
                                << " expected " << expectedRgba(n).a;
        // The depth is the sample's at which the opacity reached a half (the last sample that found less
        // before it), or the last sample's where the ray never got there.
        double k = 0.0;
        while (k + 1.0 < n && expectedRgba(k + 1.0).a < kDvrDepthOpacity) k += 1.0;
        const double forward = glm::dot(ray.dir, glm::normalize(in.camera.target - in.camera.eye));
        ASSERT_NEAR(img->depth[size_t(y) * in.width + x], (t0 + k * dt) * forward, 0.02)
            << x << "," << y << " n " << n << " sample " << k;
        ++checked;
      }
    }
  EXPECT_GT(checked, 3 * 1000);
  // Not a bound the contract gives, a record: about half the rays entering through a face lose that sample.
  EXPECT_LT(droppedEntrySamples, checked / 4);
}

// A Gaussian peak over a floor (MIP), and a Gaussian dip under a ceiling (MinIP): along each ray the largest
// (smallest) value is the peak's (dip's) at the ray's nearest approach to its center, and lies there. Through
// a gray ramp, opaque everywhere, the pixel is that value.
TEST(CpuRaycaster, ProjectionsShowEachRaysExtremeValueWhereItLies) {
  const glm::dvec3 center(20.0, 13.0, 17.0);
  const double sigma = 7.0;
  const auto gaussian = [center, sigma](glm::dvec3 p) {
    const glm::dvec3 d = p - center;
    return 20000.0 * std::exp(-glm::dot(d, d) / (sigma * sigma));
  };
  for (RenderMode mode : {RenderMode::Mip, RenderMode::MinIp}) {
    const double sign = projectionSign(mode);
    // MIP: 2000 + g; MinIP: 23000 - g.
    const auto value = [&gaussian, sign](glm::dvec3 p) { return 12500.0 + sign * (gaussian(p) - 10500.0); };
    const FunctionBricks src({40, 26, 34}, 8, SampleType::UInt16, glm::dvec3(1.0), value);
    const TfTable tf =
        TfTable::bake(TransferFunction({{0.0, {0.0, 0.0, 0.0, 1.0}}, {25000.0, {1.0, 1.0, 1.0, 1.0}}}),
                      src.info().mapping, 65535);
    CpuRenderInput in;
    in.camera = orbitCamera(35.0, 25.0, 2.0, glm::dvec3(0.0), glm::dvec3(40, 26, 34), 35.0);
    in.width = in.height = 48;
    in.params.mode = mode;
    in.params.background = {0.0, 0.0, 1.0};
    in.tf = &tf;
    const glm::dvec3 forward = cameraFrame(in.camera).forward;
    const std::string what(renderModeName(mode));
    for (const CpuImage& image :
         {ReferenceRenderer(src).render(in), renderMirrorOfCut(src, level0Cut(src.info().layout), in)}) {
      int checked = 0, nearCenter = 0;
      for (uint32_t y = 0; y < in.height; ++y)
        for (uint32_t x = 0; x < in.width; ++x) {
          const Ray ray = pixelRay(in.camera, in.width, in.height, x, y);
          const double tNearest = glm::dot(center - ray.origin, ray.dir);
          const glm::dvec3 nearest = ray.origin + tNearest * ray.dir;
          const glm::vec4 px = image.pixel(x, y);
          if (px.a == 0.0f) {
            EXPECT_EQ(px.b, 1.0f) << what;  // the background: a ray that missed the volume
            continue;
          }
          // Rays whose nearest approach lies well inside the volume (their extreme is not at its face).
          if (glm::any(glm::lessThan(nearest, glm::dvec3(2.0))) ||
              glm::any(glm::greaterThan(nearest, glm::dvec3(38, 24, 32))))
            continue;
          // Trilinear interpolation flattens the peak by up to h^2/8 of its second derivative per axis,
          // 3 (2 20000 / sigma^2) / 8 = 306 at the top; the step misses it by less.
          EXPECT_NEAR(px.r * 25000.0, value(nearest), 400.0) << what << " " << x << "," << y;
          EXPECT_EQ(px.a, 1.0f) << what;
          ++checked;
          // Far from the center the value along the ray is nearly flat, and the first sample of its extreme
          // stored (rounded) value may lie anywhere on the flat part; near it, within a voxel or two.
          if (gaussian(nearest) > 10000.0) {
            EXPECT_NEAR(image.depth[y * in.width + x], glm::dot(nearest - in.camera.eye, forward), 2.0)
                << what << " " << x << "," << y;
            ++nearCenter;
          }
        }
      EXPECT_GT(checked, 500) << what;
      EXPECT_GT(nearCenter, 50) << what;
    }
  }
}

// A ramp along x (AIP): the pixel is the mean of the ramp along the ray's part in the volume, whatever the
// levels of the leaves it crosses (through a gray ramp, opaque everywhere), and its depth the ray's entry
// (every value lies above zero).
TEST(CpuRaycaster, AnAverageProjectionShowsEachRaysMeanValue) {
  const auto value = [](glm::dvec3 p) { return 2000.0 + 450.0 * p.x; };
  const FunctionBricks src({40, 26, 34}, 8, SampleType::UInt16, glm::dvec3(1.0), value);
  const TfTable tf =
      TfTable::bake(TransferFunction({{0.0, {0.0, 0.0, 0.0, 1.0}}, {25000.0, {1.0, 1.0, 1.0, 1.0}}}),
                    src.info().mapping, 65535);
  CpuRenderInput in;
  in.camera = orbitCamera(35.0, 25.0, 2.0, glm::dvec3(0.0), glm::dvec3(40, 26, 34), 35.0);
  in.width = in.height = 48;
  in.params.mode = RenderMode::Aip;
  in.params.background = {0.0, 0.0, 1.0};
  in.tf = &tf;
  const glm::dvec3 forward = cameraFrame(in.camera).forward;
  const Cut mixed =
      cutOfLevels(src.info().layout, [](const NodeKey& k) { return (k.coord.y + 2 * k.coord.z) % 2; });
  for (const CpuImage& image : {ReferenceRenderer(src).render(in), renderMirrorOfCut(src, mixed, in)}) {
    int checked = 0;
    double lowest = 1.0, highest = 0.0;
    for (uint32_t y = 0; y < in.height; ++y)
      for (uint32_t x = 0; x < in.width; ++x) {
        const Ray ray = pixelRay(in.camera, in.width, in.height, x, y);
        double t0 = 0.0, t1 = 0.0;
        const glm::vec4 px = image.pixel(x, y);
        if (!clipToBox(ray, glm::dvec3(40, 26, 34), t0, t1)) {
          EXPECT_EQ(px.a, 0.0f);
          continue;
        }
        if (t1 - t0 < 8.0) continue;  // a corner's few samples: the step's share of the mean is large
        // Interpolation holds the ramp (a coarser level's too) but near the x faces, where a border repeats
        // the last sample: rays that come near them are left out. The mean of a ramp is its middle's value.
        const double xIn = ray.origin.x + t0 * ray.dir.x, xOut = ray.origin.x + t1 * ray.dir.x;
        if (std::min(xIn, xOut) < 1.5 || std::max(xIn, xOut) > 38.5) continue;
        const glm::dvec3 middle = ray.origin + 0.5 * (t0 + t1) * ray.dir;
        EXPECT_NEAR(px.r * 25000.0, value(middle), 25.0) << x << "," << y;
        EXPECT_EQ(px.a, 1.0f);
        EXPECT_NEAR(image.depth[y * in.width + x], t0 * glm::dot(ray.dir, forward), 0.5) << x << "," << y;
        lowest = std::min(lowest, double(px.r));
        highest = std::max(highest, double(px.r));
        ++checked;
      }
    EXPECT_GT(checked, 300);
    EXPECT_GT(highest - lowest, 0.3);  // the means differ from ray to ray
  }
}

// A linear function (slice), which trilinear interpolation and every coarser level keep exactly: each pixel
// is its value where the pixel's ray crosses the plane inside the drawn box, and its depth there, seen from
// either side of the plane; a ray crossing it outside the box (cropped) shows the background.
TEST(CpuRaycaster, ASliceShowsTheValueWhereEachRayCrossesThePlane) {
  const auto value = [](glm::dvec3 p) { return 2000.0 + 150.0 * p.x + 90.0 * p.y + 60.0 * p.z; };
  const glm::dvec3 dims(40, 26, 34);
  const FunctionBricks src(glm::u32vec3(dims), 8, SampleType::UInt16, glm::dvec3(1.0), value);
  const TfTable tf =
      TfTable::bake(TransferFunction({{0.0, {0.0, 0.0, 0.0, 1.0}}, {25000.0, {1.0, 1.0, 1.0, 1.0}}}),
                    src.info().mapping, 65535);
  const Cut mixed = cutOfLevels(src.info().layout,
                                [](const NodeKey& k) { return (k.coord.x + k.coord.y + k.coord.z) % 2; });
  const ClipPlane plane{{20.0, 13.0, 17.0}, glm::normalize(glm::dvec3(1.0, 0.5, 0.8))};
  for (bool cropped : {false, true})
    for (double azimuth : {35.0, 215.0}) {  // the eye on either side of the plane
      CpuRenderInput in;
      in.camera = orbitCamera(azimuth, 25.0, 2.0, glm::dvec3(0.0), dims, 35.0);
      in.width = in.height = 48;
      in.params.mode = RenderMode::Slice;
      in.params.clipPlane = plane;
      in.params.background = {0.0, 0.0, 1.0};
      if (cropped) in.params.crop = {{0.0, 6.0, 0.0}, {40.0, 20.0, 34.0}};
      in.tf = &tf;
      const WorldBox drawn = sampledWorldBox(in.params, glm::u32vec3(dims), glm::dvec3(1.0));
      const glm::dvec3 forward = cameraFrame(in.camera).forward;
      const std::string what = std::string(cropped ? "cropped, " : "") + "azimuth " + std::to_string(azimuth);
      for (const CpuImage& image : {ReferenceRenderer(src).render(in), renderMirrorOfCut(src, mixed, in)}) {
        int checked = 0, missed = 0;
        for (uint32_t y = 0; y < in.height; ++y)
          for (uint32_t x = 0; x < in.width; ++x) {
            const Ray ray = pixelRay(in.camera, in.width, in.height, x, y);
            const double t =
                glm::dot(plane.point - ray.origin, plane.normal) / glm::dot(ray.dir, plane.normal);
            const glm::dvec3 p = ray.origin + t * ray.dir;
            const glm::vec4 px = image.pixel(x, y);
            const glm::dvec3 inside = glm::min(p - drawn.lo, drawn.hi - p);
            if (std::min({inside.x, inside.y, inside.z}) < -0.01) {
              EXPECT_EQ(px.a, 0.0f) << what << " " << x << "," << y;
              EXPECT_EQ(px.b, 1.0f) << what;
              ++missed;
              continue;
            }
            if (std::min({inside.x, inside.y, inside.z}) < 0.01) continue;  // on the box's face
            // The volume's faces repeat their last sample (a level-1 leaf's, two voxels), bending the ramp.
            const glm::dvec3 fromFaces = glm::min(p, dims - p);
            if (std::min({fromFaces.x, fromFaces.y, fromFaces.z}) < 3.0) continue;
            EXPECT_NEAR(px.r * 25000.0, value(p), 2.0) << what << " " << x << "," << y;
            EXPECT_EQ(px.a, 1.0f) << what;
            EXPECT_NEAR(image.depth[y * in.width + x], t * glm::dot(ray.dir, forward), 1e-3) << what;
            ++checked;
          }
        EXPECT_GT(checked, 200) << what;
        EXPECT_GT(missed, 200) << what;
      }
    }
}

TEST(CpuRaycaster, LinearRampIsoPlaneHasExactDepthAcrossBricksAndLevels) {
  // uint16 ramp along x: value(p) = 100 (p.x - 0.5), exact at every level; the iso 2050 plane is x = 21.
  const glm::dvec3 spacing(1.0, 1.0, 2.0);
  const FunctionBricks src({48, 40, 24}, 8, SampleType::UInt16, spacing,
                           [](glm::dvec3 p) { return 100.0 * (p.x - 0.5); });
  const Cut mixed =
      cutOfLevels(src.info().layout, [](const NodeKey& k) { return (k.coord.y + 2 * k.coord.z) % 3; });
  CpuRenderInput in = isoInput(src, 160.0, 20.0, 1.6, 64, 2050.0);  // looking from -x towards +x
  in.camera.target = glm::dvec3(21.0, 20.0, 24.0);
  const auto img = renderMirrorOfCut(src, mixed, in);
  const glm::dvec3 forward = cameraFrame(in.camera).forward;
  int hits = 0;
  for (uint32_t y = 0; y < in.height; ++y)
    for (uint32_t x = 0; x < in.width; ++x) {
      const Ray ray = pixelRay(in.camera, in.width, in.height, x, y);
      const double t = (21.0 - ray.origin.x) / ray.dir.x;
      const glm::dvec3 p = ray.origin + t * ray.dir;
      // Only where the plane is well inside the volume (the edges replicate samples, bending the ramp).
      if (p.y < 2.0 || p.y > 38.0 || p.z < 4.0 || p.z > 44.0) continue;
      ASSERT_GT(img.pixel(x, y).a, 0.5f) << x << "," << y;
      ASSERT_NEAR(img.depth[y * in.width + x], t * glm::dot(ray.dir, forward), 0.01) << x << "," << y;
      ++hits;
    }
  EXPECT_GT(hits, 1000);
}

TEST(CpuRaycaster, ErrorsNameTheProblem) {
  const ProceduralBricks src({ProceduralKind::Sphere, 32}, 8);
  CpuRenderInput in = isoInput(src, 0.0, 0.0, 2.0, 16, 100.0);
  in.params.mode = RenderMode::Dvr;
  EXPECT_THROW(ReferenceRenderer(src).render(in), Error);
  in.params.mode = RenderMode::Iso;
  const Cut cut = level0Cut(src.info().layout);
  BricksBySlot bricks = readCutBricks(cut, src);
  bricks.erase(bricks.begin());
  try {
    renderMirror(buildRopeIndex(cut), bricks, src.info(), in);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no brick for slot"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ropecast
