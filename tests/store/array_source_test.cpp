#include "store/array_source.h"

#include <gtest/gtest.h>

#include <numeric>

#include "core/error.h"

namespace ropecast {
namespace {

VolumeInfo info16(glm::u32vec3 dims) {
  VolumeInfo info;
  info.dims = dims;
  info.type = SampleType::UInt16;
  return info;
}

TEST(ArraySource, ReadsTheRequestedSlices) {
  std::vector<uint16_t> samples(3 * 2 * 5);
  std::iota(samples.begin(), samples.end(), uint16_t(100));
  ArraySource source = ArraySource::fromSamples<uint16_t>(info16({3, 2, 5}), samples);
  std::vector<uint16_t> out(3 * 2 * 2);
  source.readSlab(2, 2, std::as_writable_bytes(std::span(out)));
  for (size_t i = 0; i < out.size(); ++i) EXPECT_EQ(out[i], samples[2 * 6 + i]);
}

TEST(ArraySource, RejectsSlicesOutsideTheVolumeAndWrongBuffers) {
  std::vector<uint16_t> samples(3 * 2 * 5);
  ArraySource source = ArraySource::fromSamples<uint16_t>(info16({3, 2, 5}), samples);
  std::vector<uint16_t> out(3 * 2 * 2);
  EXPECT_THROW(source.readSlab(4, 2, std::as_writable_bytes(std::span(out))), Error);
  EXPECT_THROW(source.readSlab(0, 1, std::as_writable_bytes(std::span(out))), Error);
}

TEST(ArraySource, RejectsSampleCountThatDoesNotMatchDims) {
  std::vector<uint16_t> samples(7);
  EXPECT_THROW(ArraySource::fromSamples<uint16_t>(info16({3, 2, 5}), samples), Error);
}

}  // namespace
}  // namespace ropecast
