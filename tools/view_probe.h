// The viewer's probe (docs/VIEWER.md "Probe"), which its ruler and centering use too: what lies under a pixel
// of the 3D view. The point where the pixel's ray stopped in the drawn frame, as its depth image holds it (an
// isosurface's hit, a DVR's sample that made it half opaque, a MIP's or MinIP's extreme, an AIP's first
// sample above zero, a slice's point on its plane), and the full-resolution voxel nearest that point, whose
// value the viewer reads from the store (store/async_voxel_reader.h). GL-free; main thread.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "core/camera.h"
#include "store/volume_source.h"

namespace ropecast::tools {

struct ProbedVoxel {
  glm::dvec3 world{0.0};  // the point in the world, where the camera is
  glm::dvec3 point{0.0};  // the same point in the volume's own axes, world units from its corner [0, n s]
  glm::u32vec3 voxel{0};  // the level-0 sample nearest the point (sample i lies at (i + 0.5) s)
  // The same point where the file places its samples (VolumeInfo::origin; LPS for medical volumes: the
  // scanner's coordinates); nullopt for a volume without an origin.
  std::optional<glm::dvec3> file;
};

// Where the ray through pixel `pixel` (x right, y down) of a width x height view of `worldCamera` stopped,
// `depth` world units along the view axis (docs/RENDERING.md: depth = dot(x - eye, forward)). The camera is
// in the world, where the volume is turned by volume.axes about its center (core/orientation.h), as the
// renderers take it. nullopt where the ray met nothing (depth +inf, or not finite).
std::optional<ProbedVoxel> probedVoxel(const Camera& worldCamera, uint32_t width, uint32_t height,
                                       glm::u32vec2 pixel, double depth, const VolumeInfo& volume);

// "voxel 12, 40, 7".
std::string voxelText(glm::u32vec3 voxel);

// The probe's line, as the stats panel and the script's probe event show it: "voxel 12, 40, 7  value 187  at
// 12.43, 40.5, 7.61", the point in the world (where --eye, --target and --clip-plane take points), and for a
// volume with an origin "  file -107.6, 83.2, 30.1", the point in the file's frame. Without a value (its
// brick still being read) "value (reading)".
std::string probeText(const ProbedVoxel& probed, std::optional<double> value);

// The ruler's line between two probed points: "length 23.41 from voxel 12, 40, 7 to voxel 30, 41, 9". The
// length is the points' distance in world units (the spacing's: mm for medical data).
std::string rulerText(const ProbedVoxel& a, const ProbedVoxel& b);

}  // namespace ropecast::tools
