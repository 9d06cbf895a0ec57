#include "occlusion/screen_rect.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

namespace ropecast {

ScreenRect intersect(const ScreenRect& a, const ScreenRect& b) {
  const ScreenRect r{std::max(a.x0, b.x0), std::max(a.y0, b.y0), std::min(a.x1, b.x1), std::min(a.y1, b.y1)};
  return r.empty() ? ScreenRect{} : r;
}

namespace {

// A corner nearer the eye plane than this fraction of the box's farthest corner distance counts as behind
// it: its projection would overflow any pixel coordinate, and rounding decides which side it is on.
constexpr double kNearEyeFraction = 1e-9;

}  // namespace

BoxProjection projectBox(glm::dvec3 lo, glm::dvec3 hi, const Camera& camera, uint32_t width,
                         uint32_t height) {
  BoxProjection p;
  if (width == 0 || height == 0) return p;
  const ScreenRect viewport = viewportRect(width, height);

  glm::dvec3 corners[8];
  double farthest = 0.0;
  for (uint32_t i = 0; i < 8; ++i) {
    corners[i] = {(i & 1u) ? hi.x : lo.x, (i & 2u) ? hi.y : lo.y, (i & 4u) ? hi.z : lo.z};
    farthest = std::max(farthest, glm::length(corners[i] - camera.eye));
  }
  const CameraFrame f = cameraFrame(camera);
  const double margin = kNearEyeFraction * farthest;

  // The inverse of pixelRay: a point at view-space (x, y, z) lies on the ray of the continuous pixel position
  // (u, v) = (px + 0.5, py + 0.5) with x / z = (2u / width - 1) tanHalf aspect, y / z = (1 - 2v / height)
  // tanHalf.
  const double tanHalf = std::tan(glm::radians(camera.fovYDeg) * 0.5);
  const double aspect = double(width) / double(height);
  double uMin = INFINITY, uMax = -INFINITY, vMin = INFINITY, vMax = -INFINITY;
  for (const glm::dvec3& corner : corners) {
    const glm::dvec3 d = corner - camera.eye;
    const double z = glm::dot(d, f.forward);
    if (!(z > margin)) {  // also catches NaN: nothing finite to project
      p.rect = viewport;
      p.nearEye = true;
      return p;
    }
    const double u = (glm::dot(d, f.right) / (z * tanHalf * aspect) + 1.0) * 0.5 * width;
    const double v = (1.0 - glm::dot(d, f.up) / (z * tanHalf)) * 0.5 * height;
    uMin = std::min(uMin, u), uMax = std::max(uMax, u);
    vMin = std::min(vMin, v), vMax = std::max(vMax, v);
  }
  if (!std::isfinite(uMin + uMax + vMin + vMax)) {  // a camera without a usable frame: assume the worst
    p.rect = viewport;
    p.nearEye = true;
    return p;
  }
  // The projection of a box lies in the convex hull of its corners' projections, so their bounding rectangle
  // holds it. floor / ceil keep every pixel the hull touches, which includes every pixel whose center ray
  // meets the box with half a pixel to spare for rounding. Clamped in floating point before the conversion.
  const auto toPixel = [](double x, uint32_t size) {
    return int32_t(std::clamp(x, -1.0, double(size) + 1.0));
  };
  const ScreenRect bounds{toPixel(std::floor(uMin), width), toPixel(std::floor(vMin), height),
                          toPixel(std::ceil(uMax), width), toPixel(std::ceil(vMax), height)};
  p.rect = intersect(bounds, viewport);
  return p;
}

}  // namespace ropecast
