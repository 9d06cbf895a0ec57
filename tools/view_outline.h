// What the viewer draws over its 3D view while the crop box and clip plane are edited: the crop box's
// edges and the polygon where the clip plane cuts the drawn box, projected as the camera's rays see them
// (core/camera.h pixelRay). GL-free; main thread.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "core/camera.h"
#include "core/orientation.h"
#include "core/render_params.h"
#include "core/world_box.h"

namespace ropecast::tools {

// A line in window pixels (x right, y down; pixel (i, j) covers [i, i+1] x [j, j+1]).
struct ScreenSegment {
  glm::dvec2 a{0.0}, b{0.0};
};

// Where a volume lies in the world: a box in its own axes turned by `axes` about `center`
// (core/orientation.h).
struct PlacedBox {
  WorldBox box;  // in the volume's own axes
  AxisDirections axes{1.0};
  glm::dvec3 center{0.0};
};

// The twelve edges of the box, as a width x height view of `camera` shows them; the parts behind the eye are
// cut away (an edge wholly behind it gives nothing).
std::vector<ScreenSegment> boxOutline(const Camera& camera, uint32_t width, uint32_t height,
                                      const PlacedBox& box);

// The polygon where `plane` (in the world) cuts the box, its sides as segments as above; none where the
// plane misses the box or is off.
std::vector<ScreenSegment> planeOutline(const Camera& camera, uint32_t width, uint32_t height,
                                        const PlacedBox& box, const ClipPlane& plane);

}  // namespace ropecast::tools
