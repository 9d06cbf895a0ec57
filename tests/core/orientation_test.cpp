// Orientation (core/orientation.h): axis vectors made directions, sheared ones refused; RAS to LPS; the
// letters; and a world camera and clip plane seen from a turned volume's axes: the same rays, turned.
#include <cmath>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include "core/orientation.h"

namespace ropecast {
namespace {

void expectNear(glm::dvec3 a, glm::dvec3 b, const char* what) {
  EXPECT_NEAR(glm::length(a - b), 0.0, 1e-12) << what << ": (" << a.x << "," << a.y << "," << a.z
                                              << ") against (" << b.x << "," << b.y << "," << b.z << ")";
}

TEST(Orientation, AxisVectorsBecomeDirectionsWhenAtRightAngles) {
  const auto d = axisDirectionsOf({0, 2, 0}, {-0.5, 0, 0}, {0, 0, 3});
  ASSERT_TRUE(d.has_value());
  EXPECT_EQ(*d, AxisDirections(glm::dvec3(0, 1, 0), glm::dvec3(-1, 0, 0), glm::dvec3(0, 0, 1)));
  EXPECT_FALSE(mirrors(*d));
  EXPECT_TRUE(isAxisAligned(*d));
  EXPECT_FALSE(axisDirectionsOf({1, 0, 0}, {0.5, 1, 0}, {0, 0, 1}).has_value());  // sheared
  EXPECT_FALSE(axisDirectionsOf({1, 0, 0}, {0, 0, 0}, {0, 0, 1}).has_value());
  EXPECT_FALSE(axisDirectionsOf({1, 0, 0}, {0, 1, 0}, {0, 0, std::nan("")}).has_value());
  const auto mirrored = axisDirectionsOf({-1, 0, 0}, {0, 1, 0}, {0, 0, 1});
  ASSERT_TRUE(mirrored.has_value());
  EXPECT_TRUE(mirrors(*mirrored));
}

TEST(Orientation, LettersNameWhereEachAxisPoints) {
  EXPECT_EQ(orientationCode(AxisDirections(1.0)), "LPS");
  EXPECT_EQ(orientationCode(rasToLps(AxisDirections(1.0))), "RAS");
  EXPECT_EQ(orientationCode(AxisDirections(glm::dvec3(0, 1, 0), glm::dvec3(0, 0, -1), glm::dvec3(-1, 0, 0))),
            "PIR");
  const double c = std::cos(0.3), s = std::sin(0.3);
  EXPECT_EQ(orientationCode(AxisDirections(glm::dvec3(c, s, 0), glm::dvec3(-s, c, 0), glm::dvec3(0, 0, 1))),
            "LPS (oblique)");
}

TEST(Orientation, DirectionLettersNameTheSidesADirectionPointsTo) {
  EXPECT_EQ(directionLetters({1, 0, 0}), "L");
  EXPECT_EQ(directionLetters({0, -2, 0}), "A");
  EXPECT_EQ(directionLetters({0, 0, -0.1}), "I");
  EXPECT_EQ(directionLetters({-1, -0.5, 0}), "RA");  // the largest first
  EXPECT_EQ(directionLetters({0.5, 0, 1}), "SL");    // 0.45 of the length
  EXPECT_EQ(directionLetters({0.25, 0, 1}), "S");    // 0.24: too little to name
  EXPECT_EQ(directionLetters({1, -1, 1}), "LAS");    // ties: x, y, z
  EXPECT_EQ(directionLetters({0, 0, 0}), "");
  EXPECT_EQ(directionLetters({std::nan(""), 0, 1}), "");
}

TEST(Orientation, AWorldCameraSeesTheTurnedVolumeAsTheVolumesAxesSeeIt) {
  // A volume turned 90 degrees about x then 30 about z, centered at c: world = c + d (p - c).
  const double a = glm::radians(30.0);
  const glm::dmat3 aboutZ(glm::dvec3(std::cos(a), std::sin(a), 0), glm::dvec3(-std::sin(a), std::cos(a), 0),
                          glm::dvec3(0, 0, 1));
  const glm::dmat3 aboutX(glm::dvec3(1, 0, 0), glm::dvec3(0, 0, 1), glm::dvec3(0, -1, 0));
  const AxisDirections d = aboutZ * aboutX;
  const glm::dvec3 center(10, 20, 5);
  const auto toWorld = [&](glm::dvec3 p) { return center + d * (p - center); };

  Camera world;
  world.eye = {40, -30, 25};
  world.target = {12, 18, 7};
  world.up = {0, 0, 1};
  world.fovYDeg = 35;
  const Camera volume = cameraInVolume(world, d, center);
  expectNear(toWorld(volume.eye), world.eye, "eye");
  expectNear(toWorld(volume.target), world.target, "target");
  EXPECT_EQ(volume.fovYDeg, world.fovYDeg);
  // Every pixel's ray, turned back into the world, is the world camera's.
  for (const auto& [px, py] : {std::pair{0.0, 0.0}, std::pair{63.0, 10.0}, std::pair{20.0, 47.0}}) {
    const Ray inVolume = pixelRay(volume, 64, 48, px, py), inWorld = pixelRay(world, 64, 48, px, py);
    expectNear(toWorld(inVolume.origin), inWorld.origin, "ray origin");
    expectNear(d * inVolume.dir, inWorld.dir, "ray direction");
  }
  // A clip plane keeps the same points.
  const ClipPlane worldPlane{{11, 19, 6}, glm::normalize(glm::dvec3(1, -2, 0.5))};
  const ClipPlane volumePlane = clipPlaneInVolume(worldPlane, d, center);
  for (const glm::dvec3 p : {glm::dvec3(0, 0, 0), glm::dvec3(15, 25, 3), glm::dvec3(5, 30, 12)}) {
    const double side = glm::dot(volumePlane.normal, p) - volumePlane.offset();
    const double worldSide = glm::dot(worldPlane.normal, toWorld(p)) - worldPlane.offset();
    EXPECT_NEAR(side, worldSide, 1e-12);
  }
  // No plane stays none; the identity changes nothing, bit for bit.
  EXPECT_FALSE(clipPlaneInVolume(ClipPlane{}, d, center).enabled());
  EXPECT_EQ(cameraInVolume(world, AxisDirections(1.0), center), world);
  EXPECT_EQ(clipPlaneInVolume(worldPlane, AxisDirections(1.0), center), worldPlane);
}

// A slice's default plane is axial (world +z) through the drawn box's center: the volume's center, or a crop
// box's, carried into the world as the volume is turned.
TEST(Orientation, TheDefaultSliceIsAxialThroughTheDrawnBoxsCenter) {
  const glm::u32vec3 dims(20, 40, 10);
  const glm::dvec3 spacing(1.0, 1.0, 2.0);
  RenderParams params;
  ClipPlane plane = defaultSlicePlane(params, dims, spacing, AxisDirections(1.0));
  expectNear(plane.point, glm::dvec3(10, 20, 10), "center");
  expectNear(plane.normal, glm::dvec3(0, 0, 1), "normal");
  params.crop = {glm::dvec3(0, 0, 6), glm::dvec3(20, 10, 10)};  // voxels; z of spacing 2: 12..20
  plane = defaultSlicePlane(params, dims, spacing, AxisDirections(1.0));
  expectNear(plane.point, glm::dvec3(10, 5, 16), "crop's center");
  // Turned 90 degrees about x (y toward world z) about the extent's center (10, 20, 10).
  const AxisDirections aboutX(glm::dvec3(1, 0, 0), glm::dvec3(0, 0, 1), glm::dvec3(0, -1, 0));
  plane = defaultSlicePlane(params, dims, spacing, aboutX);
  expectNear(plane.point, glm::dvec3(10, 20 - 6, 10 - 15), "turned crop's center");
  expectNear(plane.normal, glm::dvec3(0, 0, 1), "turned normal");
}

// --slice AXIS:INDEX: the plane through that slice's voxel centers, (i + 0.5) s along the axis, through the
// drawn box's center across it, its normal the axis; turned with the volume.
TEST(Orientation, AVoxelSlicePassesThroughItsVoxelsCentersAlongItsAxis) {
  const glm::u32vec3 dims(20, 40, 10);
  const glm::dvec3 spacing(1.0, 1.0, 2.0);
  RenderParams params;
  ClipPlane plane = voxelSlicePlane(params, 2, 3, dims, spacing, AxisDirections(1.0));
  expectNear(plane.point, glm::dvec3(10, 20, 7), "z slice 3");
  expectNear(plane.normal, glm::dvec3(0, 0, 1), "z normal");
  params.crop = {glm::dvec3(4, 0, 0), glm::dvec3(8, 40, 10)};
  plane = voxelSlicePlane(params, 1, 0, dims, spacing, AxisDirections(1.0));
  expectNear(plane.point, glm::dvec3(6, 0.5, 10), "y slice 0 of a crop");
  expectNear(plane.normal, glm::dvec3(0, 1, 0), "y normal");
  // Turned 90 degrees about x (y toward world z) about the extent's center (10, 20, 10): the y slice's normal
  // is world z, and its point (6, 0.5, 10) goes to (6, 20, 10 - 19.5).
  const AxisDirections aboutX(glm::dvec3(1, 0, 0), glm::dvec3(0, 0, 1), glm::dvec3(0, -1, 0));
  plane = voxelSlicePlane(params, 1, 0, dims, spacing, aboutX);
  expectNear(plane.point, glm::dvec3(6, 20, -9.5), "turned y slice 0");
  expectNear(plane.normal, glm::dvec3(0, 0, 1), "turned y normal");
}

// The named views: the eye on that side of the patient (LPS), superior up, anterior up from above and below;
// seen from the front and from below, the patient's right lies on the image's left, as radiology shows it.
TEST(Orientation, NamedViewsLookFromTheirSideOfThePatient) {
  const glm::dvec3 boxMin(0.0), boxMax(40.0, 30.0, 20.0), center = 0.5 * boxMax;
  const double radius = 0.5 * glm::length(boxMax);
  struct Expected {
    AnatomicalView view;
    glm::dvec3 side, up, imageRight;
  };
  for (const Expected& e : {Expected{AnatomicalView::Anterior, {0, -1, 0}, {0, 0, 1}, {1, 0, 0}},
                            Expected{AnatomicalView::Posterior, {0, 1, 0}, {0, 0, 1}, {-1, 0, 0}},
                            Expected{AnatomicalView::Left, {1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
                            Expected{AnatomicalView::Right, {-1, 0, 0}, {0, 0, 1}, {0, -1, 0}},
                            Expected{AnatomicalView::Superior, {0, 0, 1}, {0, -1, 0}, {-1, 0, 0}},
                            Expected{AnatomicalView::Inferior, {0, 0, -1}, {0, -1, 0}, {1, 0, 0}}}) {
    const Camera c = anatomicalViewCamera(e.view, 2.5, boxMin, boxMax, 35.0);
    const std::string what = "view " + std::to_string(int(e.view));
    EXPECT_EQ(cameraProblem(c), "") << what;
    EXPECT_EQ(c.target, center) << what;
    EXPECT_NEAR(glm::length(c.eye - center - 2.5 * radius * e.side), 0.0, 1e-12) << what;
    EXPECT_EQ(c.fovYDeg, 35.0) << what;
    const CameraFrame f = cameraFrame(c);
    EXPECT_NEAR(glm::length(f.up - e.up), 0.0, 1e-12) << what;
    EXPECT_NEAR(glm::length(f.right - e.imageRight), 0.0, 1e-12) << what;
  }
  // The names, in the order the options list them.
  ASSERT_EQ(std::size(kAnatomicalViewNames), 6u);
  EXPECT_STREQ(kAnatomicalViewNames[0].first, "anterior");
  EXPECT_EQ(kAnatomicalViewNames[5].second, AnatomicalView::Inferior);
}

}  // namespace
}  // namespace ropecast
