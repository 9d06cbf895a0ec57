// WorldBox: an axis-aligned box in world units (docs/RENDERING.md "Spaces"), as the refiner, the occlusion
// queries, the multi-pass leaves and the rays' clip use it. Plain data and pure functions; any thread.
#pragma once

#include <limits>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

namespace ropecast {

struct WorldBox {
  glm::dvec3 lo{0.0}, hi{0.0};

  friend bool operator==(const WorldBox&, const WorldBox&) = default;
};

// The box of all space: what a cut to nothing leaves whole.
inline WorldBox unboundedBox() {
  return {glm::dvec3(-std::numeric_limits<double>::infinity()),
          glm::dvec3(std::numeric_limits<double>::infinity())};
}

// The common part of two boxes; one without volume when they do not overlap.
inline WorldBox intersection(const WorldBox& a, const WorldBox& b) {
  return {glm::max(a.lo, b.lo), glm::min(a.hi, b.hi)};
}

// True when the box is more than a face, an edge or a point: lo < hi on every axis.
inline bool hasVolume(const WorldBox& box) {
  return box.lo.x < box.hi.x && box.lo.y < box.hi.y && box.lo.z < box.hi.z;
}

}  // namespace ropecast
