#include "store/chunk_layer.h"

#include <cstring>

#include <glm/common.hpp>

namespace ropecast {

ChunkLayer::ChunkLayer(glm::u32vec3 dims, SampleType type, uint64_t chunkDepth, uint64_t maxBytes)
    : dims_(dims),
      sampleBytes_(bytesPerSample(type)),
      sliceBytes_(size_t(dims.x) * dims.y * bytesPerSample(type)),
      chunkDepth_(std::max<uint64_t>(chunkDepth, 1)),
      fits_(std::max<uint64_t>(1, maxBytes / std::max<size_t>(sliceBytes_, 1))) {}

void ChunkLayer::read(uint32_t z0, uint32_t count, std::span<std::byte> out,
                      const std::function<void(uint64_t z)>& decode) {
  for (uint32_t done = 0; done < count;) {
    const uint64_t z = uint64_t(z0) + done;
    if (z < begin_ || z >= end_) {
      try {
        decode(z);
      } catch (...) {
        clear();
        throw;
      }
    }
    const uint32_t slices = uint32_t(std::min<uint64_t>(count - done, end_ - z));
    std::memcpy(out.data() + size_t(done) * sliceBytes_, buffer_.data() + (z - begin_) * sliceBytes_,
                size_t(slices) * sliceBytes_);
    done += slices;
  }
}

uint64_t ChunkLayer::begin(uint64_t z) {
  const uint64_t layer = z / chunkDepth_;
  const uint64_t layerEnd = std::min<uint64_t>((layer + 1) * chunkDepth_, dims_.z);
  const uint64_t first = layerEnd - layer * chunkDepth_ <= fits_ ? layer * chunkDepth_ : z;
  const uint64_t last = std::min(layerEnd, first + fits_);
  buffer_.resize(size_t(last - first) * sliceBytes_);
  begin_ = first, end_ = last;
  return layer;
}

void ChunkLayer::place(const std::byte* samples, glm::u64vec3 stride, glm::u64vec3 origin, glm::u64vec3 box) {
  if (origin.x >= dims_.x || origin.y >= dims_.y || origin.z >= dims_.z) return;  // an edge chunk's padding
  const glm::u64vec3 extent = glm::min(box, dims_ - origin);
  const size_t width = sampleBytes_;
  const uint64_t zBegin = std::max(origin.z, begin_), zEnd = std::min(origin.z + extent.z, end_);
  for (uint64_t slice = zBegin; slice < zEnd; ++slice)
    for (uint64_t y = 0; y < extent.y; ++y) {
      std::byte* target =
          buffer_.data() + (((slice - begin_) * dims_.y + origin.y + y) * dims_.x + origin.x) * width;
      const std::byte* source = samples + ((slice - origin.z) * stride.z + y * stride.y) * width;
      if (stride.x == 1) {
        std::memcpy(target, source, extent.x * width);
      } else {
        for (uint64_t x = 0; x < extent.x; ++x)
          std::memcpy(target + x * width, source + x * stride.x * width, width);
      }
    }
}

}  // namespace ropecast
