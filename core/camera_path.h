// CameraPath: the cameras of a multi-frame render (`ropecast render --path FILE --frames N`), read from a
// JSON list of keyframes and sampled uniformly. Plain data plus pure functions; any thread.
//
// File format: a JSON array (or {"keyframes": [...]}) of objects, each either
//   {"eye": [x,y,z], "target": [x,y,z], "up": [x,y,z], "fov": deg}      (up and fov optional: defaultUp, 40)
//   {"orbit": [azimuthDeg, elevationDeg, distance], "fov": deg}           (around the volume box, z up;
//                                                                          distance > 0)
//   {"view": "anterior", "distance": d, "fov": deg}                        (a side of the patient, as --view;
//                                                                          distance optional: 3 radii)
// with an optional "time" (seconds, increasing); without times the keyframes are evenly spaced. Frame i of N
// is at time t0 + i/(N-1)·(t1 - t0), interpolated linearly between the keyframes around it (orbit keyframes
// in azimuth/elevation/distance, so a path of orbits turns around the volume instead of cutting through it;
// the four views from the patient's sides are orbits at elevation 0, those from above and below cameras).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/camera.h"
#include "core/orientation.h"

namespace ropecast {

struct CameraKeyframe {
  double time = 0.0;
  bool isOrbit = false;
  glm::dvec3 orbit{0.0};  // azimuthDeg, elevationDeg, distance (isOrbit)
  Camera camera;          // eye/target/up/fov (not isOrbit; fov used by both)
  // The view from above or below the patient, at `viewDistance` radii: its camera depends on the box.
  std::optional<AnatomicalView> view;
  double viewDistance = 0.0;
};

struct CameraPath {
  std::vector<CameraKeyframe> keyframes;  // sorted by time, at least one
};

// Parses the JSON text; `sourceName` is named in errors (ropecast::Error).
CameraPath parseCameraPath(const std::string& text, const std::string& sourceName);
CameraPath loadCameraPath(const std::string& path);

// The camera of frame `frame` of `frameCount` along the path, for a volume box [boxMin, boxMax].
Camera sampleCameraPath(const CameraPath& path, uint32_t frame, uint32_t frameCount, glm::dvec3 boxMin,
                        glm::dvec3 boxMax);

}  // namespace ropecast
