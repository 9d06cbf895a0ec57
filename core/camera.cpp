#include "core/camera.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

namespace ropecast {

Camera orbitCamera(double azimuthDeg, double elevationDeg, double distance, glm::dvec3 boxMin,
                   glm::dvec3 boxMax, double fovYDeg) {
  const glm::dvec3 center = 0.5 * (boxMin + boxMax);
  const double radius = 0.5 * glm::length(boxMax - boxMin);
  const double az = glm::radians(azimuthDeg), el = glm::radians(elevationDeg);
  Camera c;
  c.target = center;
  c.eye = center + distance * radius *
                       glm::dvec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  c.up = defaultUp(c.target - c.eye);
  c.fovYDeg = fovYDeg;
  return c;
}

namespace {

// The sine of the angle between a unit forward and up below which the frame's right vector is too unstable
// to use (about 0.06 milliradians).
constexpr double kMinUpSine = 1e-6;

bool upUsable(glm::dvec3 forward, glm::dvec3 up) {
  const double length = glm::length(up);
  return length > 0.0 && std::isfinite(length) && glm::length(glm::cross(forward, up / length)) > kMinUpSine;
}

}  // namespace

glm::dvec3 defaultUp(glm::dvec3 viewDirection) {
  // Looking straight down or up the z axis: any horizontal up works; pick +y so the frame stays defined.
  return std::abs(glm::normalize(viewDirection).z) > 0.9999 ? glm::dvec3(0.0, 1.0, 0.0)
                                                            : glm::dvec3(0.0, 0.0, 1.0);
}

std::string viewProblem(glm::dvec3 eye, glm::dvec3 target) {
  const glm::dvec3 view = target - eye;
  if (view == glm::dvec3(0.0)) return "eye and target are the same point";
  if (!std::isfinite(glm::length(view))) return "the view direction (target - eye) is not finite";
  return "";
}

std::string cameraProblem(const Camera& c) {
  if (std::string problem = viewProblem(c.eye, c.target); !problem.empty()) return problem;
  if (!std::isfinite(glm::length(c.up))) return "up is not finite";
  if (c.up == glm::dvec3(0.0)) return "up is the zero vector";
  if (!upUsable(glm::normalize(c.target - c.eye), c.up))
    return "up is parallel to the view direction (target - eye)";
  if (!(c.fovYDeg > 0.0 && c.fovYDeg < 180.0)) return "the field of view must be in (0, 180) degrees";
  return "";
}

CameraFrame cameraFrame(const Camera& c) {
  CameraFrame f;
  f.forward = glm::normalize(c.target - c.eye);
  glm::dvec3 up = c.up;
  if (!upUsable(f.forward, up)) up = defaultUp(f.forward);
  f.right = glm::normalize(glm::cross(f.forward, up));
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

Camera centeredOn(const Camera& c, glm::dvec3 point) {
  const double distance = glm::length(point - c.eye);
  if (!(distance > 0.0) || !std::isfinite(distance)) return c;
  Camera moved = c;
  moved.target = point;
  moved.eye = point - cameraFrame(c).forward * distance;
  return moved;
}

bool clipToBox(const Ray& ray, const WorldBox& box, double& t0, double& t1, int* entry) {
  t0 = -std::numeric_limits<double>::infinity();
  t1 = std::numeric_limits<double>::infinity();
  int bound = kEntryNone;
  for (int a = 0; a < 3; ++a) {
    if (ray.dir[a] == 0.0) {
      if (ray.origin[a] < box.lo[a] || ray.origin[a] > box.hi[a]) return false;
      continue;
    }
    double tn = (box.lo[a] - ray.origin[a]) / ray.dir[a], tf = (box.hi[a] - ray.origin[a]) / ray.dir[a];
    if (tn > tf) std::swap(tn, tf);
    if (tn > t0) {
      t0 = tn;
      bound = ray.dir[a] > 0.0 ? a : 3 + a;
    }
    t1 = std::min(t1, tf);
  }
  if (entry) *entry = t0 > 0.0 ? bound : kEntryNone;
  t0 = std::max(t0, 0.0);
  return t0 < t1;
}

bool clipToHalfSpace(const Ray& ray, glm::dvec3 normal, double offset, double& t0, double& t1, int* entry,
                     int bound) {
  if (normal == glm::dvec3(0.0)) return t0 < t1;
  const double along = glm::dot(normal, ray.dir);
  const double above = glm::dot(normal, ray.origin) - offset;  // >= 0: the origin is kept
  if (along == 0.0) return above >= 0.0 && t0 < t1;
  const double t = -above / along;
  if (along > 0.0 && t > t0) {
    t0 = t;
    if (entry) *entry = bound;
  } else if (along < 0.0) {
    t1 = std::min(t1, t);
  }
  return t0 < t1;
}

bool startAtPlane(const Ray& ray, glm::dvec3 normal, double offset, double& t0, double t1) {
  const double along = glm::dot(normal, ray.dir);
  if (along == 0.0) return false;
  const double t = -(glm::dot(normal, ray.origin) - offset) / along;
  if (!(t >= t0 && t < t1)) return false;
  t0 = t;
  return true;
}

int entryBound(const Ray& ray, const WorldBox& box, glm::dvec3 normal, double offset) {
  double t0 = 0.0, t1 = 0.0;
  int bound = kEntryNone;
  return clipToBox(ray, box, t0, t1, &bound) && clipToHalfSpace(ray, normal, offset, t0, t1, &bound)
             ? bound
             : kEntryNone;
}

glm::dvec3 boundInwardNormal(int bound, glm::dvec3 planeNormal) {
  if (bound == kEntryPlane) return planeNormal;
  if (bound == kEntryPlaneBack) return -planeNormal;
  glm::dvec3 n(0.0);
  n[bound % 3] = bound < 3 ? 1.0 : -1.0;
  return n;
}

}  // namespace ropecast
