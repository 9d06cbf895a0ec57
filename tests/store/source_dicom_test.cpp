// Tests of the DICOM-series VolumeSource (GDCM): slices stacked by position whatever their file names, the
// spacing from Pixel Spacing and the positions, Rescale Slope and Intercept (exact integer types, float32
// otherwise), bits above Bits Stored masked and signed values sign-extended, a series chosen by one of its
// images, objects without images and other files passed over, a disc's folders searched for its series,
// Instance Number where positions are missing, notes for uneven gaps and tilted positions, a round trip
// through the converter, and each bad series (several in one folder, one position twice, sizes or
// orientations that differ, a multi-frame image among others, color images, a DICOM folder with image slices)
// giving an error that names the files. A multi-frame image is a volume of its frames, stacked by their
// positions where an enhanced image gives them.
#include "store/source_dicom.h"

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "tests/store/store_test_util.h"
#include "tests/store/testutil_dicom.h"
#include "tests/store/testutil_round_trip.h"

namespace ropecast {
namespace {

using testing::convertAndOpen;
using testing::DicomSliceSpec;
using testing::errorOf;
using testing::expectKept;
using testing::readSlab;
using testing::TempDir;
using testing::writeDicomSlice;

constexpr uint32_t kColumns = 5, kRows = 4;

// "prefix" followed by n: appended, because GCC 12 warns, wrongly, of an overlapping copy in "prefix" +
// string.
std::string numbered(const char* prefix, uint64_t n) {
  return std::string(prefix).append(std::to_string(n));
}

// Slice z's stored values: distinct in every slice and pixel.
std::vector<int64_t> storedValues(uint32_t z, int64_t base = 100) {
  std::vector<int64_t> values(kColumns * kRows);
  for (size_t i = 0; i < values.size(); ++i) values[i] = base + int64_t(z) * 37 + int64_t(i) * 3;
  return values;
}

// A series of `count` slices 2.5 apart along z, written under names whose order is not the positions' (the
// first name holds the last slice), with CT's rescale (slope 1, intercept -1024).
DicomSliceSpec ctSlice(uint32_t z) {
  DicomSliceSpec spec;
  spec.columns = kColumns;
  spec.rows = kRows;
  spec.stored = storedValues(z);
  spec.position = glm::dvec3(-10.0, 20.0, 30.0 + 2.5 * z);
  spec.instance = int(z + 1);
  spec.slope = 1.0;
  spec.intercept = -1024.0;
  return spec;
}

void writeCtSeries(const TempDir& dir, uint32_t count, const std::string& prefix = "IM") {
  for (uint32_t z = 0; z < count; ++z)
    writeDicomSlice(dir.file(prefix + std::to_string(count - z)), ctSlice(z));
}

template <typename T>
std::vector<T> expectedCt(uint32_t count) {
  std::vector<T> values;
  for (uint32_t z = 0; z < count; ++z)
    for (const int64_t stored : storedValues(z)) values.push_back(T(stored - 1024));
  return values;
}

TEST(SourceDicom, StacksByPositionWithSpacingAndRescale) {
  const TempDir dir;
  writeCtSeries(dir, 6);
  for (const std::string& spec : {dir.path().string(), dir.file("IM3")}) {
    const auto source = openVolumeSource(spec);
    const VolumeInfo& info = source->info();
    EXPECT_EQ(info.dims, glm::u32vec3(kColumns, kRows, 6)) << spec;
    EXPECT_EQ(info.type, SampleType::Int16) << spec;  // 12 bits stored, minus 1024
    EXPECT_DOUBLE_EQ(info.spacing.x, 0.5) << spec;    // Pixel Spacing's second value: between columns
    EXPECT_DOUBLE_EQ(info.spacing.y, 0.75) << spec;
    EXPECT_DOUBLE_EQ(info.spacing.z, 2.5) << spec;
    EXPECT_TRUE(info.notes.empty()) << info.notes.front();
    EXPECT_NE(info.description.find("6 images"), std::string::npos) << info.description;
    EXPECT_TRUE(info.patientFrame) << spec;  // placed by its positions, in the patient's LPS
    EXPECT_EQ(readSlab<int16_t>(*source, 0, 6), expectedCt<int16_t>(6)) << spec;
    const std::vector<int16_t> all = expectedCt<int16_t>(6);
    EXPECT_EQ(readSlab<int16_t>(*source, 3, 2),
              std::vector<int16_t>(all.begin() + 3 * kColumns * kRows, all.begin() + 5 * kColumns * kRows));
  }
}

TEST(SourceDicom, ConvertsToAStoreThatKeepsTheValues) {
  const TempDir dir, out;
  const std::filesystem::path series = dir / "series";
  std::filesystem::create_directory(series);
  for (uint32_t z = 0; z < 9; ++z) writeDicomSlice((series / numbered("s", z)).string(), ctSlice(z));
  const auto store = convertAndOpen(out, series.string());
  expectKept(*store, expectedCt<int16_t>(9), SampleType::Int16, true, "CT series");
  EXPECT_DOUBLE_EQ(store->info().volume.spacing.z, 2.5);
}

TEST(SourceDicom, SlicesGoAlongTheNormalOfTheirOrientation) {
  const TempDir dir;
  // Rows along patient y, columns along x: the normal is -z, so the slice highest in z comes first.
  for (uint32_t k = 0; k < 4; ++k) {
    DicomSliceSpec spec = ctSlice(k);
    spec.orientation = std::array<double, 6>{0, 1, 0, 1, 0, 0};
    writeDicomSlice(dir.file(numbered("a", k)), spec);
  }
  const auto source = openVolumeSource(dir.path().string());
  EXPECT_DOUBLE_EQ(source->info().spacing.z, 2.5);
  std::vector<int16_t> expected;
  for (uint32_t k = 4; k-- > 0;)
    for (const int64_t stored : storedValues(k)) expected.push_back(int16_t(stored - 1024));
  EXPECT_EQ(readSlab<int16_t>(*source, 0, 4), expected);
  // The axes: x along the rows (patient y, posterior), y down the columns (x, left), z along the normal.
  EXPECT_EQ(source->info().axes,
            AxisDirections(glm::dvec3(0, 1, 0), glm::dvec3(1, 0, 0), glm::dvec3(0, 0, -1)));
  EXPECT_EQ(orientationCode(source->info().axes), "PLI");
  EXPECT_EQ(source->info().origin, glm::dvec3(-10.0, 20.0, 30.0 + 2.5 * 3));  // the first slice stacked's

  // A sagittal series (rows along y, columns down -z): slices go along -x, to the patient's right.
  const TempDir sagittal;
  for (uint32_t k = 0; k < 3; ++k) {
    DicomSliceSpec spec = ctSlice(k);
    spec.orientation = std::array<double, 6>{0, 1, 0, 0, 0, -1};
    spec.position = glm::dvec3(-10.0 - 2.5 * k, 20.0, 30.0);
    writeDicomSlice(sagittal.file(numbered("s", k)), spec);
  }
  EXPECT_EQ(orientationCode(openVolumeSource(sagittal.path().string())->info().axes), "PIR");
}

TEST(SourceDicom, AMultiFrameImageIsAVolumeOfItsFrames) {
  for (const bool placed : {true, false}) {
    const TempDir dir;
    DicomSliceSpec spec = ctSlice(0);
    spec.frames = 3;
    spec.stored.clear();
    for (uint32_t z = 0; z < 3; ++z)
      for (const int64_t stored : storedValues(z)) spec.stored.push_back(stored);
    if (placed) spec.spacingBetweenSlices = 4.0;
    writeDicomSlice(dir.file("volume.dcm"), spec);
    const auto source = openVolumeSource(dir.file("volume.dcm"));
    const VolumeInfo& info = source->info();
    EXPECT_EQ(info.dims, glm::u32vec3(kColumns, kRows, 3));
    EXPECT_EQ(info.type, SampleType::Int16);
    EXPECT_DOUBLE_EQ(info.spacing.x, 0.5);
    EXPECT_DOUBLE_EQ(info.spacing.y, 0.75);
    // Frames without a spacing between them are frames in time: stacked at the pixel spacing, and said.
    EXPECT_DOUBLE_EQ(info.spacing.z, placed ? 4.0 : 0.5);
    EXPECT_EQ(info.notes.size(), placed ? 0u : 1u);
    if (!placed) {
      EXPECT_NE(info.notes.front().find("frames in time"), std::string::npos) << info.notes.front();
    }
    EXPECT_EQ(readSlab<int16_t>(*source, 0, 3), expectedCt<int16_t>(3));
    const std::vector<int16_t> all = expectedCt<int16_t>(3);
    EXPECT_EQ(readSlab<int16_t>(*source, 2, 1),
              std::vector<int16_t>(all.begin() + 2 * kColumns * kRows, all.end()));
  }
}

TEST(SourceDicom, AnEnhancedImagesFramesAreStackedByTheirPositions) {
  // Four frames 2 apart along z, stored in the order 2, 0, 3, 1 (Slice Thickness 1, which is not the
  // spacing).
  const uint32_t storedAt[] = {2, 0, 3, 1};
  DicomSliceSpec spec = ctSlice(0);
  spec.frames = 4;
  spec.stored.clear();
  for (const uint32_t z : storedAt) {
    for (const int64_t stored : storedValues(z)) spec.stored.push_back(stored);
    spec.framePositions.push_back(glm::dvec3(-10.0, 20.0, 30.0 + 2.0 * z));
  }
  const TempDir dir;
  writeDicomSlice(dir.file("enhanced.dcm"), spec);
  const auto source = openVolumeSource(dir.file("enhanced.dcm"));
  const VolumeInfo& info = source->info();
  EXPECT_EQ(info.dims, glm::u32vec3(kColumns, kRows, 4));
  EXPECT_EQ(info.type, SampleType::Int16);  // the rescale of the shared functional groups
  EXPECT_EQ(info.spacing, glm::dvec3(0.5, 0.75, 2.0));
  EXPECT_TRUE(info.notes.empty()) << info.notes.front();
  EXPECT_EQ(readSlab<int16_t>(*source, 0, 4), expectedCt<int16_t>(4));
  EXPECT_EQ(info.axes, AxisDirections(1.0));              // an axial image
  EXPECT_EQ(info.origin, glm::dvec3(-10.0, 20.0, 30.0));  // the lowest frame's, stored second
  EXPECT_TRUE(info.patientFrame);

  // A missing frame is filled and noted; two frames at one position (two stacks in one image) are refused.
  spec.framePositions[2].z += 2.0;
  const TempDir gaps, twice;
  writeDicomSlice(gaps.file("gap.dcm"), spec);
  const auto gap = openVolumeSource(gaps.file("gap.dcm"));
  ASSERT_EQ(gap->info().notes.size(), 1u);
  EXPECT_NE(gap->info().notes[0].find("the gaps between the frames of DICOM image"), std::string::npos)
      << gap->info().notes[0];
  EXPECT_EQ(gap->info().dims.z, 5u);  // resampled 2 apart: the missing frame filled
  EXPECT_EQ(gap->info().spacing.z, 2.0);
  spec.framePositions[2] = spec.framePositions[0];
  writeDicomSlice(twice.file("twice.dcm"), spec);
  const std::string error = errorOf(twice.file("twice.dcm"));
  EXPECT_NE(error.find("frames 1 and 3 of DICOM image " + twice.file("twice.dcm") + " lie at one position"),
            std::string::npos)
      << error;
}

TEST(SourceDicomDeathTest, AnAbortInGdcmNamesTheFile) {
  // An enhanced image whose frames have positions but no orientation: GDCM asserts while it computes their
  // spacing. The process still dies (of SIGABRT), having said which file stopped it.
  DicomSliceSpec spec = ctSlice(0);
  spec.frames = 2;
  spec.stored.clear();
  for (uint32_t z = 0; z < 2; ++z)
    for (const int64_t stored : storedValues(z)) spec.stored.push_back(stored);
  spec.framePositions = {glm::dvec3(0.0), glm::dvec3(0.0, 0.0, 1.0)};
  spec.orientation.reset();
  // The death test runs this again in a process of its own (other threads are running), which dies before
  // it can remove a folder: both use one folder, which this process removes.
  const std::filesystem::path folder = std::filesystem::path(ROPECAST_BINARY_DIR) / "dicom_death_test";
  std::filesystem::create_directories(folder);
  const std::string file = (folder / "unoriented.dcm").string();
  writeDicomSlice(file, spec);
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_DEATH(openVolumeSource(file), "GDCM stopped on the DICOM file " + file + ", which is damaged");
  std::filesystem::remove_all(folder);
}

TEST(SourceDicom, PixelDataShorterThanTheSizeIsRefused) {
  // A whole file (its elements end where they say) whose pixel data holds 2 of the 3 frames its header says.
  DicomSliceSpec spec = ctSlice(0);
  spec.frames = 3;
  spec.stored.assign(size_t(kColumns) * kRows * 3, 100);
  spec.pixelDataBytes = size_t(kColumns) * kRows * 2 * 2;
  const TempDir dir;
  writeDicomSlice(dir.file("short.dcm"), spec);
  const std::string error = errorOf(dir.file("short.dcm"));
  EXPECT_NE(error.find("its pixel data holds 80 bytes, and its header says 120 (3 frame(s) of 5x4 pixels"),
            std::string::npos)
      << error;
}

TEST(SourceDicom, TypesFollowTheRescale) {
  struct Case {
    uint16_t bitsAllocated, bitsStored;
    bool isSigned;
    std::optional<double> slope, intercept;
    SampleType type;
  } cases[] = {
      {8, 8, false, std::nullopt, std::nullopt, SampleType::UInt8},
      {16, 12, false, std::nullopt, std::nullopt, SampleType::UInt16},
      {16, 16, true, std::nullopt, std::nullopt, SampleType::Int16},
      {16, 16, true, 1.0, -1024.0, SampleType::Int32},  // below int16
      {16, 12, false, 2.0, 0.0, SampleType::UInt16},
      {16, 16, false, 1.0, -1024.0, SampleType::Int32},
      {16, 12, false, 0.5, 3.0, SampleType::Float32},
      {16, 12, false, 1.0, 0.25, SampleType::Float32},
  };
  for (const Case& c : cases) {
    const TempDir dir;
    for (uint32_t z = 0; z < 3; ++z) {
      DicomSliceSpec spec = ctSlice(z);
      spec.bitsAllocated = c.bitsAllocated;
      spec.bitsStored = c.bitsStored;
      spec.isSigned = c.isSigned;
      spec.slope = c.slope;
      spec.intercept = c.intercept;
      spec.stored = storedValues(z, c.isSigned ? -40 : 3);
      writeDicomSlice(dir.file(numbered("i", z)), spec);
    }
    const auto source = openVolumeSource(dir.path().string());
    const std::string what = std::to_string(c.bitsAllocated) + "/" + std::to_string(c.bitsStored) +
                             (c.isSigned ? " signed" : " unsigned") + ", slope " +
                             formatNumber(c.slope.value_or(1)) + ", intercept " +
                             formatNumber(c.intercept.value_or(0));
    ASSERT_EQ(source->info().type, c.type) << what;
    std::vector<double> expected;
    for (uint32_t z = 0; z < 3; ++z)
      for (const int64_t stored : storedValues(z, c.isSigned ? -40 : 3))
        expected.push_back(double(stored) * c.slope.value_or(1) + c.intercept.value_or(0));
    std::vector<double> read;
    forSampleType(c.type, [&](auto zero) {
      for (const auto v : readSlab<decltype(zero)>(*source, 0, 3)) read.push_back(double(v));
    });
    EXPECT_EQ(read, expected) << what;
  }
}

TEST(SourceDicom, BitsAboveBitsStoredAreMaskedAndTheSignExtended) {
  const TempDir dir;
  DicomSliceSpec spec = ctSlice(0);
  spec.slope.reset();
  spec.intercept.reset();
  spec.bitsStored = 12;
  spec.stored = storedValues(0);
  spec.stored[0] = 0xF000 | 7;  // an overlay bit pattern above the 12 stored bits
  writeDicomSlice(dir.file("unsigned"), spec);
  const auto unsignedSource = openVolumeSource(dir.file("unsigned"));
  EXPECT_EQ(readSlab<uint16_t>(*unsignedSource, 0, 1)[0], 7);

  const TempDir signedDir;
  spec.isSigned = true;
  spec.stored[0] = 0x0FFF;  // -1 in 12 bits, its upper bits left clear
  spec.stored[1] = -5;      // the upper bits copy the sign
  writeDicomSlice(signedDir.file("signed"), spec);
  const auto signedSource = openVolumeSource(signedDir.file("signed"));
  EXPECT_EQ(signedSource->info().type, SampleType::Int16);
  const std::vector<int16_t> values = readSlab<int16_t>(*signedSource, 0, 1);
  EXPECT_EQ(values[0], -1);
  EXPECT_EQ(values[1], -5);
}

TEST(SourceDicom, OtherFilesAndObjectsWithoutImagesArePassedOver) {
  const TempDir dir;
  writeCtSeries(dir, 3);
  testing::writeDicomWithoutImage(dir.file("DICOMDIR"));
  std::ofstream(dir.file("README.txt")) << "scanned on a Tuesday\n";
  const auto source = openVolumeSource(dir.path().string());
  EXPECT_EQ(source->info().dims.z, 3u);
  EXPECT_NE(errorOf(dir.file("DICOMDIR")).find("DICOM file without an image"), std::string::npos)
      << errorOf(dir.file("DICOMDIR"));
}

TEST(SourceDicom, ADiscsFoldersAreSearchedForItsSeries) {
  // A disc's or an export's layout: a DICOMDIR beside DICOM/patient/study/series folders.
  const TempDir disc;
  testing::writeDicomWithoutImage(disc.file("DICOMDIR"));
  const std::filesystem::path study = disc / "DICOM" / "PA000000" / "ST000000";
  std::filesystem::create_directories(study / "SE000000");
  for (uint32_t z = 0; z < 3; ++z)
    writeDicomSlice((study / "SE000000" / numbered("IM", 2 - z)).string(), ctSlice(z));
  std::ofstream(disc.file("AUTORUN.INF")) << "[autorun]\n";
  for (const std::filesystem::path& given : {disc.path(), disc / "DICOMDIR", disc / "DICOM"}) {
    const auto source = openVolumeSource(given.string());
    EXPECT_EQ(source->info().dims, glm::u32vec3(kColumns, kRows, 3)) << given;
    EXPECT_EQ(readSlab<int16_t>(*source, 0, 3), expectedCt<int16_t>(3)) << given;
  }

  // A second series, in a folder of its own: the search lists both, each with an image to give instead.
  std::filesystem::create_directories(study / "SE000001");
  DicomSliceSpec mr = ctSlice(0);
  mr.seriesUid = "1.2.826.0.1.3680043.9.7607.2";
  mr.modality = "MR";
  writeDicomSlice((study / "SE000001" / "IM0").string(), mr);
  const std::string error = errorOf(disc.path().string());
  EXPECT_NE(error.find("holds 2 series in its folders"), std::string::npos) << error;
  EXPECT_NE(error.find("MR, 1 image, e.g. " + (study / "SE000001" / "IM0").string()), std::string::npos)
      << error;
  EXPECT_EQ(openVolumeSource((study / "SE000000" / "IM0").string())->info().dims.z, 3u);
  EXPECT_EQ(errorOf((disc / "DICOMDIR").string()), error);

  // Deeper than the search goes: the folder is said to have no images.
  const TempDir deep;
  testing::writeDicomWithoutImage(deep.file("DICOMDIR"));
  std::filesystem::path folder = deep.path();
  for (int level = 0; level <= kDicomSearchDepth; ++level) folder /= numbered("L", uint64_t(level));
  std::filesystem::create_directories(folder);
  writeDicomSlice((folder / "IM1").string(), ctSlice(0));
  const std::string tooDeep = errorOf(deep.path().string());
  EXPECT_NE(tooDeep.find("has no DICOM images"), std::string::npos) << tooDeep;
  EXPECT_EQ(openVolumeSource(folder.parent_path().string())->info().dims.z, 1u);
}

TEST(SourceDicom, OneImageChoosesItsSeriesAndAFolderOfSeveralIsRefused) {
  const TempDir dir;
  writeCtSeries(dir, 4, "ct");
  for (uint32_t z = 0; z < 2; ++z) {
    DicomSliceSpec spec = ctSlice(z);
    spec.seriesUid = "1.2.826.0.1.3680043.9.7607.2";
    spec.modality = "MR";
    spec.seriesDescription = "T1 AXIAL";
    spec.slope.reset();
    spec.intercept.reset();
    writeDicomSlice(dir.file(numbered("mr", z)), spec);
  }
  const std::string error = errorOf(dir.path().string());
  EXPECT_NE(error.find("holds 2 series"), std::string::npos) << error;
  EXPECT_NE(error.find("1.2.826.0.1.3680043.9.7607.1: CT, 4 images, e.g. " + dir.file("ct1")),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("MR 'T1 AXIAL', 2 images"), std::string::npos) << error;
  EXPECT_EQ(openVolumeSource(dir.file("ct2"))->info().dims.z, 4u);
  const auto mr = openVolumeSource(dir.file("mr1"));
  EXPECT_EQ(mr->info().dims.z, 2u);
  EXPECT_EQ(mr->info().type, SampleType::UInt16);
}

TEST(SourceDicom, InstanceNumberOrdersSlicesWithoutPositions) {
  const TempDir dir;
  for (uint32_t z = 0; z < 3; ++z) {
    DicomSliceSpec spec = ctSlice(z);
    spec.position.reset();
    spec.orientation.reset();
    spec.instance = int(10 * z + 5);
    writeDicomSlice(dir.file(numbered("x", 2 - z)), spec);
  }
  const auto source = openVolumeSource(dir.path().string());
  EXPECT_EQ(readSlab<int16_t>(*source, 0, 3), expectedCt<int16_t>(3));
  // Without positions or Slice Thickness, the spacing across is the spacing between rows (said too).
  EXPECT_DOUBLE_EQ(source->info().spacing.z, 0.75);
  EXPECT_FALSE(source->info().patientFrame);  // placed nowhere
  ASSERT_EQ(source->info().notes.size(), 2u);
  EXPECT_NE(source->info().notes[0].find("stacked by Instance Number"), std::string::npos)
      << source->info().notes[0];
  EXPECT_NE(source->info().notes[1].find("spacing across the DICOM slices is unknown"), std::string::npos)
      << source->info().notes[1];

  DicomSliceSpec unordered = ctSlice(3);
  unordered.position.reset();
  unordered.instance.reset();
  writeDicomSlice(dir.file("x9"), unordered);
  EXPECT_NE(errorOf(dir.path().string()).find("their order is unknown"), std::string::npos)
      << errorOf(dir.path().string());
}

// Slices are drawn where their positions place them (store/placed_stack.h): a missing slice is filled
// between its neighbours, a gantry's tilt (each slice moved down its columns against the one below) is
// undone on a grid that holds every slice; each is noted.
TEST(SourceDicom, AMissingSliceAndATiltedGantryAreResampledWhereTheSlicesLie) {
  const TempDir gaps, tilted;
  for (const uint32_t z : {0u, 1u, 2u, 4u, 5u}) writeDicomSlice(gaps.file(numbered("g", z)), ctSlice(z));
  const auto missing = openVolumeSource(gaps.path().string());
  EXPECT_EQ(missing->info().dims, glm::u32vec3(kColumns, kRows, 6));
  EXPECT_EQ(missing->info().spacing, glm::dvec3(0.5, 0.75, 2.5));
  EXPECT_EQ(missing->info().origin, glm::dvec3(-10.0, 20.0, 30.0));
  ASSERT_EQ(missing->info().notes.size(), 1u);
  EXPECT_NE(missing->info().notes[0].find("vary from 2.5 to 5 (a missing slice?); they are resampled"),
            std::string::npos)
      << missing->info().notes[0];
  // The values grow evenly from slice to slice: the missing one's lie halfway between its neighbours'.
  EXPECT_EQ(readSlab<int16_t>(*missing, 0, 6), expectedCt<int16_t>(6));

  // Moved 0.8 down the columns a slice (1.07 rows: 3.2 rows in all, so the grid has 4 more).
  for (uint32_t z = 0; z < 4; ++z) {
    DicomSliceSpec spec = ctSlice(z);
    spec.position = *spec.position + glm::dvec3(0.0, 0.8 * z, 0.0);
    writeDicomSlice(tilted.file(numbered("t", z)), spec);
  }
  const auto sheared = openVolumeSource(tilted.path().string());
  const VolumeInfo& info = sheared->info();
  EXPECT_EQ(info.dims, glm::u32vec3(kColumns, kRows + 4, 4));
  EXPECT_EQ(info.spacing, glm::dvec3(0.5, 0.75, 2.5));
  EXPECT_EQ(info.origin, glm::dvec3(-10.0, 20.0, 30.0));
  ASSERT_EQ(info.notes.size(), 1u);
  EXPECT_NE(info.notes[0].find("as a gantry tilted 17.7 degrees places them); they are resampled"),
            std::string::npos)
      << info.notes[0];
  const std::vector<int16_t> samples = readSlab<int16_t>(*sheared, 0, 4);
  for (uint32_t z = 0; z < 4; ++z)
    for (uint32_t y = 0; y < info.dims.y; ++y)
      for (uint32_t x = 0; x < kColumns; ++x) {
        // Row y of the grid is row y - 1.07 z of slice z: its values there, linear down the columns.
        const double row = y - 0.8 * z / 0.75;
        const int16_t value = samples[(size_t(z) * info.dims.y + y) * kColumns + x];
        if (row >= 0.0 && row <= kRows - 1) {
          EXPECT_NEAR(value, 100 + 37.0 * z + 3.0 * (row * kColumns + x) - 1024, 0.5)
              << x << "," << y << "," << z;
        } else if (row <= -1.0 || row >= kRows) {
          EXPECT_EQ(value, 100 - 1024) << x << "," << y << "," << z;  // the bottom slice's smallest
        }
      }
}

// A series holding each of its 3 positions 2 times (a 4D CT's phases): told apart by Temporal Position
// Identifier, else by Instance Number; the first time point read by default, with a warning, the other by
// --time. Time point t's slice z holds storedValues(z, 100 + 1000 t).
TEST(SourceDicom, ATimeSeriesPicksOneTimePoint) {
  for (const bool temporal : {true, false}) {
    const TempDir dir;
    for (uint32_t t = 0; t < 2; ++t)
      for (uint32_t z = 0; z < 3; ++z) {
        DicomSliceSpec slice = ctSlice(z);
        slice.stored = storedValues(z, 100 + 1000 * int64_t(t));
        // Instance Numbers against the time points where Temporal Position Identifier tells them apart.
        slice.instance = temporal ? int(10 - (3 * t + z)) : int(3 * t + z + 1);
        if (temporal) slice.temporalPosition = int(t + 1);
        writeDicomSlice(dir.file(numbered("f", 3 * t + z)), slice);
      }
    const auto expected = [](uint32_t t) {
      std::vector<int16_t> values;
      for (uint32_t z = 0; z < 3; ++z)
        for (const int64_t stored : storedValues(z, 100 + 1000 * int64_t(t)))
          values.push_back(int16_t(stored - 1024));
      return values;
    };
    const auto first = openVolumeSource(dir.path().string());
    EXPECT_EQ(first->info().dims, glm::u32vec3(kColumns, kRows, 3));
    EXPECT_DOUBLE_EQ(first->info().spacing.z, 2.5);
    EXPECT_EQ(readSlab<int16_t>(*first, 0, 3), expected(0)) << temporal;
    ASSERT_EQ(first->info().notes.size(), 1u);
    EXPECT_EQ(first->info().notes[0],
              "DICOM series " + dir.path().string() +
                  " holds 2 time points: time point 0 of 2 is read; --time T (0 to 1) "
                  "picks another");
    SourceOptions options;
    options.timePoint = 1;
    const auto second = openVolumeSource(dir.path().string(), options);
    EXPECT_EQ(readSlab<int16_t>(*second, 0, 3), expected(1)) << temporal;
    EXPECT_NE(second->info().description.find("3 images) (time point 1 of 2)"), std::string::npos)
        << second->info().description;
    options.timePoint = 2;
    EXPECT_EQ(errorOf(dir.path().string(), options),
              "--time 2: DICOM series " + dir.path().string() + " holds 2 time points (--time 0 to 1)");
  }
  // A single volume has time point 0 alone.
  const TempDir dir;
  writeCtSeries(dir, 3);
  SourceOptions options;
  options.timePoint = 1;
  EXPECT_NE(errorOf(dir.path().string(), options).find("holds 1 time point (--time 0 alone)"),
            std::string::npos);
}

TEST(SourceDicom, BadSeriesNameTheirFiles) {
  const auto errorFor = [](const std::vector<DicomSliceSpec>& slices) {
    const TempDir dir;
    for (size_t z = 0; z < slices.size(); ++z) writeDicomSlice(dir.file(numbered("f", z)), slices[z]);
    return errorOf(dir.path().string());
  };
  DicomSliceSpec twice = ctSlice(1);
  std::string error = errorFor({ctSlice(0), ctSlice(1), twice});
  EXPECT_NE(error.find("lie at one position"), std::string::npos) << error;
  EXPECT_NE(error.find("/f1"), std::string::npos) << error;
  EXPECT_NE(error.find("/f2"), std::string::npos) << error;

  DicomSliceSpec wider = ctSlice(1);
  wider.columns = kColumns + 1;
  wider.stored.resize(size_t(wider.columns) * kRows);
  error = errorFor({ctSlice(0), wider});
  EXPECT_NE(error.find("has Columns 6, but"), std::string::npos) << error;

  DicomSliceSpec turned = ctSlice(1);
  turned.orientation = std::array<double, 6>{0, 1, 0, 1, 0, 0};
  error = errorFor({ctSlice(0), turned});
  EXPECT_NE(error.find("oriented otherwise"), std::string::npos) << error;

  DicomSliceSpec frames = ctSlice(0);
  frames.frames = 3;
  error = errorFor({frames, ctSlice(1)});
  EXPECT_NE(error.find("holds 3 frames, and its series 2 images"), std::string::npos) << error;

  DicomSliceSpec color = ctSlice(0);
  color.samplesPerPixel = 3;
  color.photometric = "RGB";
  color.bitsAllocated = color.bitsStored = 8;
  error = errorFor({color});
  EXPECT_NE(error.find("3 samples per pixel (RGB)"), std::string::npos) << error;

  DicomSliceSpec flat = ctSlice(0);
  flat.slope = 0.0;
  error = errorFor({flat});
  EXPECT_NE(error.find("Rescale Slope '0'"), std::string::npos) << error;
}

TEST(SourceDicom, AFolderOfDicomAndSlicesIsAmbiguous) {
  const TempDir dir;
  writeCtSeries(dir, 2);
  std::ofstream(dir.file("slice_0.png")) << "not read";
  const std::string error = errorOf(dir.path().string());
  EXPECT_NE(error.find("holds DICOM files and image slices"), std::string::npos) << error;
  EXPECT_EQ(openVolumeSource(dir.file("IM1"))->info().dims.z, 2u);  // one image still names its series

  const TempDir empty;
  std::ofstream(empty.file("scan.dcm")) << "no preamble";
  EXPECT_NE(errorOf(empty.file("scan.dcm")).find("no DICM signature"), std::string::npos)
      << errorOf(empty.file("scan.dcm"));
}

TEST(SourceDicom, RawOptionsAreRefusedAndSpacingOverrides) {
  const TempDir dir;
  writeCtSeries(dir, 2);
  SourceOptions options;
  options.dims = glm::u32vec3(1);
  EXPECT_NE(errorOf(dir.path().string(), options).find("a DICOM series states its own"), std::string::npos)
      << errorOf(dir.path().string(), options);
  options = {};
  options.spacing = glm::dvec3(1.0, 2.0, 3.0);
  EXPECT_EQ(openVolumeSource(dir.path().string(), options)->info().spacing, glm::dvec3(1.0, 2.0, 3.0));
}

}  // namespace
}  // namespace ropecast
