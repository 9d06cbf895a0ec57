// The viewer's probe (tools/view_probe.h): a ray stopped at a depth names the point there, in the volume's
// own axes, for a turned volume too, and the voxel nearest it; a ray that met nothing names none.
#include "tools/view_probe.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "core/orientation.h"

namespace ropecast::tools {
namespace {

constexpr uint32_t kViewWidth = 101, kViewHeight = 81;  // odd: the middle pixel's ray goes through the target

VolumeInfo probedVolume(AxisDirections axes) {
  VolumeInfo v;
  v.dims = {40, 30, 20};
  v.spacing = {0.5, 1.0, 2.0};  // the box [0, 20] x [0, 30] x [0, 40]
  v.axes = axes;
  return v;
}

Camera probeCamera(glm::dvec3 eye, glm::dvec3 target) {
  Camera c;
  c.eye = eye;
  c.target = target;
  c.up = {0, 0, 1};
  c.fovYDeg = 40;
  return c;
}

TEST(ViewProbe, TheStopDepthNamesThePointAndItsVoxel) {
  const double a = glm::radians(35.0);
  const AxisDirections turned(glm::dvec3(std::cos(a), std::sin(a), 0),
                              glm::dvec3(-std::sin(a), std::cos(a), 0), glm::dvec3(0, 0, 1));
  for (const AxisDirections& axes : {AxisDirections(1.0), turned}) {
    const VolumeInfo volume = probedVolume(axes);
    const glm::dvec3 center = 0.5 * volume.worldMax();
    // A point of the volume (its own axes) where it lies in the world; the camera looks at it obliquely.
    const glm::dvec3 inside(7.3, 21.6, 13.1);
    const glm::dvec3 world = center + axes * (inside - center);
    const Camera camera = probeCamera(world + glm::dvec3(-30, -45, 25), world);
    const double depth = glm::length(world - camera.eye);  // along the view axis: the middle pixel's ray
    const auto probed = probedVoxel(camera, kViewWidth, kViewHeight, {50, 40}, depth, volume);
    ASSERT_TRUE(probed.has_value());
    EXPECT_NEAR(glm::length(probed->point - inside), 0.0, 1e-9);
    EXPECT_NEAR(glm::length(probed->world - world), 0.0, 1e-9);
    EXPECT_EQ(probed->voxel, glm::u32vec3(14, 21, 6));  // floor(inside / spacing)
    EXPECT_FALSE(probed->file);                         // a volume placed nowhere

    // With an origin: the point where the file places it, origin + axes (inside - s / 2) (sample i's center
    // lies at (i + 0.5) s in the volume's own axes).
    VolumeInfo placed = volume;
    placed.origin = glm::dvec3(-120.5, 88.0, 30.25);
    const auto inFile = probedVoxel(camera, kViewWidth, kViewHeight, {50, 40}, depth, placed);
    ASSERT_TRUE(inFile && inFile->file);
    const glm::dvec3 expectedFile = *placed.origin + axes * (inside - 0.5 * placed.spacing);
    EXPECT_NEAR(glm::length(*inFile->file - expectedFile), 0.0, 1e-9);

    // Another pixel: the depth is along the view axis, not along its ray.
    const Ray ray = pixelRay(camera, kViewWidth, kViewHeight, 12, 70);
    const glm::dvec3 worldHit = ray.origin + 40.0 * ray.dir;
    const double hitDepth = glm::dot(worldHit - camera.eye, glm::normalize(camera.target - camera.eye));
    const auto other = probedVoxel(camera, kViewWidth, kViewHeight, {12, 70}, hitDepth, volume);
    ASSERT_TRUE(other.has_value());
    const glm::dvec3 expected = center + glm::transpose(axes) * (worldHit - center);
    EXPECT_NEAR(glm::length(other->point - expected), 0.0, 1e-9);
    EXPECT_NEAR(glm::length(other->world - worldHit), 0.0, 1e-9);
  }
}

TEST(ViewProbe, AMissNamesNothingAndAFacesRoundingStaysInTheVolume) {
  const VolumeInfo volume = probedVolume(AxisDirections(1.0));
  const Camera camera = probeCamera({10, -50, 20}, {10, 15, 20});  // the y = 0 face's middle, straight on
  EXPECT_FALSE(
      probedVoxel(camera, kViewWidth, kViewHeight, {50, 40}, std::numeric_limits<double>::infinity(), volume)
          .has_value());
  EXPECT_FALSE(probedVoxel(camera, kViewWidth, kViewHeight, {50, 40}, std::nan(""), volume).has_value());
  // Stopped a hair before the face (y = -1e-9): the voxel of the face's layer.
  const auto front = probedVoxel(camera, kViewWidth, kViewHeight, {50, 40}, 50.0 - 1e-9, volume);
  ASSERT_TRUE(front.has_value());
  EXPECT_EQ(front->voxel, glm::u32vec3(20, 0, 10));
  // And at the far face (y = 30): the last layer.
  const auto back = probedVoxel(camera, kViewWidth, kViewHeight, {50, 40}, 80.0, volume);
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->voxel, glm::u32vec3(20, 29, 10));
}

TEST(ViewProbe, TheLineNamesTheVoxelAndItsValue) {
  ProbedVoxel p;
  p.voxel = {12, 40, 7};
  p.world = {12.43, -40.5, 1234567.0};
  EXPECT_EQ(probeText(p, 187.0), "voxel 12, 40, 7  value 187  at 12.43, -40.5, 1.23457e+06");
  EXPECT_EQ(probeText(p, -1024.0).substr(0, 33), "voxel 12, 40, 7  value -1024  at ");
  EXPECT_EQ(probeText(p, 0.123456789).substr(0, 37), "voxel 12, 40, 7  value 0.1234568  at ");
  EXPECT_EQ(probeText(p, std::nullopt), "voxel 12, 40, 7  value (reading)  at 12.43, -40.5, 1.23457e+06");
  p.file = glm::dvec3(-107.625, 83.25, 30);
  EXPECT_EQ(probeText(p, 187.0),
            "voxel 12, 40, 7  value 187  at 12.43, -40.5, 1.23457e+06  file -107.625, 83.25, 30");
}

TEST(ViewProbe, TheRulerIsTheDistanceBetweenItsPoints) {
  ProbedVoxel a, b;
  a.point = {1.5, 2, 3};
  a.voxel = {1, 2, 3};
  b.point = {4.5, 6, 3};  // 3, 4, 0 away
  b.voxel = {4, 6, 3};
  EXPECT_EQ(rulerText(a, b), "length 5 from voxel 1, 2, 3 to voxel 4, 6, 3");
  b.point.z = 4;
  EXPECT_EQ(rulerText(a, b), "length 5.099 from voxel 1, 2, 3 to voxel 4, 6, 3");
}

}  // namespace
}  // namespace ropecast::tools
