#include "store/volume_source.h"

#include <string>

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

}  // namespace ropecast
