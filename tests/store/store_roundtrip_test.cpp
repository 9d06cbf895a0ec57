// Round trips through convert -> Store -> extract for every sample type and odd sizes.
#include <gtest/gtest.h>

#include <limits>

#include "core/error.h"
#include "store/converter.h"
#include "store/extract.h"
#include "store/store.h"
#include "store/verify.h"
#include "tests/store/store_test_util.h"

namespace ropecast {
namespace {

using testing::TempDir;

// Level 0 of a float32 store, as extract writes it.
std::vector<float> level0Floats(const Store& store) {
  const std::vector<std::byte> bytes = extractLevelBytes(store, 0);
  std::vector<float> floats(bytes.size() / sizeof(float));
  std::memcpy(floats.data(), bytes.data(), floats.size() * sizeof(float));
  return floats;
}

template <typename T>
void expectLevel0ByteIdentical(SampleType type, double lo, double hi, glm::u32vec3 dims, uint32_t brick) {
  TempDir dir;
  const std::vector<T> samples = testing::toType<T>(testing::ballField(dims, 7), lo, hi);
  ArraySource source = ArraySource::fromSamples<T>(testing::volumeInfo(dims, type), samples);
  ConvertOptions options;
  options.brickSize = brick;
  convertVolume(source, dir / "v.store", options);
  const auto store = Store::open(dir / "v.store");
  const std::vector<std::byte> extracted = extractLevelBytes(*store, 0);
  ASSERT_EQ(extracted.size(), source.bytes().size());
  EXPECT_TRUE(std::equal(extracted.begin(), extracted.end(), source.bytes().begin()))
      << "level 0 of a " << sampleTypeName(type) << " store differs from its source";
  EXPECT_EQ(store->info().volume.type, type);
  EXPECT_EQ(store->info().storedType, storedTypeFor(type));
  const auto [mn, mx] = std::minmax_element(samples.begin(), samples.end());
  EXPECT_EQ(*store->info().volume.valueMin, double(*mn));
  EXPECT_EQ(*store->info().volume.valueMax, double(*mx));
  const VerifyReport report = verifyStore(*store);
  EXPECT_TRUE(report.ok()) << (report.problems.empty() ? "" : report.problems.front());
}

TEST(StoreRoundTrip, UInt8Level0IsByteIdentical) {
  expectLevel0ByteIdentical<uint8_t>(SampleType::UInt8, 3, 250, {45, 37, 29}, 8);
}
TEST(StoreRoundTrip, UInt16Level0IsByteIdentical) {
  expectLevel0ByteIdentical<uint16_t>(SampleType::UInt16, 100, 60000, {45, 37, 29}, 8);
}
TEST(StoreRoundTrip, Int16Level0IsByteIdentical) {
  expectLevel0ByteIdentical<int16_t>(SampleType::Int16, -1024, 3071, {45, 37, 29}, 8);
}
TEST(StoreRoundTrip, OddSizesWithOtherBrickSizes) {
  expectLevel0ByteIdentical<uint16_t>(SampleType::UInt16, 0, 4095, {33, 1, 17}, 4);
  expectLevel0ByteIdentical<uint8_t>(SampleType::UInt8, 0, 255, {5, 70, 3}, 16);
}

TEST(StoreRoundTrip, LargeOddUInt16VolumeIsByteIdentical) {
  expectLevel0ByteIdentical<uint16_t>(SampleType::UInt16, 0, 40000, {301, 370, 316}, 32);
}

TEST(StoreRoundTrip, Float32IsQuantizedWithinHalfAStepOverItsRange) {
  TempDir dir;
  const glm::u32vec3 dims{45, 37, 29};
  const std::vector<double> field = testing::ballField(dims, 3);
  std::vector<float> samples(field.size());
  for (size_t i = 0; i < field.size(); ++i) samples[i] = float(-2.5 + 7.0 * field[i]);
  ArraySource source =
      ArraySource::fromSamples<float>(testing::volumeInfo(dims, SampleType::Float32), samples);
  ConvertOptions options;
  options.brickSize = 8;
  std::vector<ConvertProgress::Phase> phases;
  options.progress = [&](const ConvertProgress& p) { phases.push_back(p.phase); };
  convertVolume(source, dir / "f.store", options);
  // No known range: the converter scans it first.
  ASSERT_FALSE(phases.empty());
  EXPECT_EQ(phases.front(), ConvertProgress::Phase::ValueRange);
  EXPECT_EQ(phases.back(), ConvertProgress::Phase::Bricks);

  const auto store = Store::open(dir / "f.store");
  const auto [mn, mx] = std::minmax_element(samples.begin(), samples.end());
  EXPECT_FLOAT_EQ(float(*store->info().volume.valueMin), *mn);
  EXPECT_FLOAT_EQ(float(*store->info().volume.valueMax), *mx);
  const double step = (double(*mx) - *mn) / 65535.0;
  EXPECT_NEAR(store->info().mapping.scale, step, 1e-12);
  const std::vector<float> back = level0Floats(*store);
  ASSERT_EQ(back.size(), samples.size());
  for (size_t i = 0; i < samples.size(); ++i)
    ASSERT_NEAR(back[i], samples[i], 0.5 * step + 1e-6) << "sample " << i;
  EXPECT_TRUE(verifyStore(*store).ok());
}

TEST(StoreRoundTrip, Float32WithAKnownRangeSkipsThePrePassAndClampsOutliers) {
  TempDir dir;
  const glm::u32vec3 dims{9, 8, 7};
  std::vector<float> samples(size_t(dims.x) * dims.y * dims.z);
  for (size_t i = 0; i < samples.size(); ++i) samples[i] = float(i % 50) * 0.1f;  // [0, 4.9]
  samples[3] = -10.0f;                                                            // below the known range
  samples[4] = 99.0f;                                                             // above it
  samples[5] = std::numeric_limits<float>::quiet_NaN();  // no value: the range's low end
  VolumeInfo info = testing::volumeInfo(dims, SampleType::Float32);
  info.valueMin = 0.0;
  info.valueMax = 4.0;
  ArraySource source = ArraySource::fromSamples<float>(info, samples);
  ConvertOptions options;
  options.brickSize = 4;
  std::vector<ConvertProgress::Phase> phases;
  options.progress = [&](const ConvertProgress& p) { phases.push_back(p.phase); };
  convertVolume(source, dir / "k.store", options);
  EXPECT_EQ(std::count(phases.begin(), phases.end(), ConvertProgress::Phase::ValueRange), 0);
  const auto store = Store::open(dir / "k.store");
  EXPECT_EQ(*store->info().volume.valueMin, 0.0);
  EXPECT_EQ(*store->info().volume.valueMax, 4.0);
  const std::vector<float> back = level0Floats(*store);
  ASSERT_EQ(back.size(), samples.size());
  EXPECT_FLOAT_EQ(back[3], 0.0f);
  EXPECT_FLOAT_EQ(back[4], 4.0f);
  EXPECT_FLOAT_EQ(back[5], 0.0f);
  for (size_t i = 6; i < samples.size(); ++i)
    ASSERT_NEAR(back[i], std::min(samples[i], 4.0f), 0.5 * 4.0 / 65535 + 1e-6) << "sample " << i;
}

TEST(StoreRoundTrip, Float32WhoseFiniteValuesAreOneKeepsInfinitiesInTheRange) {
  // Every finite value 5, one +inf and one -inf: the value range is [5, 5], and every sample reads back 5.
  TempDir dir;
  const glm::u32vec3 dims{8, 8, 8};
  std::vector<float> samples(size_t(dims.x) * dims.y * dims.z, 5.0f);
  samples[100] = std::numeric_limits<float>::infinity();
  samples[200] = -std::numeric_limits<float>::infinity();
  ArraySource source =
      ArraySource::fromSamples<float>(testing::volumeInfo(dims, SampleType::Float32), samples);
  ConvertOptions options;
  options.brickSize = 4;
  convertVolume(source, dir / "c.store", options);
  const auto store = Store::open(dir / "c.store");
  EXPECT_EQ(*store->info().volume.valueMin, 5.0);
  EXPECT_EQ(*store->info().volume.valueMax, 5.0);
  const std::vector<float> back = level0Floats(*store);
  ASSERT_EQ(back.size(), samples.size());
  for (size_t i = 0; i < back.size(); ++i) ASSERT_EQ(back[i], 5.0f) << "sample " << i;
}

TEST(StoreRoundTrip, EveryLevelMatchesTheDirectBoxFilter) {
  TempDir dir;
  const glm::u32vec3 dims{45, 37, 29};
  const auto samples = testing::toType<int16_t>(testing::ballField(dims, 11), -1000, 2000);
  ArraySource source =
      ArraySource::fromSamples<int16_t>(testing::volumeInfo(dims, SampleType::Int16), samples);
  ConvertOptions options;
  options.brickSize = 4;
  convertVolume(source, dir / "v.store", options);
  const auto store = Store::open(dir / "v.store");
  const OctreeLayout& layout = store->info().layout;
  const auto levels = testing::levelPyramid(testing::storedValues(samples), layout);
  ASSERT_GE(layout.maxDepth, 3u);
  for (uint32_t level = 0; level <= layout.maxDepth; ++level) {
    const std::vector<std::byte> bytes = extractLevelBytes(*store, level);
    ASSERT_EQ(bytes.size(), levels[level].size() * 2) << "level " << level;
    std::vector<int16_t> got(levels[level].size());
    std::memcpy(got.data(), bytes.data(), bytes.size());
    for (size_t i = 0; i < got.size(); ++i)
      ASSERT_EQ(int32_t(got[i]) + 32768, levels[level][i]) << "level " << level << " sample " << i;
  }
  EXPECT_THROW(extractLevelBytes(*store, layout.maxDepth + 1), Error);
}

TEST(StoreRoundTrip, MetadataKeepsSpacingSourceAndOptions) {
  TempDir dir;
  const glm::u32vec3 dims{20, 9, 13};
  const auto samples = testing::toType<uint8_t>(testing::ballField(dims, 5), 0, 200);
  ArraySource source =
      ArraySource::fromSamples<uint8_t>(testing::volumeInfo(dims, SampleType::UInt8), samples);
  ConvertOptions options;
  options.brickSize = 8;
  options.zstdLevel = 7;
  options.discardBelow = 20.0;
  options.creationTool = "store test";
  convertVolume(source, dir / "m.store", options);
  const auto store = Store::open(dir / "m.store");
  const StoreMetadata& m = store->metadata();
  EXPECT_EQ(m.volume.dims, dims);
  EXPECT_EQ(m.volume.spacing, glm::dvec3(0.5, 0.75, 1.25));
  EXPECT_EQ(m.volume.description, "test volume");
  EXPECT_EQ(m.brickSize, 8u);
  EXPECT_EQ(m.border, kBrickBorder);
  EXPECT_EQ(m.levels, store->info().layout.maxDepth + 1);
  EXPECT_EQ(m.zstdLevel, 7);
  EXPECT_EQ(m.discardBelow, 20.0);
  EXPECT_EQ(m.creationTool, "store test");
}

TEST(StoreRoundTrip, ASourceNameThatIsNotUtf8IsKeptWithReplacementCharacters) {
  TempDir dir;
  const glm::u32vec3 dims{9, 8, 7};
  const auto samples = testing::toType<uint8_t>(testing::ballField(dims, 5), 0, 200);
  VolumeInfo info = testing::volumeInfo(dims, SampleType::UInt8);
  info.description = "scan\xff\xfe.raw";  // a file name Linux allows
  ArraySource source = ArraySource::fromSamples<uint8_t>(info, samples);
  ConvertOptions options;
  options.brickSize = 8;
  convertVolume(source, dir / "n.store", options);
  EXPECT_EQ(Store::open(dir / "n.store")->metadata().volume.description, "scan\uFFFD\uFFFD.raw");
}

}  // namespace
}  // namespace ropecast
