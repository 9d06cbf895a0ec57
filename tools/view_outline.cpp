#include "tools/view_outline.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

namespace ropecast::tools {

namespace {

std::array<glm::dvec3, 8> cornersOf(const WorldBox& b) {
  std::array<glm::dvec3, 8> c;
  for (int i = 0; i < 8; ++i)
    c[i] = {i & 1 ? b.hi.x : b.lo.x, i & 2 ? b.hi.y : b.lo.y, i & 4 ? b.hi.z : b.lo.z};
  return c;
}

// Corner pairs that differ in one axis.
std::vector<std::pair<int, int>> boxEdges() {
  std::vector<std::pair<int, int>> edges;
  for (int i = 0; i < 8; ++i)
    for (int bit : {1, 2, 4})
      if (!(i & bit)) edges.emplace_back(i, i | bit);
  return edges;
}

class Projector {
 public:
  Projector(const Camera& camera, uint32_t width, uint32_t height, const PlacedBox& placed)
      : camera_(camera), frame_(cameraFrame(camera)), width_(width), height_(height), placed_(placed) {
    tanHalf_ = std::tan(glm::radians(camera.fovYDeg) * 0.5);
    aspect_ = double(width) / double(height);
    // A point this close to the eye's plane, or behind it, is cut away: a thousandth of the box's size.
    near_ = 1e-3 * std::max(glm::length(placed.box.hi - placed.box.lo), 1e-12);
  }

  // A segment given in the volume's own axes, cut to what lies in front of the eye, in window pixels.
  std::optional<ScreenSegment> segment(glm::dvec3 a, glm::dvec3 b) const {
    glm::dvec3 va = toView(a), vb = toView(b);
    if (va.z < near_ && vb.z < near_) return std::nullopt;
    if (va.z < near_) va = va + (vb - va) * ((near_ - va.z) / (vb.z - va.z));
    if (vb.z < near_) vb = vb + (va - vb) * ((near_ - vb.z) / (va.z - vb.z));
    return ScreenSegment{toPixels(va), toPixels(vb)};
  }

 private:
  // Right, up and forward distances from the eye of a point in the volume's own axes.
  glm::dvec3 toView(glm::dvec3 p) const {
    const glm::dvec3 world = placed_.center + placed_.axes * (p - placed_.center);
    const glm::dvec3 v = world - camera_.eye;
    return {glm::dot(v, frame_.right), glm::dot(v, frame_.up), glm::dot(v, frame_.forward)};
  }
  // pixelRay inverted: the ray through window point (X, Y) has x = (2X / width - 1) tanHalf aspect.
  glm::dvec2 toPixels(glm::dvec3 v) const {
    const double x = v.x / v.z / (tanHalf_ * aspect_), y = v.y / v.z / tanHalf_;
    return {(x + 1.0) * 0.5 * width_, (1.0 - y) * 0.5 * height_};
  }

  Camera camera_;
  CameraFrame frame_;
  uint32_t width_, height_;
  PlacedBox placed_;
  double tanHalf_ = 1.0, aspect_ = 1.0, near_ = 0.0;
};

}  // namespace

std::vector<ScreenSegment> boxOutline(const Camera& camera, uint32_t width, uint32_t height,
                                      const PlacedBox& box) {
  const Projector project(camera, width, height, box);
  const std::array<glm::dvec3, 8> corners = cornersOf(box.box);
  std::vector<ScreenSegment> segments;
  for (const auto& [i, j] : boxEdges())
    if (const auto s = project.segment(corners[i], corners[j])) segments.push_back(*s);
  return segments;
}

std::vector<ScreenSegment> planeOutline(const Camera& camera, uint32_t width, uint32_t height,
                                        const PlacedBox& box, const ClipPlane& worldPlane) {
  if (!worldPlane.enabled()) return {};
  const ClipPlane plane = clipPlaneInVolume(worldPlane, box.axes, box.center);
  const std::array<glm::dvec3, 8> corners = cornersOf(box.box);
  // Where the plane crosses the box's edges: the polygon's corners, in order around their centroid.
  std::vector<glm::dvec3> points;
  for (const auto& [i, j] : boxEdges()) {
    const double da = glm::dot(plane.normal, corners[i]) - plane.offset(),
                 db = glm::dot(plane.normal, corners[j]) - plane.offset();
    if ((da < 0.0) == (db < 0.0) || da == db) continue;
    const glm::dvec3 p = corners[i] + (corners[j] - corners[i]) * (da / (da - db));
    // A corner on the plane ends three edges: once.
    const double tolerance = 1e-9 * glm::length(box.box.hi - box.box.lo);
    if (std::none_of(points.begin(), points.end(),
                     [&](const glm::dvec3& q) { return glm::length(q - p) <= tolerance; }))
      points.push_back(p);
  }
  if (points.size() < 3) return {};  // the plane only touches the box
  glm::dvec3 centroid(0.0);
  for (const glm::dvec3& p : points) centroid += p / double(points.size());
  const glm::dvec3 u = glm::normalize(points[0] - centroid);
  const glm::dvec3 v = glm::cross(plane.normal, u);
  std::sort(points.begin(), points.end(), [&](const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::dot(a - centroid, v), glm::dot(a - centroid, u)) <
           std::atan2(glm::dot(b - centroid, v), glm::dot(b - centroid, u));
  });
  const Projector project(camera, width, height, box);
  std::vector<ScreenSegment> segments;
  for (size_t k = 0; k < points.size(); ++k)
    if (const auto s = project.segment(points[k], points[(k + 1) % points.size()])) segments.push_back(*s);
  return segments;
}

std::optional<ScreenSegment> segmentOutline(const Camera& camera, uint32_t width, uint32_t height,
                                            const PlacedBox& box, glm::dvec3 a, glm::dvec3 b) {
  return Projector(camera, width, height, box).segment(a, b);
}

EdgeLetters edgeLetters(const Camera& camera) {
  const CameraFrame f = cameraFrame(camera);
  return {directionLetters(-f.right), directionLetters(f.right), directionLetters(f.up),
          directionLetters(-f.up)};
}

std::array<TriadAxis, 3> axesTriad(const Camera& camera, const AxisDirections& axes) {
  const CameraFrame f = cameraFrame(camera);
  std::array<TriadAxis, 3> triad;
  for (int a = 0; a < 3; ++a)
    triad[a] = {{glm::dot(axes[a], f.right), -glm::dot(axes[a], f.up)}, -glm::dot(axes[a], f.forward)};
  return triad;
}

}  // namespace ropecast::tools
