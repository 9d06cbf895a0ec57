#include "tools/view_probe.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

namespace ropecast::tools {

std::optional<ProbedVoxel> probedVoxel(const Camera& worldCamera, uint32_t width, uint32_t height,
                                       glm::u32vec2 pixel, double depth, const VolumeInfo& volume) {
  if (!std::isfinite(depth) || width == 0 || height == 0) return std::nullopt;
  const Ray ray = pixelRay(worldCamera, width, height, pixel.x, pixel.y);
  const double alongView = glm::dot(ray.dir, cameraFrame(worldCamera).forward);
  if (!(alongView > 0.0)) return std::nullopt;
  ProbedVoxel probed;
  probed.world = ray.origin + ray.dir * (depth / alongView);
  // The volume is turned about its center (core/orientation.h); its directions' inverse is their transpose.
  const glm::dvec3 center = 0.5 * volume.worldMax();
  probed.point = center + glm::transpose(volume.axes) * (probed.world - center);
  // The ray stops inside the volume's box, but a point on its faces may round to just outside it.
  const glm::dvec3 index = glm::floor(probed.point / volume.spacing);
  probed.voxel = glm::u32vec3(glm::clamp(index, glm::dvec3(0.0), glm::dvec3(volume.dims) - 1.0));
  if (volume.origin) probed.file = probed.world + fileFrameOffset(volume);
  return probed;
}

std::string voxelText(glm::u32vec3 voxel) {
  char text[64];
  std::snprintf(text, sizeof text, "voxel %u, %u, %u", voxel.x, voxel.y, voxel.z);
  return text;
}

std::string probeText(const ProbedVoxel& probed, std::optional<double> value) {
  char number[32] = "(reading)";
  if (value) std::snprintf(number, sizeof number, "%.7g", *value);
  char text[160];
  std::snprintf(text, sizeof text, "  value %s  at %.6g, %.6g, %.6g", number, probed.world.x, probed.world.y,
                probed.world.z);
  char file[96] = "";
  if (probed.file)
    std::snprintf(file, sizeof file, "  file %.6g, %.6g, %.6g", probed.file->x, probed.file->y,
                  probed.file->z);
  return voxelText(probed.voxel) + text + file;
}

std::string rulerText(const ProbedVoxel& a, const ProbedVoxel& b) {
  char text[32];
  std::snprintf(text, sizeof text, "length %.4g from ", glm::length(b.point - a.point));
  return text + voxelText(a.voxel) + " to " + voxelText(b.voxel);
}

}  // namespace ropecast::tools
