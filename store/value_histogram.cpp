#include "store/value_histogram.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace ropecast {

ValueHistogram coarseHistogram(const BrickSource& source, uint32_t bins, double minValue, double maxValue) {
  const BrickSourceInfo& info = source.info();
  const OctreeLayout& layout = info.layout;
  ValueHistogram h;
  h.minValue = minValue;
  h.maxValue = maxValue > minValue ? maxValue : minValue + 1.0;
  h.counts.assign(std::max(1u, bins), 0);
  h.level = layout.levelOfDepth(0);
  const NodeKey root{0, glm::u32vec3(0)};
  if (source.node(root).kind == NodeKind::Outside) return h;

  std::vector<std::byte> brick(source.brickBytes());
  source.readBrick(root, brick);
  const glm::u32vec3 dims = layout.levelDims(h.level);
  const uint32_t edge = layout.storedBrickEdge();
  const bool wide = info.storedType == SampleType::UInt16;
  const double binWidth = (h.maxValue - h.minValue) / double(h.counts.size());
  for (uint32_t z = 0; z < std::min(dims.z, layout.brickSize); ++z)
    for (uint32_t y = 0; y < std::min(dims.y, layout.brickSize); ++y)
      for (uint32_t x = 0; x < std::min(dims.x, layout.brickSize); ++x) {
        const size_t i = (size_t(z + kBrickBorder) * edge + (y + kBrickBorder)) * edge + (x + kBrickBorder);
        uint32_t stored = 0;
        if (wide) {
          uint16_t v = 0;
          std::memcpy(&v, brick.data() + i * 2, 2);
          stored = v;
        } else {
          stored = uint32_t(brick[i]);
        }
        const double value = info.mapping.toData(double(stored));
        const double bin = std::floor((value - h.minValue) / binWidth);
        h.counts[size_t(std::clamp(bin, 0.0, double(h.counts.size() - 1)))] += 1;
      }
  return h;
}

}  // namespace ropecast
