// What the viewer draws over its 3D view: while the crop box and clip plane are edited, the crop box's
// edges and the polygon where the clip plane cuts the drawn box, projected as the camera's rays see them
// (core/camera.h pixelRay); its ruler; and its orientation marks, the sides of the patient the view's edges
// face and the volume's axes as a triad. GL-free; main thread.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
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

// The segment between two points given in the volume's own axes (the viewer's ruler), as a view of `camera`
// shows it; nullopt where it lies wholly behind the eye.
std::optional<ScreenSegment> segmentOutline(const Camera& camera, uint32_t width, uint32_t height,
                                            const PlacedBox& box, glm::dvec3 a, glm::dvec3 b);

// The sides of the patient (core/orientation.h directionLetters) that the edges of a view of `camera`
// face: where the camera's right, up and their opposites point in the world.
struct EdgeLetters {
  std::string left, right, top, bottom;
};
EdgeLetters edgeLetters(const Camera& camera);

// The volume's x, y and z axes (their world directions: `axes`, core/orientation.h) as a view of `camera`
// turns them, for an orientation triad drawn without perspective: each axis's unit vector on the screen (x
// right, y down; length 1 where the axis lies in the image plane, 0 where it points along the view) and how
// far it points toward the eye (the triad draws the farthest first).
struct TriadAxis {
  glm::dvec2 screen{0.0};
  double towardEye = 0.0;
};
std::array<TriadAxis, 3> axesTriad(const Camera& camera, const AxisDirections& axes);

}  // namespace ropecast::tools
