#include "store/cropped_source.h"

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "core/error.h"

namespace ropecast {

namespace {

// Slices of the wrapped source read at once: about this many bytes, at least one slice.
constexpr size_t kReadChunkBytes = size_t(16) << 20;

std::string rangesText(glm::u32vec3 begin, glm::u32vec3 end) {
  std::string text;
  for (int axis = 0; axis < 3; ++axis)
    text += (axis ? "," : "") + std::to_string(begin[axis]) + ":" + std::to_string(end[axis]);
  return text;
}

class CroppedSource final : public VolumeSource {
 public:
  CroppedSource(std::unique_ptr<VolumeSource> source, glm::u32vec3 begin, glm::u32vec3 end)
      : source_(std::move(source)), begin_(begin) {
    info_ = source_->info();
    info_.dims = end - begin;
    if (info_.origin) info_.origin = *info_.origin + info_.axes * (glm::dvec3(begin) * info_.spacing);
    info_.valueMin.reset();
    info_.valueMax.reset();
    info_.description += " cropped to " + rangesText(begin, end);
  }

  const VolumeInfo& info() const override { return info_; }

 private:
  void readSlices(uint32_t z0, uint32_t count, std::span<std::byte> out) override {
    const VolumeInfo& whole = source_->info();
    const size_t sample = bytesPerSample(whole.type);
    const size_t rowBytes = size_t(info_.dims.x) * sample;
    const size_t wholeSlice = whole.sliceBytes();
    const uint32_t chunk = uint32_t(std::clamp<size_t>(kReadChunkBytes / wholeSlice, 1, count));
    std::byte* to = out.data();
    for (uint32_t done = 0; done < count; done += chunk) {
      const uint32_t slices = std::min(chunk, count - done);
      buffer_.resize(size_t(slices) * wholeSlice);
      source_->readSlab(begin_.z + z0 + done, slices, buffer_);
      for (uint32_t z = 0; z < slices; ++z)
        for (uint32_t y = 0; y < info_.dims.y; ++y) {
          const size_t from = z * wholeSlice + (size_t(begin_.y + y) * whole.dims.x + begin_.x) * sample;
          std::memcpy(to, buffer_.data() + from, rowBytes);
          to += rowBytes;
        }
    }
  }

  std::unique_ptr<VolumeSource> source_;
  glm::u32vec3 begin_;
  VolumeInfo info_;
  std::vector<std::byte> buffer_;
};

}  // namespace

std::unique_ptr<VolumeSource> cropVolumeSource(std::unique_ptr<VolumeSource> source, glm::u32vec3 begin,
                                               glm::u32vec3 end) {
  const glm::u32vec3 dims = source->info().dims;
  for (int axis = 0; axis < 3; ++axis)
    if (!(begin[axis] < end[axis]) || end[axis] > dims[axis])
      throw Error("crop of '" + source->info().description + "': the voxels " + rangesText(begin, end) +
                  " are not a box inside its " + formatDims(dims));
  return std::make_unique<CroppedSource>(std::move(source), begin, end);
}

}  // namespace ropecast
