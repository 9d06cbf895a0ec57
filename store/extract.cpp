#include "store/extract.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "core/error.h"
#include "store/store_writer.h"

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

void extractLevel(const BrickSource& source, uint32_t level,
                  const std::function<void(std::span<const std::byte>)>& sink) {
  const BrickSourceInfo& info = source.info();
  const OctreeLayout& layout = info.layout;
  if (level > layout.maxDepth)
    throw UsageError("extract: --level " + std::to_string(level) + ": the store has levels 0.." +
                     std::to_string(layout.maxDepth));
  const uint32_t depth = layout.maxDepth - level, b = layout.brickSize, edge = layout.storedBrickEdge();
  const glm::u32vec3 dims = layout.levelDims(level), nodes = layout.insideNodes(depth);
  const SampleType type = info.volume.type;
  const size_t outBytes = bytesPerSample(type), sliceBytes = size_t(dims.x) * dims.y * outBytes;
  std::vector<std::byte> brick(source.brickBytes());
  std::vector<std::byte> slab;
  for (uint32_t row = 0; row < nodes.z; ++row) {
    const uint32_t z0 = row * b, slices = std::min(b, dims.z - z0);
    slab.assign(size_t(slices) * sliceBytes, std::byte{0});
    for (uint32_t cy = 0; cy < nodes.y; ++cy) {
      for (uint32_t cx = 0; cx < nodes.x; ++cx) {
        source.readBrick({depth, {cx, cy, row}}, brick);
        const uint32_t x0 = cx * b, y0 = cy * b;
        const uint32_t nx = std::min(b, dims.x - x0), ny = std::min(b, dims.y - y0);
        for (uint32_t k = 0; k < slices; ++k)
          for (uint32_t j = 0; j < ny; ++j) {
            const size_t in = (size_t(k + kBrickBorder) * edge + (j + kBrickBorder)) * edge + kBrickBorder;
            std::byte* out = slab.data() + k * sliceBytes + ((size_t(y0) + j) * dims.x + x0) * outBytes;
            for (uint32_t i = 0; i < nx; ++i) {
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

std::vector<std::byte> extractLevelBytes(const BrickSource& source, uint32_t level) {
  std::vector<std::byte> all;
  extractLevel(source, level,
               [&](std::span<const std::byte> piece) { all.insert(all.end(), piece.begin(), piece.end()); });
  return all;
}

void extractLevelToFile(const BrickSource& source, uint32_t level, const std::filesystem::path& output) {
  TemporaryFile file(output, "extract");
  uint64_t offset = 0;
  extractLevel(source, level, [&](std::span<const std::byte> piece) {
    file.writeAt(offset, piece);
    offset += piece.size();
  });
  file.commit();
}

}  // namespace ropecast
