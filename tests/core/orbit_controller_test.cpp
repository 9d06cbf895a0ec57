// The viewer's camera (core/orbit_controller.h): its home is render's default orbit, a drag lands on the
// orbit `render --orbit` takes, and pan, zoom, fly and reset move it as docs/VIEWER.md says.
#include <cmath>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "core/camera.h"
#include "core/orbit_controller.h"

namespace ropecast {
namespace {

const glm::dvec3 kBoxMax{64.0, 48.0, 32.0};

OrbitController defaultController() {
  return OrbitController(glm::dvec3(0.0), kBoxMax,
                         OrbitController::orbitAroundBox(glm::dvec3(0.0), kBoxMax, 30.0, 20.0, 3.0, 40.0));
}

void expectSameCamera(const Camera& a, const Camera& b) {
  EXPECT_EQ(a.eye, b.eye);
  EXPECT_EQ(a.target, b.target);
  EXPECT_EQ(a.up, b.up);
  EXPECT_EQ(a.fovYDeg, b.fovYDeg);
}

TEST(OrbitController, HomeIsTheOrbitCameraOfRender) {
  expectSameCamera(defaultController().camera(),
                   orbitCamera(30.0, 20.0, 3.0, glm::dvec3(0.0), kBoxMax, 40.0));
}

TEST(OrbitController, ADragRightAndDownTurnsToTheDocumentedOrbit) {
  OrbitController c = defaultController();
  c.rotate(40.0, 20.0);  // 0.25 degrees per pixel: azimuth 30 - 10, elevation 20 + 5
  expectSameCamera(c.camera(), orbitCamera(20.0, 25.0, 3.0, glm::dvec3(0.0), kBoxMax, 40.0));
  ASSERT_TRUE(c.renderOrbit().has_value());
  EXPECT_EQ(*c.renderOrbit(), glm::dvec3(20.0, 25.0, 3.0));
}

TEST(OrbitController, ElevationStopsShortOfThePoles) {
  OrbitController c = defaultController();
  c.rotate(0.0, 10000.0);
  EXPECT_EQ(c.state().elevationDeg, OrbitController::kMaxElevationDeg);
  EXPECT_EQ(c.camera().up, glm::dvec3(0.0, 0.0, 1.0));
  c.rotate(0.0, -20000.0);
  EXPECT_EQ(c.state().elevationDeg, -OrbitController::kMaxElevationDeg);
}

// render takes any orbit; the viewer starts there, and a move goes from there in its direction, never to the
// limit on the other side (a tiny zoom in from 0.001 jumped 10x farther, a 1-pixel drag from 120 to 89).
TEST(OrbitController, ACameraStartedBeyondTheLimitsMovesFromWhereItIs) {
  OrbitController c(glm::dvec3(0.0), kBoxMax,
                    OrbitController::orbitAroundBox(glm::dvec3(0.0), kBoxMax, 30.0, 120.0, 0.001, 40.0));
  c.zoom(0.01);  // closer
  EXPECT_LE(c.state().distance, 0.001);
  c.zoom(-0.01);  // a hair farther: still far below the limit
  EXPECT_NEAR(c.state().distance, 0.001, 1e-5);
  c.rotate(1.0, 0.0);
  EXPECT_EQ(c.state().elevationDeg, 120.0);
  c.rotate(0.0, -4.0);  // towards the limits: lower
  EXPECT_DOUBLE_EQ(c.state().elevationDeg, 119.0);
  c.rotate(0.0, 40.0);  // away from them: held where it was
  EXPECT_DOUBLE_EQ(c.state().elevationDeg, 119.0);
  OrbitController far(glm::dvec3(0.0), kBoxMax,
                      OrbitController::orbitAroundBox(glm::dvec3(0.0), kBoxMax, 30.0, 20.0, 5000.0, 40.0));
  far.zoom(0.01);
  EXPECT_GT(far.state().distance, 4990.0);
}

TEST(OrbitController, WheelClicksScaleTheDistance) {
  OrbitController c = defaultController();
  c.zoom(2.0);
  EXPECT_DOUBLE_EQ(c.state().distance, 3.0 * 0.9 * 0.9);
  c.zoom(-2.0);
  EXPECT_NEAR(c.state().distance, 3.0, 1e-12);
}

TEST(OrbitController, PanMovesTheCenterInTheViewPlaneWithTheMouse) {
  OrbitController c = defaultController();
  const Camera before = c.camera();
  const CameraFrame f = cameraFrame(before);
  c.pan(10.0, 0.0, 100);
  const glm::dvec3 moved = c.camera().target - before.target;
  EXPECT_NEAR(glm::dot(moved, f.forward), 0.0, 1e-9);
  EXPECT_NEAR(glm::dot(moved, f.up), 0.0, 1e-9);
  EXPECT_LT(glm::dot(moved, f.right), 0.0);  // the volume follows the mouse right: the camera moves left
  // 10 of 100 pixels at the center's depth: a tenth of the view's height there.
  const double viewHeight = 2.0 * glm::length(before.eye - before.target) * std::tan(glm::radians(20.0));
  EXPECT_NEAR(glm::length(moved), 0.1 * viewHeight, 1e-9);
  EXPECT_FALSE(c.renderOrbit().has_value());
}

TEST(OrbitController, FlyingForwardMovesEyeAndCenterAlongTheView) {
  OrbitController c = defaultController();
  const Camera before = c.camera();
  c.fly(1, 0, 0, 2.0);
  const Camera after = c.camera();
  const double expected = 2.0 * OrbitController::kFlyRadiiPerSecond * c.radius();
  EXPECT_NEAR(glm::dot(after.eye - before.eye, cameraFrame(before).forward), expected, 1e-9);
  EXPECT_NEAR(glm::length(after.target - before.target), expected, 1e-9);
}

TEST(OrbitController, ResetReturnsHome) {
  OrbitController c = defaultController();
  c.rotate(13.0, -7.0);
  c.pan(3.0, 4.0, 64);
  c.zoom(1.0);
  c.reset();
  expectSameCamera(c.camera(), defaultController().camera());
}

TEST(OrbitController, AGivenCameraStaysExactUntilItMoves) {
  Camera given;
  given.eye = {100.0, 10.0, 20.0};
  given.target = {32.0, 24.0, 16.0};
  given.up = {0.0, 1.0, 0.0};
  given.fovYDeg = 30.0;
  OrbitController c = OrbitController::fromCamera(glm::dvec3(0.0), kBoxMax, given);
  expectSameCamera(c.camera(), given);
  c.zoom(0.0);
  expectSameCamera(c.camera(), given);
  c.rotate(1.0, 0.0);
  EXPECT_EQ(c.camera().target, given.target);
  EXPECT_NEAR(glm::length(c.camera().eye - c.camera().target), glm::length(given.eye - given.target), 1e-9);
  c.reset();
  expectSameCamera(c.camera(), given);
}

// The viewer's named views: the controller moves to the camera exactly, orbits on from it, and reset still
// returns to the starting view.
TEST(OrbitController, LookingFromACameraKeepsTheHome) {
  OrbitController c = defaultController();
  Camera view;
  view.eye = {32.0, 24.0, 120.0};
  view.target = {32.0, 24.0, 16.0};
  view.up = {0.0, -1.0, 0.0};
  view.fovYDeg = 40.0;
  c.lookFrom(view);
  expectSameCamera(c.camera(), view);
  EXPECT_FALSE(c.renderOrbit());  // no orbit of render's says this camera's up
  EXPECT_NEAR(c.state().distance * c.radius(), 104.0, 1e-9);
  c.rotate(4.0, 0.0);
  EXPECT_EQ(c.camera().target, view.target);
  c.reset();
  expectSameCamera(c.camera(), defaultController().camera());
}

}  // namespace
}  // namespace ropecast
