#include "core/orbit_controller.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

namespace ropecast {

OrbitController::OrbitController(glm::dvec3 boxMin, glm::dvec3 boxMax, const OrbitState& home)
    : boxCenter_(0.5 * (boxMin + boxMax)),
      radius_(0.5 * glm::length(boxMax - boxMin)),
      home_(home),
      state_(home) {}

OrbitState OrbitController::orbitAroundBox(glm::dvec3 boxMin, glm::dvec3 boxMax, double azimuthDeg,
                                           double elevationDeg, double distance, double fovYDeg) {
  OrbitState s;
  s.center = 0.5 * (boxMin + boxMax);
  s.azimuthDeg = azimuthDeg;
  s.elevationDeg = elevationDeg;
  s.distance = distance;
  s.fovYDeg = fovYDeg;
  return s;
}

OrbitController OrbitController::fromCamera(glm::dvec3 boxMin, glm::dvec3 boxMax, const Camera& camera) {
  OrbitController c(boxMin, boxMax, OrbitState{});
  c.lookFrom(camera);
  c.home_ = c.state_;
  c.exactHome_ = c.exact_;
  return c;
}

void OrbitController::lookFrom(const Camera& camera) {
  const glm::dvec3 offset = camera.eye - camera.target;
  const double length = glm::length(offset);
  OrbitState s;
  s.center = camera.target;
  s.distance = radius_ > 0.0 ? length / radius_ : length;
  s.elevationDeg = glm::degrees(std::asin(std::clamp(offset.z / length, -1.0, 1.0)));
  s.azimuthDeg = glm::degrees(std::atan2(offset.y, offset.x));
  s.fovYDeg = camera.fovYDeg;
  state_ = s;
  exact_ = camera;
}

Camera OrbitController::camera() const {
  if (exact_) return *exact_;
  const double az = glm::radians(state_.azimuthDeg), el = glm::radians(state_.elevationDeg);
  Camera c;
  c.target = state_.center;
  // The expression of orbitCamera, so that the same orbit gives bit-identical rays.
  c.eye =
      state_.center + state_.distance * radius_ *
                          glm::dvec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  c.up = defaultUp(c.target - c.eye);
  c.fovYDeg = state_.fovYDeg;
  return c;
}

namespace {

// `value` within [lo, hi], or within the wider range that still holds `previous`: a camera started outside
// the limits (render's options take any orbit) moves from where it is, not from the limit.
double clampFrom(double value, double lo, double hi, double previous) {
  return std::clamp(value, std::min(lo, previous), std::max(hi, previous));
}

}  // namespace

void OrbitController::rotate(double dxPixels, double dyPixels) {
  if (dxPixels == 0.0 && dyPixels == 0.0) return;
  exact_.reset();
  state_.azimuthDeg = std::remainder(state_.azimuthDeg - dxPixels * kDegreesPerPixel, 360.0);
  state_.elevationDeg = clampFrom(state_.elevationDeg + dyPixels * kDegreesPerPixel, -kMaxElevationDeg,
                                  kMaxElevationDeg, state_.elevationDeg);
}

void OrbitController::pan(double dxPixels, double dyPixels, uint32_t viewportHeight) {
  if ((dxPixels == 0.0 && dyPixels == 0.0) || viewportHeight == 0) return;
  const CameraFrame f = cameraFrame(camera());
  exact_.reset();
  const double worldPerPixel =
      2.0 * state_.distance * radius_ * std::tan(glm::radians(state_.fovYDeg) * 0.5) / double(viewportHeight);
  state_.center += worldPerPixel * (-dxPixels * f.right + dyPixels * f.up);
}

void OrbitController::zoom(double clicks) {
  if (clicks == 0.0) return;
  exact_.reset();
  state_.distance = clampFrom(state_.distance * std::pow(kZoomPerClick, clicks), kMinDistance, kMaxDistance,
                              state_.distance);
}

void OrbitController::fly(int forward, int right, int up, double seconds) {
  if ((forward == 0 && right == 0 && up == 0) || seconds <= 0.0) return;
  const CameraFrame f = cameraFrame(camera());
  exact_.reset();
  state_.center += kFlyRadiiPerSecond * radius_ * seconds *
                   (double(forward) * f.forward + double(right) * f.right + double(up) * f.up);
}

void OrbitController::reset() {
  state_ = home_;
  exact_ = exactHome_;
}

std::optional<glm::dvec3> OrbitController::renderOrbit() const {
  if (exact_ || state_.center != boxCenter_) return std::nullopt;
  return glm::dvec3(state_.azimuthDeg, state_.elevationDeg, state_.distance);
}

}  // namespace ropecast
