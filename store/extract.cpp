#include "store/extract.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include <glm/common.hpp>

#include "core/error.h"
#include "store/store_writer.h"
#include "store/volume_source.h"

namespace ropecast {

namespace {

// The data value of a stored sample as the integer type I: rounded to nearest, within I's range.
template <typename I>
I roundedData(uint16_t stored, const ValueMapping& mapping) {
  const double v = std::nearbyint(mapping.toData(stored));
  return I(std::clamp(v, double(std::numeric_limits<I>::min()), double(std::numeric_limits<I>::max())));
}

// Writes one stored sample in the original type.
void writeOriginal(uint16_t stored, SampleType type, const ValueMapping& mapping, std::byte* out) {
  switch (type) {
    case SampleType::UInt8:
      *out = std::byte(stored);
      return;
    case SampleType::Int8:
      *out = std::byte(uint8_t(int8_t(int32_t(stored) - 128)));
      return;
    case SampleType::UInt16:
      std::memcpy(out, &stored, 2);
      return;
    case SampleType::Int16: {
      const int16_t v = int16_t(int32_t(stored) - 32768);
      std::memcpy(out, &v, 2);
      return;
    }
    case SampleType::UInt32: {
      const uint32_t v = roundedData<uint32_t>(stored, mapping);
      std::memcpy(out, &v, 4);
      return;
    }
    case SampleType::Int32: {
      const int32_t v = roundedData<int32_t>(stored, mapping);
      std::memcpy(out, &v, 4);
      return;
    }
    case SampleType::Float32: {
      const float v = float(mapping.toData(stored));
      std::memcpy(out, &v, 4);
      return;
    }
    case SampleType::Float64: {
      const double v = mapping.toData(stored);
      std::memcpy(out, &v, 8);
      return;
    }
  }
}

}  // namespace

glm::u32vec3 levelDimsOf(const BrickSource& source, uint32_t level) {
  const OctreeLayout& layout = source.info().layout;
  if (level > layout.maxDepth)
    throw UsageError("extract: --level " + std::to_string(level) + ": the store has levels 0.." +
                     std::to_string(layout.maxDepth));
  return layout.levelDims(level);
}

void extractLevel(const BrickSource& source, uint32_t level,
                  const std::function<void(std::span<const std::byte>)>& sink, const LevelRegion& region) {
  const BrickSourceInfo& info = source.info();
  const OctreeLayout& layout = info.layout;
  const glm::u32vec3 levelDims = levelDimsOf(source, level);
  const uint32_t depth = layout.maxDepth - level, b = layout.brickSize, edge = layout.storedBrickEdge();
  const glm::u32vec3 begin = region.begin, end = glm::min(region.end, levelDims);
  for (int axis = 0; axis < 3; ++axis)
    if (!(begin[axis] < end[axis]))
      throw UsageError("extract: the region from voxel " + formatDims(begin) + " to " + formatDims(end) +
                       " holds no voxel of level " + std::to_string(level) + " (" + formatDims(levelDims) +
                       ")");
  const glm::u32vec3 dims = end - begin;  // of the output
  const SampleType type = info.volume.type;
  const size_t outBytes = bytesPerSample(type), sliceBytes = size_t(dims.x) * dims.y * outBytes;
  std::vector<std::byte> brick(source.brickBytes());
  std::vector<std::byte> slab;
  for (uint32_t row = begin.z / b; row * b < end.z; ++row) {
    // The row's slices inside the region, [za, zb) in level voxels.
    const uint32_t za = std::max(row * b, begin.z), zb = std::min((row + 1) * b, end.z);
    slab.assign(size_t(zb - za) * sliceBytes, std::byte{0});
    for (uint32_t cy = begin.y / b; cy * b < end.y; ++cy) {
      const uint32_t ya = std::max(cy * b, begin.y), yb = std::min((cy + 1) * b, end.y);
      for (uint32_t cx = begin.x / b; cx * b < end.x; ++cx) {
        const uint32_t xa = std::max(cx * b, begin.x), xb = std::min((cx + 1) * b, end.x);
        source.readBrick({depth, {cx, cy, row}}, brick);
        for (uint32_t z = za; z < zb; ++z)
          for (uint32_t y = ya; y < yb; ++y) {
            // The brick's sample (xa, y, z), behind its border.
            const size_t in =
                (size_t(z - row * b + kBrickBorder) * edge + (y - cy * b + kBrickBorder)) * edge +
                (xa - cx * b + kBrickBorder);
            std::byte* out = slab.data() + (z - za) * sliceBytes +
                             ((size_t(y) - begin.y) * dims.x + (xa - begin.x)) * outBytes;
            for (uint32_t i = 0; i < xb - xa; ++i) {
              uint16_t stored;
              if (info.storedType == SampleType::UInt8)
                stored = uint16_t(brick[in + i]);
              else
                std::memcpy(&stored, brick.data() + 2 * (in + i), 2);
              writeOriginal(stored, type, info.mapping, out + i * outBytes);
            }
          }
      }
    }
    sink(slab);
  }
}

std::vector<std::byte> extractLevelBytes(const BrickSource& source, uint32_t level,
                                         const LevelRegion& region) {
  std::vector<std::byte> all;
  extractLevel(
      source, level,
      [&](std::span<const std::byte> piece) { all.insert(all.end(), piece.begin(), piece.end()); }, region);
  return all;
}

void extractLevelToFile(const BrickSource& source, uint32_t level, const std::filesystem::path& output,
                        const LevelRegion& region) {
  TemporaryFile file(output, "extract");
  uint64_t offset = 0;
  extractLevel(
      source, level,
      [&](std::span<const std::byte> piece) {
        file.writeAt(offset, piece);
        offset += piece.size();
      },
      region);
  file.commit();
}

}  // namespace ropecast
