// ScreenRect and projectBox: pixel rectangles of the image, and the conservative screen rectangle of a
// world-space box, as the occlusion-query scheme of Gobbetti et al. 2008, Sect. 6 partitions the screen with
// them. Plain data and pure functions; any thread.
//
// projectBox maps points to pixels exactly as core/camera.h pixelRay maps pixels to rays (pixel (px, py) has
// its center at (px + 0.5, py + 0.5), row 0 at the top), so a box's rectangle holds every pixel whose ray the
// ray caster sends through the box.
#pragma once

#include <cstdint>

#include <glm/vec3.hpp>

#include "core/camera.h"

namespace ropecast {

// A pixel rectangle [x0, x1) x [y0, y1), in image rows (row 0 = top, as the ray caster's targets).
struct ScreenRect {
  int32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;

  int32_t width() const { return x1 > x0 ? x1 - x0 : 0; }
  int32_t height() const { return y1 > y0 ? y1 - y0 : 0; }
  bool empty() const { return x1 <= x0 || y1 <= y0; }
  int64_t area() const { return int64_t(width()) * height(); }
  // `inner` entirely inside this rectangle (an empty `inner` is inside nothing: it holds no pixel to place).
  bool contains(const ScreenRect& inner) const {
    return !inner.empty() && inner.x0 >= x0 && inner.x1 <= x1 && inner.y0 >= y0 && inner.y1 <= y1;
  }
  // The two share at least one pixel.
  bool overlaps(const ScreenRect& other) const {
    return !empty() && !other.empty() && x0 < other.x1 && other.x0 < x1 && y0 < other.y1 && other.y0 < y1;
  }
  friend bool operator==(const ScreenRect&, const ScreenRect&) = default;
};

// The pixels both rectangles hold; {} (all zero) when they share none.
ScreenRect intersect(const ScreenRect& a, const ScreenRect& b);

// The whole width x height image.
inline ScreenRect viewportRect(uint32_t width, uint32_t height) {
  return {0, 0, int32_t(width), int32_t(height)};
}

// The projection of a world-space box for a camera and viewport.
struct BoxProjection {
  // Conservative bounding rectangle of the projected box, clipped to the viewport: every pixel that the
  // projected box touches at all (not only at its center) is inside. {} (all zero) when it projects outside.
  ScreenRect rect;
  // The box holds the eye or reaches behind the eye plane (its projection is unbounded): rect = whole
  // viewport, and it must not be queried (counted visible).
  bool nearEye = false;
};

// The projection of the box [lo, hi] (world units) seen by `camera` in a width x height image. Corners
// closer to the eye plane than a small margin (relative to the scene's scale) count as behind it: their
// projection is not finite. Zero width or height gives an empty rect.
BoxProjection projectBox(glm::dvec3 lo, glm::dvec3 hi, const Camera& camera, uint32_t width, uint32_t height);

}  // namespace ropecast
