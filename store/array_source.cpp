#include "store/array_source.h"

#include <cstring>
#include <string>

#include "core/error.h"

namespace ropecast {

ArraySource::ArraySource(VolumeInfo info, std::vector<std::byte> samples)
    : info_(std::move(info)), samples_(std::move(samples)) {
  const uint64_t expected = info_.sampleCount() * bytesPerSample(info_.type);
  if (samples_.size() != expected)
    throw Error("ArraySource: expected " + std::to_string(expected) +
                " bytes for the given dims and type, got " + std::to_string(samples_.size()));
  if (info_.description.empty()) info_.description = "array";
}

void ArraySource::readSlices(uint32_t z0, uint32_t count, std::span<std::byte> out) {
  const size_t sliceBytes = info_.sliceBytes();
  if (count > 0) std::memcpy(out.data(), samples_.data() + sliceBytes * z0, sliceBytes * count);
}

}  // namespace ropecast
