#include "loader/camera.h"

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

namespace ropecast {

Camera orbitCamera(double azimuthDeg, double elevationDeg, double distance, glm::dvec3 boxMin, glm::dvec3 boxMax,
                   double fovYDeg) {
  const glm::dvec3 center = 0.5 * (boxMin + boxMax);
  const double radius = 0.5 * glm::length(boxMax - boxMin);
  const double az = glm::radians(azimuthDeg), el = glm::radians(elevationDeg);
  Camera c;
  c.target = center;
  c.eye = center + distance * radius * glm::dvec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  c.up = {0.0, 0.0, 1.0};
  // Looking straight down or up the z axis: any horizontal up works; pick +y so the frame stays defined.
  if (std::abs(glm::dot(glm::normalize(c.target - c.eye), c.up)) > 0.9999) c.up = {0.0, 1.0, 0.0};
  c.fovYDeg = fovYDeg;
  return c;
}

CameraFrame cameraFrame(const Camera& c) {
  CameraFrame f;
  f.forward = glm::normalize(c.target - c.eye);
  f.right = glm::normalize(glm::cross(f.forward, c.up));
  f.up = glm::cross(f.right, f.forward);
  return f;
}

Ray pixelRay(const Camera& c, uint32_t width, uint32_t height, double px, double py) {
  const CameraFrame f = cameraFrame(c);
  const double tanHalf = std::tan(glm::radians(c.fovYDeg) * 0.5);
  const double aspect = double(width) / double(height);
  const double x = (2.0 * (px + 0.5) / width - 1.0) * tanHalf * aspect;
  const double y = (1.0 - 2.0 * (py + 0.5) / height) * tanHalf;
  return {c.eye, glm::normalize(f.forward + x * f.right + y * f.up)};
}

glm::dmat4 viewMatrix(const Camera& c) { return glm::lookAt(c.eye, c.target, cameraFrame(c).up); }

glm::dmat4 projectionMatrix(const Camera& c, double aspect, double nearDist, double farDist) {
  return glm::perspective(glm::radians(c.fovYDeg), aspect, nearDist, farDist);
}

}  // namespace ropecast
