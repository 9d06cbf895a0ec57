// Round trips through convert -> Store -> extract for every sample type and odd sizes; the wider types (int8,
// uint32, int32, float64) from raw and NRRD files, read back through the store's mapping.
#include <gtest/gtest.h>

#include <bit>
#include <cstdio>
#include <fstream>
#include <limits>

#include "core/error.h"
#include "store/converter.h"
#include "store/extract.h"
#include "store/nifti_header.h"
#include "store/store.h"
#include "store/verify.h"
#include "tests/store/store_test_util.h"
#include "tests/store/testutil_round_trip.h"

namespace ropecast {
namespace {

using testing::convertAndOpen;
using testing::expectKept;
using testing::extractedLevel0;
using testing::fileBytes;
using testing::TempDir;
using testing::writeFile;

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

// A volume whose axes mirror (a left-handed frame) is stored with each row reversed and its x axis turned
// around, so that the store's axes are a rotation placing every sample where the source's axes put it; one
// whose axes are a rotation is stored as it is. Extract gives either back in the file's order, a region and a
// voxel in the file's indices.
TEST(StoreRoundTrip, AMirroringVolumeIsStoredWithItsXAxisReversed) {
  const glm::u32vec3 dims{13, 7, 5};
  const std::vector<uint8_t> samples = testing::toType<uint8_t>(testing::ballField(dims, 3), 0, 255);
  VolumeInfo info = testing::volumeInfo(dims, SampleType::UInt8);
  const AxisDirections turned(glm::dvec3(0, 0, 1), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0));
  info.origin = glm::dvec3(10.0, -20.0, 30.0);
  for (const bool mirrored : {false, true}) {
    TempDir dir;
    info.axes = turned;
    if (mirrored) info.axes[0] = -turned[0];
    info.patientFrame = mirrored;  // kept by the store as it is (absent from the metadata when false)
    ArraySource source = ArraySource::fromSamples<uint8_t>(info, samples);
    ConvertOptions options;
    options.brickSize = 4;
    convertVolume(source, dir / "m.store", options);
    const auto store = Store::open(dir / "m.store");
    EXPECT_EQ(store->info().volume.axes, turned) << "mirrored " << mirrored;
    EXPECT_EQ(store->info().xReversed, mirrored);
    EXPECT_EQ(store->info().volume.patientFrame, mirrored);
    // The bricks hold the rows reversed: level 0's node at the store's x = 0 holds the file's last column.
    std::vector<std::byte> brick(store->brickBytes());
    store->readBrick({store->info().layout.maxDepth, {0, 0, 0}}, brick);
    const uint32_t edge = store->info().layout.storedBrickEdge();
    const size_t first = (size_t(kBrickBorder) * edge + kBrickBorder) * edge + kBrickBorder;
    EXPECT_EQ(uint8_t(brick[first]), samples[mirrored ? dims.x - 1 : 0]) << "mirrored " << mirrored;

    const std::vector<std::byte> level0 = extractLevelBytes(*store, 0);
    ASSERT_EQ(level0.size(), samples.size());
    EXPECT_TRUE(std::equal(level0.begin(), level0.end(), samples.begin(),
                           [](std::byte a, uint8_t b) { return uint8_t(a) == b; }))
        << "mirrored " << mirrored << ": extract is not the file's order";
    const std::vector<std::byte> region = extractLevelBytes(*store, 0, {{2, 1, 0}, {7, 3, 1}});
    ASSERT_EQ(region.size(), 10u);
    for (uint32_t y = 1; y < 3; ++y)
      for (uint32_t x = 2; x < 7; ++x)
        EXPECT_EQ(uint8_t(region[(y - 1) * 5 + (x - 2)]), samples[y * dims.x + x])
            << "mirrored " << mirrored << " at " << x << "," << y;
    EXPECT_EQ(voxelValue(*store, 0, {11, 4, 3}), samples[(3 * dims.y + 4) * dims.x + 11]);
    EXPECT_TRUE(verifyStore(*store).ok());

    // The store's origin is its own sample 0's: the file's last along x when x is kept reversed. Every
    // voxel's center in the renderers' world, moved by fileFrameOffset, is where the file places its sample.
    const VolumeInfo& stored = store->info().volume;
    ASSERT_TRUE(stored.origin);
    const glm::dvec3 fileLast = *info.origin + info.axes[0] * (info.spacing.x * (dims.x - 1));
    EXPECT_NEAR(glm::distance(*stored.origin, mirrored ? fileLast : *info.origin), 0.0, 1e-12);
    const glm::dvec3 center = 0.5 * stored.worldMax();
    for (const glm::u32vec3 voxel : {glm::u32vec3(0), glm::u32vec3(11, 4, 3), glm::u32vec3(3, 6, 1)}) {
      const glm::dvec3 world = center + stored.axes * ((glm::dvec3(voxel) + 0.5) * stored.spacing - center);
      const glm::dvec3 fileIndex(fileVoxelX(store->info(), voxel.x, dims.x), voxel.y, voxel.z);
      const glm::dvec3 expected = *info.origin + info.axes * (fileIndex * info.spacing);
      EXPECT_NEAR(glm::distance(world + fileFrameOffset(stored), expected), 0.0, 1e-12)
          << "mirrored " << mirrored << " at voxel " << voxel.x << "," << voxel.y << "," << voxel.z;
    }
    // A region's NRRD header places its first sample, the file's (2, 1, 0), where the file does.
    const std::string header = nrrdHeaderOf(*store, 0, {{2, 1, 0}, {7, 3, 1}});
    const glm::dvec3 regionFirst = *info.origin + info.axes * (glm::dvec3(2, 1, 0) * info.spacing);
    glm::dvec3 written(0.0);
    ASSERT_EQ(std::sscanf(header.c_str() + header.find("space origin: "), "space origin: (%lf,%lf,%lf)",
                          &written.x, &written.y, &written.z),
              3)
        << header;
    EXPECT_NEAR(glm::distance(written, regionFirst), 0.0, 1e-12) << "mirrored " << mirrored << "\n" << header;
    // The NIfTI-1 header of the region, read back as the NIfTI source reads it: the file's axes (a mirroring
    // frame too), spacing, and the first sample's place, to float's precision.
    const std::string nifti = niftiHeaderOf(*store, 0, {{2, 1, 0}, {7, 3, 1}});
    ASSERT_EQ(nifti.size(), kNiftiHeaderBytes);
    const NiftiHeader parsed =
        parseNiftiHeader(std::as_bytes(std::span(nifti.data(), nifti.size())), "r.nii");
    EXPECT_EQ(parsed.sizes, glm::u32vec3(5, 2, 1));
    EXPECT_EQ(parsed.type, SampleType::UInt8);
    EXPECT_EQ(parsed.voxOffset, kNiftiHeaderBytes);
    EXPECT_FALSE(parsed.scaled);
    EXPECT_NEAR(glm::distance(parsed.spacing, info.spacing), 0.0, 1e-6);
    for (int axis = 0; axis < 3; ++axis)
      EXPECT_NEAR(glm::distance(parsed.axes[axis], info.axes[axis]), 0.0, 1e-6) << "mirrored " << mirrored;
    ASSERT_TRUE(parsed.origin);
    EXPECT_NEAR(glm::distance(*parsed.origin, regionFirst), 0.0, 1e-5) << "mirrored " << mirrored;
  }
}

// NIfTI-1 counts samples in 16 bits: a longer axis is refused, naming the other formats; a box of it is not.
TEST(StoreRoundTrip, ANiftiHeaderRefusesMoreThan32767SamplesAnAxis) {
  TempDir dir;
  const glm::u32vec3 dims{33000, 2, 2};
  ArraySource source = ArraySource::fromSamples<uint8_t>(testing::volumeInfo(dims, SampleType::UInt8),
                                                         std::vector<uint8_t>(size_t(dims.x) * 4, 7));
  ConvertOptions options;
  options.brickSize = 8;
  convertVolume(source, dir / "long.store", options);
  const auto store = Store::open(dir / "long.store");
  try {
    niftiHeaderOf(*store, 0);
    FAIL() << "33000 samples along x accepted";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("at most 32767 samples per axis; the region has 33000 along x"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(niftiHeaderOf(*store, 1).size(), kNiftiHeaderBytes);  // 16500 along x
  EXPECT_EQ(niftiHeaderOf(*store, 0, {{0, 0, 0}, {32767, 2, 2}}).size(), kNiftiHeaderBytes);
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
  const ConvertStats stats = convertVolume(source, dir / "k.store", options);
  EXPECT_EQ(std::count(phases.begin(), phases.end(), ConvertProgress::Phase::ValueRange), 0);
  // What the mapping could not keep is counted (convert warns with it).
  EXPECT_EQ(stats.nanSamples, 1u);
  EXPECT_EQ(stats.infiniteSamples, 0u);
  const auto outside = [](float v) { return v < 0.0f || v > 4.0f; };  // -10, 99 and those of 4.1 to 4.9
  EXPECT_EQ(stats.clampedSamples, uint64_t(std::count_if(samples.begin(), samples.end(), outside)));
  EXPECT_EQ(stats.valueMin, 0.0);
  EXPECT_EQ(stats.valueMax, 4.0);
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
  const ConvertStats stats = convertVolume(source, dir / "c.store", options);
  EXPECT_EQ(stats.infiniteSamples, 2u);
  EXPECT_EQ(stats.nanSamples + stats.clampedSamples, 0u);
  const auto store = Store::open(dir / "c.store");
  EXPECT_EQ(*store->info().volume.valueMin, 5.0);
  EXPECT_EQ(*store->info().volume.valueMax, 5.0);
  const std::vector<float> back = level0Floats(*store);
  ASSERT_EQ(back.size(), samples.size());
  for (size_t i = 0; i < back.size(); ++i) ASSERT_EQ(back[i], 5.0f) << "sample " << i;
}

// An int16 ball of 45x37x29 samples converted in bricks of 4 (levels 0..4), and its samples.
std::vector<int16_t> ballSamples() {
  return testing::toType<int16_t>(testing::ballField({45, 37, 29}, 11), -1000, 2000);
}
std::unique_ptr<Store> ballStore(const TempDir& dir) {
  ArraySource source =
      ArraySource::fromSamples<int16_t>(testing::volumeInfo({45, 37, 29}, SampleType::Int16), ballSamples());
  ConvertOptions options;
  options.brickSize = 4;
  convertVolume(source, dir / "v.store", options);
  return Store::open(dir / "v.store");
}

TEST(StoreRoundTrip, EveryLevelMatchesTheDirectBoxFilter) {
  TempDir dir;
  const auto samples = ballSamples();
  const auto store = ballStore(dir);
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

TEST(StoreRoundTrip, ARegionOfALevelIsThatLevelsSamplesInTheRegion) {
  TempDir dir;
  const auto store = ballStore(dir);
  for (uint32_t level : {0u, 1u}) {
    const std::vector<std::byte> whole = extractLevelBytes(*store, level);
    const glm::u32vec3 d = store->info().layout.levelDims(level);
    // Brick borders inside and at the ends of the region, and a region of one voxel's width.
    for (const LevelRegion region :
         {LevelRegion{{3, 5, 2}, {d.x - 6, d.y, 11}}, LevelRegion{{7, 0, 0}, {8, 9, d.z}}}) {
      const std::vector<std::byte> part = extractLevelBytes(*store, level, region);
      std::vector<std::byte> expected;
      for (uint32_t z = region.begin.z; z < region.end.z; ++z)
        for (uint32_t y = region.begin.y; y < region.end.y; ++y) {
          const size_t row = 2 * ((size_t(z) * d.y + y) * d.x);
          expected.insert(expected.end(), whole.begin() + row + 2 * region.begin.x,
                          whole.begin() + row + 2 * region.end.x);
        }
      EXPECT_EQ(part, expected) << "level " << level << " region from x " << region.begin.x;
    }
  }
  const glm::u32vec3 d0 = store->info().layout.levelDims(0);
  EXPECT_THROW(extractLevelBytes(*store, 0, LevelRegion{{5, 0, 0}, {5, d0.y, d0.z}}), UsageError);
  EXPECT_THROW(extractLevelBytes(*store, 0, LevelRegion{{d0.x, 0, 0}, {d0.x + 4, d0.y, d0.z}}), UsageError);
}

TEST(StoreRoundTrip, AVoxelsValueIsItsSampleInDataUnits) {
  TempDir dir;
  const auto samples = ballSamples();
  const auto store = ballStore(dir);
  const glm::u32vec3 d = store->info().layout.levelDims(0);
  // Corners, a brick's borders (bricks of 4) and the middle.
  for (const glm::u32vec3 v : {glm::u32vec3(0, 0, 0), glm::u32vec3(d.x - 1, d.y - 1, d.z - 1),
                               glm::u32vec3(3, 4, 7), glm::u32vec3(4, 3, 8), glm::u32vec3(22, 18, 14)}) {
    const size_t index = (size_t(v.z) * d.y + v.y) * d.x + v.x;
    EXPECT_EQ(voxelValue(*store, 0, v), double(samples[index])) << v.x << "," << v.y << "," << v.z;
  }
  const std::vector<std::byte> level1 = extractLevelBytes(*store, 1);
  const glm::u32vec3 d1 = store->info().layout.levelDims(1), v1(9, 5, 6);
  int16_t expected = 0;
  std::memcpy(&expected, level1.data() + 2 * ((size_t(v1.z) * d1.y + v1.y) * d1.x + v1.x), 2);
  EXPECT_EQ(voxelValue(*store, 1, v1), double(expected));
  EXPECT_THROW(voxelValue(*store, 0, {d.x, 0, 0}), UsageError);
  EXPECT_THROW(voxelValue(*store, 0, {0, 0, UINT32_MAX}), UsageError);
}

// A BrickSource that counts its brick reads.
class CountingSource : public BrickSource {
 public:
  explicit CountingSource(const BrickSource& inner) : inner_(inner) {}
  const BrickSourceInfo& info() const override { return inner_.info(); }
  NodeInfo node(const NodeKey& key) const override { return inner_.node(key); }
  void readBrick(const NodeKey& key, std::span<std::byte> out) const override {
    ++reads;
    inner_.readBrick(key, out);
  }
  mutable int reads = 0;

 private:
  const BrickSource& inner_;
};

TEST(StoreRoundTrip, AVoxelReaderReadsABrickOnceForItsVoxels) {
  TempDir dir;
  const auto samples = ballSamples();
  const auto store = ballStore(dir);  // bricks of 4
  const glm::u32vec3 d = store->info().layout.levelDims(0);
  CountingSource counting(*store);
  VoxelReader reader(counting);
  const auto sample = [&](glm::u32vec3 v) { return double(samples[(size_t(v.z) * d.y + v.y) * d.x + v.x]); };
  for (const glm::u32vec3 v : {glm::u32vec3(8, 4, 12), glm::u32vec3(11, 7, 15), glm::u32vec3(9, 5, 12)})
    EXPECT_EQ(reader.value(0, v), sample(v));
  EXPECT_EQ(counting.reads, 1);
  EXPECT_EQ(reader.value(0, {12, 4, 12}), sample({12, 4, 12}));  // the next brick along x
  EXPECT_EQ(reader.value(1, {4, 2, 6}), voxelValue(*store, 1, {4, 2, 6}));
  EXPECT_EQ(counting.reads, 3);
  EXPECT_THROW(reader.value(0, {0, d.y, 0}), UsageError);
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

// An attached NRRD of `values`, big-endian.
template <typename T>
std::string nrrdBytes(const std::string& nrrdType, glm::u32vec3 d, const std::vector<T>& values) {
  return "NRRD0004\ntype: " + nrrdType + "\ndimension: 3\nsizes: " + std::to_string(d.x) + " " +
         std::to_string(d.y) + " " + std::to_string(d.z) + "\nencoding: raw\nendian: big\n\n" +
         fileBytes(values, true);
}

// A MetaImage of `values`, big-endian, its data after the header (LOCAL).
template <typename T>
std::string metaImageBytes(SampleType type, glm::u32vec3 d, const std::vector<T>& values) {
  const char* metaType = type == SampleType::Int8      ? "MET_CHAR"
                         : type == SampleType::Int32   ? "MET_INT"
                         : type == SampleType::UInt32  ? "MET_UINT"
                         : type == SampleType::Float64 ? "MET_DOUBLE"
                                                       : "unexpected type";
  return "ObjectType = Image\nNDims = 3\nDimSize = " + std::to_string(d.x) + " " + std::to_string(d.y) + " " +
         std::to_string(d.z) + "\nElementType = " + metaType +
         "\nBinaryDataByteOrderMSB = True\nElementDataFile = LOCAL\n" + fileBytes(values, true);
}

// Through a little-endian raw file named name_XxYxZ_type.raw, a big-endian one with a header given by
// options, a big-endian NRRD and a big-endian MetaImage.
template <typename T>
void expectRoundTripThroughFiles(const std::string& typeName, const std::string& nrrdType, SampleType type,
                                 glm::u32vec3 d, const std::vector<T>& values, bool exact) {
  TempDir dir;
  const std::string dimsText = std::to_string(d.x) + "x" + std::to_string(d.y) + "x" + std::to_string(d.z);
  const std::string named = dir.file("v_" + dimsText + "_" + typeName + ".raw");
  writeFile(named, fileBytes(values));
  expectKept(*convertAndOpen(dir, named), values, type, exact, named);

  const std::string headed = dir.file("headed.bin");
  writeFile(headed, fileBytes(values, true, 301));
  SourceOptions options;
  options.dims = d;
  options.type = type;
  options.byteOrder = ByteOrder::Big;
  options.headerBytes = 301;
  expectKept(*convertAndOpen(dir, headed, options), values, type, exact, headed);

  const std::string nrrd = dir.file(typeName + ".nrrd");
  writeFile(nrrd, nrrdBytes(nrrdType, d, values));
  expectKept(*convertAndOpen(dir, nrrd), values, type, exact, nrrd);

  const std::string metaImage = dir.file(typeName + ".mha");
  writeFile(metaImage, metaImageBytes(type, d, values));
  expectKept(*convertAndOpen(dir, metaImage), values, type, exact, metaImage);
}

constexpr glm::u32vec3 kDims{21, 13, 11};

TEST(StoreRoundTrip, Int8IsKeptExactlyAsValuePlus128) {
  std::vector<int8_t> values = testing::samplePattern<int8_t>(kDims);
  values[0] = -128;
  values[1] = 127;
  expectRoundTripThroughFiles<int8_t>("int8", "signed char", SampleType::Int8, kDims, values, true);
}

// 32-bit integers whose range spans at most 65535 are stored as value - min, exactly: here at both ends of
// their type and with the widest such span.
TEST(StoreRoundTrip, ThirtyTwoBitIntegersWhoseRangeFits16BitsAreKeptExactly) {
  std::vector<uint32_t> unsignedValues(size_t(kDims.x) * kDims.y * kDims.z);
  for (size_t i = 0; i < unsignedValues.size(); ++i)
    unsignedValues[i] = 4294901760u + uint32_t(i * 7919 % 65536);
  unsignedValues[0] = 4294901760u;
  unsignedValues[1] = 4294967295u;
  expectRoundTripThroughFiles<uint32_t>("uint32", "uint32_t", SampleType::UInt32, kDims, unsignedValues,
                                        true);

  std::vector<int32_t> signedValues(unsignedValues.size());
  for (size_t i = 0; i < signedValues.size(); ++i) signedValues[i] = INT32_MIN + int32_t(i * 7919 % 65536);
  signedValues[0] = INT32_MIN;
  signedValues[1] = INT32_MIN + 65535;
  expectRoundTripThroughFiles<int32_t>("int32", "int", SampleType::Int32, kDims, signedValues, true);
}

// Wider ranges are quantized over [min, max] as float32 is: within half a step in the store, and extracted
// as the nearest integer to that.
TEST(StoreRoundTrip, ThirtyTwoBitIntegersOverWiderRangesAreQuantizedWithinHalfAStep) {
  std::vector<int32_t> full(size_t(kDims.x) * kDims.y * kDims.z);
  for (size_t i = 0; i < full.size(); ++i) full[i] = int32_t(uint32_t(i * 2654435761u));
  full[0] = INT32_MIN;
  full[1] = INT32_MAX;
  expectRoundTripThroughFiles<int32_t>("int32", "int32", SampleType::Int32, kDims, full, false);

  std::vector<int32_t> justWider(full.size());  // a span of 65536: one more value than 16 bits hold
  for (size_t i = 0; i < justWider.size(); ++i) justWider[i] = -1000 + int32_t(i * 7919 % 65537);
  justWider[0] = -1000;
  justWider[1] = -1000 + 65536;
  expectRoundTripThroughFiles<int32_t>("i32", "signed int", SampleType::Int32, kDims, justWider, false);

  std::vector<uint32_t> unsignedValues(full.size());
  for (size_t i = 0; i < unsignedValues.size(); ++i) unsignedValues[i] = uint32_t(i * 2654435761u);
  expectRoundTripThroughFiles<uint32_t>("uint32", "unsigned int", SampleType::UInt32, kDims, unsignedValues,
                                        false);
}

// float64 is quantized over its finite range as float32 is, there beyond what a float holds; NaN reads as
// the range's low end, infinities as the ends they point to.
TEST(StoreRoundTrip, Float64IsQuantizedWithinHalfAStepOverItsRange) {
  const std::vector<double> field = testing::ballField(kDims, 9);
  std::vector<double> values(field.size());
  for (size_t i = 0; i < field.size(); ++i) values[i] = -3e40 + 7e40 * field[i];
  expectRoundTripThroughFiles<double>("float64", "double", SampleType::Float64, kDims, values, false);

  TempDir dir;
  values[10] = std::numeric_limits<double>::quiet_NaN();
  values[11] = std::numeric_limits<double>::infinity();
  values[12] = -std::numeric_limits<double>::infinity();
  const std::string path = dir.file("odd_21x13x11_f64.raw");
  writeFile(path, fileBytes(values));
  const auto store = convertAndOpen(dir, path);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (double v : values)
    if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  EXPECT_EQ(*store->info().volume.valueMin, lo);
  EXPECT_EQ(*store->info().volume.valueMax, hi);
  const std::vector<double> back = extractedLevel0<double>(*store);
  EXPECT_EQ(back[10], lo);
  EXPECT_DOUBLE_EQ(back[11], hi);
  EXPECT_EQ(back[12], lo);
}

// A float64 range wider than a double holds (max - min overflows) cannot be quantized: an error naming the
// source, and no store.
TEST(StoreRoundTrip, Float64WhoseRangeOverflowsIsRefused) {
  TempDir dir;
  std::vector<double> values(8 * 8 * 8, 0.0);
  values[0] = -1e308;
  values[1] = 1e308;
  const std::string path = dir.file("huge_8x8x8_float64.raw");
  writeFile(path, fileBytes(values));
  const auto source = openVolumeSource(path);
  try {
    convertVolume(*source, dir / "huge.store");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("cannot be quantized"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "huge.store"));
  EXPECT_EQ(dir.fileCount(), 1u);  // the source alone: no temporary left
}

}  // namespace
}  // namespace ropecast
