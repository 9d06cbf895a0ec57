// convert --crop's source: a box of voxels of another source, read slab by slab.
#include "store/cropped_source.h"

#include <gtest/gtest.h>

#include <numeric>

#include "core/error.h"
#include "store/array_source.h"

namespace ropecast {
namespace {

template <typename T>
std::unique_ptr<VolumeSource> iotaSource(glm::u32vec3 dims, SampleType type) {
  VolumeInfo info;
  info.dims = dims;
  info.type = type;
  info.spacing = {0.5, 1.0, 2.0};
  info.valueMin = 0.0;
  info.valueMax = 1e6;
  info.description = "iota";
  std::vector<T> samples(info.sampleCount());
  for (size_t i = 0; i < samples.size(); ++i) samples[i] = T(i * 7 + i / 1000);  // no row repeats another
  return std::make_unique<ArraySource>(ArraySource::fromSamples<T>(info, samples));
}

template <typename T>
T sampleOf(const VolumeSource& whole, glm::u32vec3 p) {
  const glm::u32vec3 d = whole.info().dims;
  const size_t i = (size_t(p.z) * d.y + p.y) * d.x + p.x;
  return T(i * 7 + i / 1000);
}

TEST(CroppedSource, ReadsTheSamplesOfTheBoxAndSaysWhatItIs) {
  std::unique_ptr<VolumeSource> whole = iotaSource<uint16_t>({7, 5, 6}, SampleType::UInt16);
  const VolumeSource& original = *whole;
  const std::unique_ptr<VolumeSource> crop = cropVolumeSource(std::move(whole), {1, 2, 1}, {6, 5, 5});
  const VolumeInfo& info = crop->info();
  EXPECT_EQ(info.dims, glm::u32vec3(5, 3, 4));
  EXPECT_EQ(info.type, SampleType::UInt16);
  EXPECT_EQ(info.spacing, glm::dvec3(0.5, 1.0, 2.0));
  EXPECT_EQ(info.description, "iota cropped to 1:6,2:5,1:5");
  EXPECT_FALSE(info.origin);  // placed nowhere, as the whole
  // The whole volume's range may be wider than the box's: the converter finds the box's.
  EXPECT_FALSE(info.valueMin);
  EXPECT_FALSE(info.valueMax);
  std::vector<uint16_t> out(5 * 3 * 2);
  crop->readSlab(1, 2, std::as_writable_bytes(std::span(out)));
  size_t i = 0;
  for (uint32_t z = 0; z < 2; ++z)
    for (uint32_t y = 0; y < 3; ++y)
      for (uint32_t x = 0; x < 5; ++x)
        EXPECT_EQ(out[i++], sampleOf<uint16_t>(original, {x + 1, y + 2, z + 2})) << x << "," << y << "," << z;
}

// The box's first sample is where the whole volume places its sample `begin`, along its own axes.
TEST(CroppedSource, MovesTheOriginToTheBoxsFirstSample) {
  VolumeInfo info;
  info.dims = {7, 5, 6};
  info.spacing = {0.5, 1.0, 2.0};
  info.axes = AxisDirections(glm::dvec3(0, 1, 0), glm::dvec3(0, 0, -1), glm::dvec3(-1, 0, 0));
  info.origin = glm::dvec3(10.0, -20.0, 30.0);
  const std::vector<uint8_t> samples(info.sampleCount(), 1);
  const auto crop = cropVolumeSource(
      std::make_unique<ArraySource>(ArraySource::fromSamples<uint8_t>(info, samples)), {2, 1, 3}, {6, 5, 5});
  // x: 2 * 0.5 along +y; y: 1 * 1 along -z; z: 3 * 2 along -x.
  EXPECT_EQ(crop->info().origin, glm::dvec3(10.0 - 6.0, -20.0 + 1.0, 30.0 - 1.0));
  EXPECT_EQ(crop->info().axes, info.axes);
}

TEST(CroppedSource, ReadsSlabsOfLargeSlicesAFewSlicesAtATime) {
  // 4 MiB slices: the wrapped source is read four slices at a time.
  std::unique_ptr<VolumeSource> whole = iotaSource<uint8_t>({2048, 2048, 9}, SampleType::UInt8);
  const VolumeSource& original = *whole;
  const std::unique_ptr<VolumeSource> crop =
      cropVolumeSource(std::move(whole), {1000, 3, 0}, {1003, 2045, 9});
  std::vector<uint8_t> out(3 * 2042 * 9);
  crop->readSlab(0, 9, std::as_writable_bytes(std::span(out)));
  size_t i = 0, wrong = 0;
  for (uint32_t z = 0; z < 9; ++z)
    for (uint32_t y = 0; y < 2042; ++y)
      for (uint32_t x = 0; x < 3; ++x) wrong += out[i++] != sampleOf<uint8_t>(original, {x + 1000, y + 3, z});
  EXPECT_EQ(wrong, 0u);
}

TEST(CroppedSource, RefusesABoxThatIsEmptyOrLeavesTheVolume) {
  for (auto [begin, end] : {std::pair{glm::u32vec3(0), glm::u32vec3(8, 5, 6)},
                            std::pair{glm::u32vec3(2, 0, 0), glm::u32vec3(2, 5, 6)},
                            std::pair{glm::u32vec3(3, 0, 0), glm::u32vec3(1, 5, 6)}}) {
    try {
      cropVolumeSource(iotaSource<uint16_t>({7, 5, 6}, SampleType::UInt16), begin, end);
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("crop of 'iota': the voxels"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("are not a box inside its 7x5x6"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace ropecast
