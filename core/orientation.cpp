#include "core/orientation.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

namespace ropecast {

namespace {

bool finite(glm::dvec3 v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

std::optional<AxisDirections> axisDirectionsOf(glm::dvec3 x, glm::dvec3 y, glm::dvec3 z) {
  constexpr double kOrthogonal = 1e-3;
  const glm::dvec3 axes[3] = {x, y, z};
  AxisDirections d(1.0);
  for (int a = 0; a < 3; ++a) {
    const double length = glm::length(axes[a]);
    if (!finite(axes[a]) || !(length > 0.0) || !std::isfinite(length)) return std::nullopt;
    d[a] = axes[a] / length;
  }
  for (int a = 0; a < 3; ++a)
    if (std::abs(glm::dot(d[a], d[(a + 1) % 3])) > kOrthogonal) return std::nullopt;
  return d;
}

AxisDirections rasToLps(const AxisDirections& ras) {
  AxisDirections lps = ras;
  for (int a = 0; a < 3; ++a) {
    lps[a].x = -ras[a].x;
    lps[a].y = -ras[a].y;
  }
  return lps;
}

bool mirrors(const AxisDirections& d) {
  return glm::determinant(d) < 0.0;
}

bool isAxisAligned(const AxisDirections& d) {
  constexpr double kTolerance = 1e-6;
  for (int a = 0; a < 3; ++a) {
    int along = 0;
    for (int w = 0; w < 3; ++w) along += std::abs(d[a][w]) > kTolerance;
    if (along != 1) return false;
  }
  return true;
}

std::string orientationCode(const AxisDirections& d) {
  static constexpr char kPositive[3] = {'L', 'P', 'S'}, kNegative[3] = {'R', 'A', 'I'};
  std::string code;
  for (int a = 0; a < 3; ++a) {
    int largest = 0;
    for (int w = 1; w < 3; ++w)
      if (std::abs(d[a][w]) > std::abs(d[a][largest])) largest = w;
    code += d[a][largest] >= 0.0 ? kPositive[largest] : kNegative[largest];
  }
  if (!isAxisAligned(d)) code += " (oblique)";
  return code;
}

std::string directionLetters(glm::dvec3 worldDirection) {
  static constexpr char kPositive[3] = {'L', 'P', 'S'}, kNegative[3] = {'R', 'A', 'I'};
  const double length = glm::length(worldDirection);
  if (!(length > 0.0) || !std::isfinite(length)) return "";
  int order[3] = {0, 1, 2};
  std::stable_sort(std::begin(order), std::end(order),
                   [&](int a, int b) { return std::abs(worldDirection[a]) > std::abs(worldDirection[b]); });
  std::string letters;
  for (int axis : order)
    if (std::abs(worldDirection[axis]) >= kDirectionLetterShare * length)
      letters += worldDirection[axis] > 0.0 ? kPositive[axis] : kNegative[axis];
  return letters;
}

Camera cameraInVolume(const Camera& world, const AxisDirections& d, glm::dvec3 center) {
  if (d == AxisDirections(1.0)) return world;
  // The directions are orthonormal: their inverse is their transpose.
  const glm::dmat3 toVolume = glm::transpose(d);
  Camera c = world;
  c.eye = center + toVolume * (world.eye - center);
  c.target = center + toVolume * (world.target - center);
  c.up = toVolume * world.up;
  return c;
}

ClipPlane clipPlaneInVolume(const ClipPlane& world, const AxisDirections& d, glm::dvec3 center) {
  if (d == AxisDirections(1.0) || !world.enabled()) return world;
  const glm::dmat3 toVolume = glm::transpose(d);
  return {center + toVolume * (world.point - center), toVolume * world.normal, world.slab};
}

ClipPlane voxelSlicePlane(const RenderParams& params, int axis, uint32_t index, glm::u32vec3 dims,
                          glm::dvec3 spacing, const AxisDirections& d) {
  const WorldBox drawn = sampledWorldBox(params, dims, spacing);
  const glm::dvec3 center = 0.5 * glm::dvec3(dims) * spacing;
  glm::dvec3 point = 0.5 * (drawn.lo + drawn.hi);
  point[axis] = (double(index) + 0.5) * spacing[axis];
  return {center + d * (point - center), d[axis]};
}

ClipPlane defaultSlicePlane(const RenderParams& params, glm::u32vec3 dims, glm::dvec3 spacing,
                            const AxisDirections& d) {
  const WorldBox drawn = sampledWorldBox(params, dims, spacing);
  const glm::dvec3 center = 0.5 * glm::dvec3(dims) * spacing;
  return {center + d * (0.5 * (drawn.lo + drawn.hi) - center), glm::dvec3(0.0, 0.0, 1.0)};
}

Camera anatomicalViewCamera(AnatomicalView view, double distance, glm::dvec3 boxMin, glm::dvec3 boxMax,
                            double fovYDeg) {
  // Where the eye lies from the center, and the up vector.
  glm::dvec3 side(0.0), up(0.0, 0.0, 1.0);
  switch (view) {
    case AnatomicalView::Anterior:
      side = {0.0, -1.0, 0.0};
      break;
    case AnatomicalView::Posterior:
      side = {0.0, 1.0, 0.0};
      break;
    case AnatomicalView::Left:
      side = {1.0, 0.0, 0.0};
      break;
    case AnatomicalView::Right:
      side = {-1.0, 0.0, 0.0};
      break;
    case AnatomicalView::Superior:
      side = {0.0, 0.0, 1.0}, up = {0.0, -1.0, 0.0};
      break;
    case AnatomicalView::Inferior:
      side = {0.0, 0.0, -1.0}, up = {0.0, -1.0, 0.0};
      break;
  }
  const glm::dvec3 center = 0.5 * (boxMin + boxMax);
  Camera c;
  c.target = center;
  c.eye = center + distance * 0.5 * glm::length(boxMax - boxMin) * side;
  c.up = up;
  c.fovYDeg = fovYDeg;
  return c;
}

}  // namespace ropecast
