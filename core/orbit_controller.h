// OrbitController: the interactive camera of `ropecast view` (docs/VIEWER.md "Camera"), as plain math over
// the camera frame of core/camera.h. The eye orbits a center point: azimuth around +z from +x, elevation
// above the xy plane (degrees), distance in bounding-sphere radii of the volume box, up +z, exactly as
// orbitCamera places it, so that an orbit reached by dragging renders the image `ropecast render --orbit
// AZ,EL,DIST` does. Mouse input arrives in window pixels (y down); the viewer turns events into these calls.
//
// Plain state, no clock and no GL: the caller measures time. Owned by the viewer's main thread.
#pragma once

#include <cstdint>
#include <optional>

#include <glm/vec3.hpp>

#include "core/camera.h"

namespace ropecast {

struct OrbitState {
  glm::dvec3 center{0.0};  // the point orbited and looked at (world units)
  double azimuthDeg = 30.0;
  double elevationDeg = 20.0;
  double distance = 3.0;  // bounding-sphere radii
  double fovYDeg = 40.0;
};

class OrbitController {
 public:
  // Degrees of azimuth and elevation per pixel of a rotating drag.
  static constexpr double kDegreesPerPixel = 0.25;
  // Elevation stays within +-kMaxElevationDeg: beyond it the view runs along z and orbitCamera's up flips.
  static constexpr double kMaxElevationDeg = 89.0;
  // One wheel click scales the distance by this factor (towards the center for positive clicks).
  static constexpr double kZoomPerClick = 0.9;
  static constexpr double kMinDistance = 0.01, kMaxDistance = 1000.0;
  // Flying moves eye and center together by this many bounding-sphere radii per second.
  static constexpr double kFlyRadiiPerSecond = 0.5;

  // A controller around the volume box [boxMin, boxMax], starting (and resetting) at `home`.
  OrbitController(glm::dvec3 boxMin, glm::dvec3 boxMax, const OrbitState& home);
  // A controller starting at an arbitrary camera (`render --eye --target --up`): its orbit is the eye's
  // position around the target. The camera is returned unchanged (its own up) until the first movement.
  static OrbitController fromCamera(glm::dvec3 boxMin, glm::dvec3 boxMax, const Camera& camera);
  // Moves to `camera` (eye and target distinct) as fromCamera starts at one, keeping the home that reset()
  // returns to: the viewer's named views.
  void lookFrom(const Camera& camera);

  // The home orbit around the box center with the given azimuth, elevation and distance.
  static OrbitState orbitAroundBox(glm::dvec3 boxMin, glm::dvec3 boxMax, double azimuthDeg,
                                   double elevationDeg, double distance, double fovYDeg);

  Camera camera() const;
  const OrbitState& state() const { return state_; }
  double radius() const { return radius_; }

  // Left drag by (dx, dy) window pixels: dragging right turns the volume right (azimuth falls), dragging down
  // tips its top towards the viewer (elevation rises).
  void rotate(double dxPixels, double dyPixels);
  // Middle or shift-left drag: the center moves in the view plane so that the point at the center's depth
  // follows the mouse, in a view `viewportHeight` pixels tall.
  void pan(double dxPixels, double dyPixels, uint32_t viewportHeight);
  // Wheel clicks: positive moves closer.
  void zoom(double clicks);
  // WASD (and Q/E down/up): move eye and center along the view, right and up axes by `seconds` of flight;
  // forward, right, up each in {-1, 0, 1}.
  void fly(int forward, int right, int up, double seconds);
  void reset();

  // The orbit as `render --orbit AZ,EL,DIST` takes it, when the center is the box center (else nullopt: the
  // view needs --eye/--target).
  std::optional<glm::dvec3> renderOrbit() const;

 private:
  glm::dvec3 boxCenter_;
  double radius_;
  OrbitState home_, state_;
  std::optional<Camera> exactHome_;  // fromCamera: its camera, while nothing moved
  std::optional<Camera> exact_;
};

}  // namespace ropecast
