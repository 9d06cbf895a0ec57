// ArraySource: an in-memory VolumeSource over a byte vector, for tests and small tools.
// Owned by whoever built it. info() from any thread; readSlab() from one thread at a time (VolumeSource).
#pragma once

#include <cstddef>
#include <cstring>
#include <span>
#include <vector>

#include "store/volume_source.h"

namespace ropecast {

class ArraySource final : public VolumeSource {
 public:
  // `samples` holds info.sampleCount() samples of info.type, x fastest. Throws ropecast::Error if the size
  // does not match.
  ArraySource(VolumeInfo info, std::vector<std::byte> samples);

  // Builds one from typed samples (T = uint8_t, uint16_t, int16_t or float).
  template <typename T>
  static ArraySource fromSamples(VolumeInfo info, std::span<const T> samples) {
    std::vector<std::byte> bytes(samples.size_bytes());
    if (!bytes.empty()) std::memcpy(bytes.data(), samples.data(), bytes.size());
    return ArraySource(std::move(info), std::move(bytes));
  }

  const VolumeInfo& info() const override { return info_; }
  std::span<const std::byte> bytes() const { return samples_; }

 private:
  void readSlices(uint32_t z0, uint32_t count, std::span<std::byte> out) override;

  VolumeInfo info_;
  std::vector<std::byte> samples_;
};

}  // namespace ropecast
