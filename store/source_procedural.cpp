#include "store/source_procedural.h"

#include <algorithm>
#include <string>
#include <thread>
#include <vector>

#include "core/error.h"

namespace ropecast {
namespace {

// Below this many samples a slab is generated on the calling thread (thread start-up would dominate).
constexpr uint64_t kSamplesPerThreadMin = uint64_t(1) << 16;

class ProceduralSource final : public VolumeSource {
 public:
  ProceduralSource(ProceduralField field, glm::dvec3 spacing) : field_(field) {
    info_.dims = glm::u32vec3(field.size);
    info_.spacing = spacing;
    info_.type = SampleType::UInt8;
    info_.valueMin = 0.0;
    info_.valueMax = 255.0;
    info_.description = proceduralSpecOf(field);
  }

  const VolumeInfo& info() const override { return info_; }

 private:
  void readSlices(uint32_t z0, uint32_t count, std::span<std::byte> out) override {
    generateProceduralSlab(field_, z0, count, out);
  }

  ProceduralField field_;
  VolumeInfo info_;
};

}  // namespace

void generateProceduralSlab(const ProceduralField& field, uint32_t z0, uint32_t count,
                            std::span<std::byte> out, unsigned threadCount) {
  const uint64_t size = field.size;
  const uint64_t rows = uint64_t(count) * size;  // rows of `size` samples, (y, z) flattened
  auto fillRows = [&](uint64_t rowBegin, uint64_t rowEnd) {
    for (uint64_t row = rowBegin; row < rowEnd; ++row) {
      const uint32_t y = uint32_t(row % size);
      const uint32_t z = z0 + uint32_t(row / size);
      std::byte* dst = out.data() + row * size;
      for (uint32_t x = 0; x < size; ++x) dst[x] = std::byte(proceduralSample(field, x, y, z));
    }
  };
  if (threadCount == 0) threadCount = std::max(1u, std::thread::hardware_concurrency());
  const uint64_t workers =
      std::clamp<uint64_t>(rows * size / kSamplesPerThreadMin, 1, std::min<uint64_t>(threadCount, rows));
  if (workers <= 1) {
    fillRows(0, rows);
    return;
  }
  std::vector<std::jthread> threads;
  for (uint64_t w = 1; w < workers; ++w)
    threads.emplace_back(fillRows, rows * w / workers, rows * (w + 1) / workers);
  fillRows(0, rows / workers);
}

std::unique_ptr<VolumeSource> openProceduralSource(std::string_view nameAndSize,
                                                   const SourceOptions& options) {
  const ProceduralField field = parseProceduralField(nameAndSize);
  return std::make_unique<ProceduralSource>(field, options.spacing.value_or(glm::dvec3(1.0)));
}

}  // namespace ropecast
