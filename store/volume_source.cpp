#include "store/volume_source.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/header_text.h"
#include "core/number_text.h"

namespace ropecast {

void VolumeSource::readSlab(uint32_t z0, uint32_t count, std::span<std::byte> out) {
  const VolumeInfo& volume = info();
  if (uint64_t(z0) + count > volume.dims.z)
    throw Error("readSlab: slices [" + std::to_string(z0) + ", " + std::to_string(uint64_t(z0) + count) +
                ") outside " + volume.description + " (" + std::to_string(volume.dims.z) + " slices)");
  const uint64_t bytes = uint64_t(count) * volume.sliceBytes();
  if (out.size() != bytes)
    throw Error("readSlab: " + volume.description + ": output buffer has " + std::to_string(out.size()) +
                " bytes, expected " + std::to_string(bytes));
  readSlices(z0, count, out);
}

glm::dvec3 fileFrameOffset(const VolumeInfo& v) {
  if (!v.origin) return glm::dvec3(0.0);
  // Sample (0, 0, 0) is at origin in the file's frame, at center + axes (0.5 s - center) in the world.
  const glm::dvec3 center = 0.5 * v.worldMax();
  return *v.origin - center - v.axes * (0.5 * v.spacing - center);
}

SizesText parseSizesText(std::string_view text) {
  const auto words = splitWords(text);
  SizesText parsed;
  if (words.size() != 3) return {{0, 0, 0}, "expected 3 positive integers, got " + quotedExcerpt(text)};
  constexpr uint64_t kMaxDataBytes = uint64_t(1) << 62;
  uint64_t bytes = 8;  // the widest sample: the bound holds whatever the type
  for (int axis = 0; axis < 3; ++axis) {
    const auto n = parseWholeNumber<int64_t>(words[axis]);
    if (!n || *n < 1 || *n > int64_t(UINT32_MAX))
      return {{0, 0, 0}, "expected 3 positive integers (each < 2^32), got " + quotedExcerpt(text)};
    if (bytes > kMaxDataBytes / uint64_t(*n))
      return {{0, 0, 0}, quotedExcerpt(text) + " is too large (more than 2^62 bytes of data)"};
    bytes *= uint64_t(*n);
    parsed.sizes[axis] = uint32_t(*n);
  }
  return parsed;
}

std::string unappliedTransformNote(const std::string& path, const std::string& transform) {
  return path + ": " + transform +
         " does not keep the axes at right angles (a sheared grid); it is not applied, so the volume is "
         "shown "
         "unsheared and axis-aligned";
}

}  // namespace ropecast
