// Tests of the NIfTI header parser and the NIfTI VolumeSource: NIfTI-1 and NIfTI-2 in both byte orders,
// single files plain and gzip-compressed, header/image pairs given by either file, every scalar datatype,
// scl_slope and scl_inter applied in a type that holds the values, the qform's and sform's note, and each
// malformed header or data file giving an error that names the file.
#include <bit>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "store/nifti_header.h"
#include "store/source_nifti.h"
#include "store/volume_source.h"
#include "tests/store/store_test_util.h"

namespace ropecast {
namespace {

using testing::errorOf;
using testing::expectHeadersRefused;
using testing::expectVolume;
using testing::fileBytes;
using testing::gzipOf;
using testing::readSlab;
using testing::RefusedHeader;
using testing::samplePattern;
using testing::TempDir;
using testing::writeFile;

constexpr glm::u32vec3 kNiftiDims{9, 6, 5};
constexpr size_t kNiftiSamples = 9 * 6 * 5;

// A NIfTI header as a writer (nibabel, FSL) leaves one: dims, datatype, pixdim, vox_offset past a 4-byte
// extension flag, no scaling, no transform; fields set in the file's byte order.
class NiftiWriter {
 public:
  NiftiWriter(int version, int16_t datatype, int16_t bitpix, bool bigEndian = false)
      : wide_(version == 2), big_(bigEndian), bytes_(wide_ ? 540 : 348, '\0') {
    put<int32_t>(0, wide_ ? 540 : 348);
    put<int16_t>(wide_ ? 12 : 70, datatype);
    put<int16_t>(wide_ ? 14 : 72, bitpix);
    dims({3, kNiftiDims.x, kNiftiDims.y, kNiftiDims.z});
    pixdim(0, 1.0);
    for (int axis = 1; axis <= 3; ++axis) pixdim(axis, 0.5 * axis);
    voxOffset(bytes_.size() + 4);
    std::memcpy(bytes_.data() + (wide_ ? 4 : 344), wide_ ? "n+2\0\r\n\032\n" : "n+1\0", wide_ ? 8 : 4);
  }

  template <typename T>
  void put(size_t offset, T value) {
    auto raw = std::bit_cast<std::array<char, sizeof(T)>>(value);
    if (big_ != (std::endian::native == std::endian::big)) std::reverse(raw.begin(), raw.end());
    std::memcpy(bytes_.data() + offset, raw.data(), sizeof(T));
  }
  void integer(size_t offset1, size_t offset2, int64_t v) {
    wide_ ? put<int64_t>(offset2, v) : put<int16_t>(offset1, int16_t(v));
  }
  void real(size_t offset1, size_t offset2, double v) {
    wide_ ? put<double>(offset2, v) : put<float>(offset1, float(v));
  }
  void dims(std::vector<int64_t> d) {
    for (size_t i = 0; i < d.size(); ++i) integer(40 + 2 * i, 16 + 8 * i, d[i]);
  }
  void pixdim(int i, double v) { real(76 + 4 * size_t(i), 104 + 8 * size_t(i), v); }
  void voxOffset(double v) { wide_ ? put<int64_t>(168, int64_t(v)) : put<float>(108, float(v)); }
  void scale(double slope, double intercept) {
    real(112, 176, slope);
    real(116, 184, intercept);
  }
  void sform(const double rows[3][4]) {
    wide_ ? put<int32_t>(348, 1) : put<int16_t>(254, 1);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) real(280 + 4 * size_t(r * 4 + c), 400 + 8 * size_t(r * 4 + c), rows[r][c]);
  }
  void qform(double b, double c, double d, glm::dvec3 offset = glm::dvec3(0.0)) {
    wide_ ? put<int32_t>(344, 1) : put<int16_t>(252, 1);
    real(256, 352, b);
    real(260, 360, c);
    real(264, 368, d);
    for (int i = 0; i < 3; ++i) real(268 + 4 * size_t(i), 376 + 8 * size_t(i), offset[i]);
  }
  void paired() { std::memcpy(bytes_.data() + (wide_ ? 4 : 344), wide_ ? "ni2" : "ni1", 3); }

  // The header, its 4-byte extension flag (no extensions) and then `data`.
  std::string file(const std::string& data) const { return bytes_ + std::string(4, '\0') + data; }
  const std::string& header() const { return bytes_; }

 private:
  bool wide_, big_;
  std::string bytes_;
};

NiftiHeader parsed(const std::string& bytes) {
  return parseNiftiHeader(std::as_bytes(std::span(bytes.data(), bytes.size())), "t.nii");
}

TEST(SourceNifti, EveryDatatypeInBothVersions) {
  TempDir dir;
  for (const int version : {1, 2}) {
    auto check = [&](auto tag, int16_t datatype, SampleType type) {
      using T = decltype(tag);
      const auto values = samplePattern<T>(kNiftiSamples);
      const std::string path =
          dir.file("v" + std::to_string(version) + "_" + std::to_string(datatype) + ".nii");
      writeFile(path, NiftiWriter(version, datatype, int16_t(8 * sizeof(T))).file(fileBytes(values)));
      expectVolume(*openVolumeSource(path), {kNiftiDims, type, {0.5, 1.0, 1.5}, "nifti:" + path}, values);
    };
    check(uint8_t{}, 2, SampleType::UInt8);
    check(int16_t{}, 4, SampleType::Int16);
    check(int32_t{}, 8, SampleType::Int32);
    check(float{}, 16, SampleType::Float32);
    check(double{}, 64, SampleType::Float64);
    check(int8_t{}, 256, SampleType::Int8);
    check(uint16_t{}, 512, SampleType::UInt16);
    check(uint32_t{}, 768, SampleType::UInt32);
  }
}

TEST(SourceNifti, BigEndianCompressedAndFourDimensionsOfOneVolume) {
  TempDir dir;
  const auto values = samplePattern<int16_t>(kNiftiSamples);
  for (const int version : {1, 2}) {
    NiftiWriter big(version, 4, 16, true);
    big.dims({4, kNiftiDims.x, kNiftiDims.y, kNiftiDims.z, 1});  // one volume of a time series
    const std::string plain = dir.file("big" + std::to_string(version) + ".nii");
    writeFile(plain, big.file(fileBytes(values, true)));
    EXPECT_EQ(readSlab<int16_t>(*openVolumeSource(plain), 0, 5), values) << plain;

    // Compressed whole, header included; slabs out of order restart the stream.
    const std::string gz = dir.file("big" + std::to_string(version) + ".nii.GZ");
    writeFile(gz, gzipOf(big.file(fileBytes(values, true))));
    auto source = openVolumeSource(gz);
    EXPECT_EQ(source->info().dims, kNiftiDims);
    for (const uint32_t z : {3u, 1u, 4u, 0u, 2u}) {
      const auto slab = readSlab<int16_t>(*source, z, 1);
      EXPECT_TRUE(std::equal(slab.begin(), slab.end(), values.begin() + z * 54)) << gz << " slice " << z;
    }
  }
}

// A series of 3 time points of 2 components each (dim[4], dim[5]): volume v holds the pattern plus 1000 v,
// time fastest.
TEST(SourceNifti, TimePointsAndComponentsArePickedByTimeAndChannel) {
  TempDir dir;
  const auto first = samplePattern<int16_t>(kNiftiSamples);
  std::vector<int16_t> series;
  for (int volume = 0; volume < 6; ++volume)
    for (const int16_t v : first) series.push_back(int16_t(v + 1000 * volume));
  const auto volumeOf = [&](int index) {
    return std::vector<int16_t>(series.begin() + index * long(kNiftiSamples),
                                series.begin() + (index + 1) * long(kNiftiSamples));
  };
  for (const int version : {1, 2}) {
    NiftiWriter writer(version, 4, 16);
    writer.dims({5, kNiftiDims.x, kNiftiDims.y, kNiftiDims.z, 3, 2});
    const std::string plain = dir.file("series" + std::to_string(version) + ".nii");
    writeFile(plain, writer.file(fileBytes(series)));
    const std::string gz = dir.file("series" + std::to_string(version) + ".nii.gz");
    writeFile(gz, gzipOf(writer.file(fileBytes(series))));

    // Without --time and --channel: the first volume, and a warning that says what else the file holds.
    auto source = openVolumeSource(plain);
    EXPECT_EQ(source->info().dims, kNiftiDims);
    EXPECT_EQ(readSlab<int16_t>(*source, 0, 5), volumeOf(0));
    ASSERT_EQ(source->info().notes.size(), 1u);
    EXPECT_EQ(source->info().notes[0],
              "NIfTI file " + plain +
                  " holds 3 time points and 2 channels: time point 0 of 3, channel 0 of 2 is read; --time T "
                  "(0 to 2) or --channel C (0 to 1) picks another");
    EXPECT_EQ(source->info().description, "nifti:" + plain + " (time point 0 of 3, channel 0 of 2)");

    for (const std::string& path : {plain, gz}) {
      SourceOptions options;
      options.timePoint = 2;
      options.channel = 1;
      source = openVolumeSource(path, options);
      EXPECT_EQ(readSlab<int16_t>(*source, 0, 5), volumeOf(5)) << path;
      EXPECT_TRUE(source->info().notes.empty()) << path;
      EXPECT_EQ(source->info().description, "nifti:" + path + " (time point 2 of 3, channel 1 of 2)");
      options.timePoint = 1;
      options.channel.reset();
      source = openVolumeSource(path, options);
      EXPECT_EQ(readSlab<int16_t>(*source, 2, 3),
                std::vector<int16_t>(series.begin() + 1 * long(kNiftiSamples) + 2 * 54,
                                     series.begin() + 2 * long(kNiftiSamples)))
          << path;
      ASSERT_EQ(source->info().notes.size(), 1u) << path;
      EXPECT_NE(source->info().notes[0].find("--channel C (0 to 1) picks another"), std::string::npos);
      EXPECT_EQ(source->info().notes[0].find("--time T"), std::string::npos) << source->info().notes[0];
    }

    SourceOptions past;
    past.timePoint = 3;
    EXPECT_EQ(errorOf(plain, past), "--time 3: NIfTI file " + plain + " holds 3 time points (--time 0 to 2)");
    past.timePoint.reset();
    past.channel = 2;
    EXPECT_EQ(errorOf(plain, past),
              "--channel 2: NIfTI file " + plain + " holds 2 channels (--channel 0 to 1)");

    // A series cut short within the volume asked for is refused as truncated; earlier ones still read.
    const std::string cut = dir.file("cut" + std::to_string(version) + ".nii");
    writeFile(cut, writer.file(fileBytes(series).substr(0, 5 * kNiftiSamples * 2 + 10)));
    SourceOptions last;
    last.timePoint = 2;
    last.channel = 1;
    EXPECT_NE(errorOf(cut, last).find("truncated"), std::string::npos) << errorOf(cut, last);
    last.channel = 0;
    EXPECT_EQ(readSlab<int16_t>(*openVolumeSource(cut, last), 0, 5), volumeOf(2));
  }

  // A file of one volume has only time point 0 and channel 0.
  const std::string single = dir.file("single.nii");
  writeFile(single, NiftiWriter(1, 4, 16).file(fileBytes(first)));
  SourceOptions options;
  options.timePoint = 0;
  options.channel = 0;
  EXPECT_EQ(readSlab<int16_t>(*openVolumeSource(single, options), 0, 5), first);
  options.timePoint = 1;
  EXPECT_EQ(errorOf(single, options),
            "--time 1: NIfTI file " + single + " holds 1 time point (--time 0 alone)");
}

// An ANALYZE 7.5 pair (a NIfTI-1 layout without the magic, hist.smin where the magic would be, an
// orientation code and originator where NIfTI keeps qform_code and sform_code), in both byte orders: its
// sizes, spacing, vox_offset and SPM's scale factor read; its orientation not, with a warning. A single file
// without the magic is still refused.
TEST(SourceNifti, AnAnalyzeHeaderIsReadWithoutOrientation) {
  TempDir dir;
  const auto values = samplePattern<int16_t>(kNiftiSamples);
  for (const bool big : {false, true}) {
    NiftiWriter analyze(1, 4, 16, big);
    analyze.put<int32_t>(344, 17);      // hist.smin
    analyze.put<int16_t>(252, 0x0101);  // hist.orient 1 (coronal) and originator's first byte
    analyze.put<int16_t>(254, 0x0203);  // the originator's next bytes
    analyze.voxOffset(0);
    analyze.scale(2.0, 0.0);  // SPM's funused1
    const std::string name = big ? "big" : "little";
    writeFile(dir.file(name + ".hdr"), analyze.header());
    writeFile(dir.file(name + ".img"), fileBytes(values, big));
    for (const std::string& path : {dir.file(name + ".hdr"), dir.file(name + ".img")}) {
      const auto source = openVolumeSource(path);
      const VolumeInfo& info = source->info();
      EXPECT_EQ(info.dims, kNiftiDims);
      EXPECT_EQ(info.spacing, glm::dvec3(0.5, 1.0, 1.5));
      EXPECT_EQ(info.axes, AxisDirections(1.0));
      EXPECT_FALSE(info.origin);
      EXPECT_FALSE(info.patientFrame);
      EXPECT_EQ(info.description.substr(0, 8 + path.size()), "analyze:" + path);
      ASSERT_EQ(info.notes.size(), 1u);
      EXPECT_EQ(info.notes[0], dir.file(name + ".hdr") +
                                   " is an ANALYZE 7.5 header (no NIfTI magic): the volume is drawn in the "
                                   "file's axes, unoriented (programs read ANALYZE's orientation code "
                                   "differently, left and right above all)");
      std::vector<double> expected, got;
      for (const int16_t v : values) expected.push_back(2.0 * v);
      const size_t bytes = bytesPerSample(info.type);
      std::vector<std::byte> slab(kNiftiSamples * bytes);
      source->readSlab(0, 5, slab);
      for (size_t i = 0; i < kNiftiSamples; ++i) {
        if (info.type == SampleType::Int32) {
          int32_t v;
          std::memcpy(&v, slab.data() + i * 4, 4);
          got.push_back(v);
        } else {
          float v;
          std::memcpy(&v, slab.data() + i * 4, 4);
          got.push_back(v);
        }
      }
      EXPECT_EQ(got, expected) << path;
    }
  }
  NiftiWriter single(1, 4, 16);
  single.put<int32_t>(344, 0);
  writeFile(dir.file("nomagic.nii"), single.file(fileBytes(values)));
  EXPECT_NE(errorOf(dir.file("nomagic.nii")).find("not a NIfTI file"), std::string::npos);
}

TEST(SourceNifti, AHeaderAndImagePairIsReadFromEither) {
  TempDir dir;
  const auto values = samplePattern<uint16_t>(kNiftiSamples);
  NiftiWriter pair(1, 512, 16);
  pair.paired();
  pair.voxOffset(0);
  writeFile(dir.file("scan.hdr"), pair.header());
  writeFile(dir.file("scan.img"), fileBytes(values));
  EXPECT_EQ(readSlab<uint16_t>(*openVolumeSource(dir.file("scan.hdr")), 0, 5), values);
  EXPECT_EQ(readSlab<uint16_t>(*openVolumeSource(dir.file("scan.img")), 0, 5), values);
  EXPECT_EQ(niftiDataPath(readNiftiHeaderFile(dir.file("scan.hdr")), dir.file("scan.hdr")),
            dir.file("scan.img"));

  // Both compressed, upper-case names.
  writeFile(dir.file("SCAN2.HDR.GZ"), gzipOf(pair.header()));
  writeFile(dir.file("SCAN2.IMG.GZ"), gzipOf(fileBytes(values)));
  EXPECT_EQ(readSlab<uint16_t>(*openVolumeSource(dir.file("SCAN2.HDR.GZ")), 0, 5), values);
  EXPECT_EQ(readSlab<uint16_t>(*openVolumeSource(dir.file("SCAN2.IMG.GZ")), 0, 5), values);

  writeFile(dir.file("alone.hdr"), pair.header());
  const std::string message = errorOf(dir.file("alone.hdr"));
  EXPECT_NE(message.find(dir.file("alone.hdr")), std::string::npos) << message;
  EXPECT_NE(message.find("no .img or .img.gz"), std::string::npos) << message;
}

TEST(SourceNifti, ScaledValuesAreDeliveredInATypeThatHoldsThem) {
  TempDir dir;
  const auto u16 = samplePattern<uint16_t>(kNiftiSamples);
  NiftiWriter shifted(1, 512, 16);
  shifted.scale(1.0, -1024.0);  // CT stored as uint16 with an intercept: -1024 to 64511 needs int32
  const std::string a = dir.file("shifted.nii");
  writeFile(a, shifted.file(fileBytes(u16)));
  auto source = openVolumeSource(a);
  EXPECT_EQ(source->info().type, SampleType::Int32);
  EXPECT_NE(source->info().description.find("scl_slope 1 and scl_inter -1024"), std::string::npos);
  const auto values = readSlab<int32_t>(*source, 0, 5);
  for (size_t i = 0; i < kNiftiSamples; ++i) ASSERT_EQ(values[i], int32_t(u16[i]) - 1024) << i;

  const auto u8 = samplePattern<uint8_t>(kNiftiSamples);
  NiftiWriter doubled(2, 2, 8);
  doubled.scale(2.0, -100.0);  // -100 to 410: int16
  const std::string b = dir.file("doubled.nii");
  writeFile(b, doubled.file(fileBytes(u8)));
  auto second = openVolumeSource(b);
  EXPECT_EQ(second->info().type, SampleType::Int16);
  const auto wide = readSlab<int16_t>(*second, 1, 3);
  for (size_t i = 0; i < wide.size(); ++i) ASSERT_EQ(wide[i], 2 * int16_t(u8[54 + i]) - 100) << i;

  NiftiWriter fractional(1, 4, 16, true);
  fractional.scale(0.25, 0.5);
  const auto i16 = samplePattern<int16_t>(kNiftiSamples);
  const std::string c = dir.file("fractional.nii");
  writeFile(c, fractional.file(fileBytes(i16, true)));
  auto third = openVolumeSource(c);
  EXPECT_EQ(third->info().type, SampleType::Float32);
  const auto floats = readSlab<float>(*third, 0, 5);
  for (size_t i = 0; i < kNiftiSamples; ++i) ASSERT_EQ(floats[i], float(i16[i] * 0.25 + 0.5)) << i;

  // A slope of 0 (unset) or 1 with intercept 0 leaves the values as stored.
  NiftiWriter identity(1, 4, 16);
  identity.scale(1.0, 0.0);
  EXPECT_FALSE(parsed(identity.header()).scaled);
  identity.scale(0.0, 7.0);
  EXPECT_FALSE(parsed(identity.header()).scaled);
}

TEST(SourceNifti, TheSformOrQformGivesTheAxesInLps) {
  NiftiWriter writer(1, 2, 8);
  EXPECT_EQ(parsed(writer.header()).axes, AxisDirections(1.0));  // neither set: as stored
  writer.qform(0.0, 0.0, 0.0);  // RAS as stored: i to the right, j to the front
  EXPECT_EQ(orientationCode(parsed(writer.header()).axes), "RAS");
  writer.pixdim(0, -1.0);  // qfac -1: the third axis flipped
  EXPECT_EQ(orientationCode(parsed(writer.header()).axes), "RAI");
  EXPECT_TRUE(mirrors(parsed(writer.header()).axes));
  writer.pixdim(0, 1.0);
  writer.qform(0.0, 0.0, 1.0);  // 180 degrees about z: i to the left, j to the back
  EXPECT_EQ(parsed(writer.header()).axes, AxisDirections(1.0));
  writer.qform(0.0, 0.0, std::sqrt(0.5));  // 90 degrees about z: i to the front, j to the left
  EXPECT_EQ(orientationCode(parsed(writer.header()).axes), "ALS");
  // The sform, where set, is the one used.
  const double scaling[3][4] = {{0.5, 0, 0, 10}, {0, 1, 0, 20}, {0, 0, 1.5, 30}};
  writer.sform(scaling);
  EXPECT_EQ(orientationCode(parsed(writer.header()).axes), "RAS");
  const double radiological[3][4] = {{-0.5, 0, 0, 10}, {0, 1, 0, 20}, {0, 0, 1.5, 30}};
  writer.sform(radiological);
  EXPECT_EQ(orientationCode(parsed(writer.header()).axes), "LAS");
  // Columns, not rows: i along y, j along -x.
  const double turned[3][4] = {{0, -2, 0, 0}, {2, 0, 0, 0}, {0, 0, 1, 0}};
  writer.sform(turned);
  EXPECT_EQ(orientationCode(parsed(writer.header()).axes), "ALS");
  EXPECT_FALSE(parsed(writer.header()).transformNotApplied);

  TempDir dir;
  const std::string path = dir.file("flip.nii");
  writer.sform(radiological);
  writeFile(path, writer.file(fileBytes(samplePattern<uint8_t>(kNiftiSamples))));
  auto source = openVolumeSource(path);
  EXPECT_TRUE(source->info().notes.empty());
  EXPECT_EQ(orientationCode(source->info().axes), "LAS");
  const double sheared[3][4] = {{1, 0.5, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};
  writer.sform(sheared);
  writeFile(path, writer.file(fileBytes(samplePattern<uint8_t>(kNiftiSamples))));
  source = openVolumeSource(path);
  ASSERT_EQ(source->info().notes.size(), 1u);
  EXPECT_NE(source->info().notes[0].find("qform or sform does not keep the axes at right angles"),
            std::string::npos);
  EXPECT_EQ(source->info().axes, AxisDirections(1.0));
}

// The first sample's center: the sform's offsets where it is set, else the qform's, turned from RAS into LPS;
// none without either, or with a transform that is not applied.
TEST(SourceNifti, TheSformOrQformPlacesTheFirstSampleInLps) {
  for (int version : {1, 2}) {
    NiftiWriter writer(version, 2, 8);
    EXPECT_FALSE(parsed(writer.header()).origin) << version;
    writer.qform(0.0, 0.0, 1.0, {10.5, -20.0, 30.0});
    EXPECT_EQ(parsed(writer.header()).origin, glm::dvec3(-10.5, 20.0, 30.0)) << version;
    const double radiological[3][4] = {{-0.5, 0, 0, 90}, {0, 1, 0, -126}, {0, 0, 1.5, -72}};
    writer.sform(radiological);
    EXPECT_EQ(parsed(writer.header()).origin, glm::dvec3(-90.0, 126.0, -72.0)) << version;
    const double sheared[3][4] = {{1, 0.5, 0, 1}, {0, 1, 0, 2}, {0, 0, 1, 3}};
    writer.sform(sheared);
    EXPECT_FALSE(parsed(writer.header()).origin) << version;

    TempDir dir;
    const std::string path = dir.file("placed.nii");
    writer.sform(radiological);
    writeFile(path, writer.file(fileBytes(samplePattern<uint8_t>(kNiftiSamples))));
    EXPECT_EQ(openVolumeSource(path)->info().origin, glm::dvec3(-90.0, 126.0, -72.0)) << version;
    // A qform or sform applied puts the volume in the patient's frame; neither, or a sheared one, does not.
    EXPECT_TRUE(openVolumeSource(path)->info().patientFrame) << version;
    writer.sform(sheared);
    writeFile(path, writer.file(fileBytes(samplePattern<uint8_t>(kNiftiSamples))));
    EXPECT_FALSE(openVolumeSource(path)->info().patientFrame) << version;
    NiftiWriter unplaced(version, 2, 8);
    writeFile(path, unplaced.file(fileBytes(samplePattern<uint8_t>(kNiftiSamples))));
    EXPECT_FALSE(openVolumeSource(path)->info().patientFrame) << version;

    // An sform whose third column alone is off the slices' normal (a gantry's tilt kept in the file): the
    // slices placed where they lie, a row further a slice (LPS: x (1,0,0), y (0,-1,0), z (0,-1,2)).
    const double skewed[3][4] = {{-1, 0, 0, 90}, {0, 1, 1, -126}, {0, 0, 2, -72}};
    writer.sform(skewed);
    writeFile(path, writer.file(fileBytes(samplePattern<uint8_t>(kNiftiSamples))));
    const auto tilted = openVolumeSource(path);
    EXPECT_EQ(tilted->info().dims, glm::u32vec3(kNiftiDims.x, kNiftiDims.y + kNiftiDims.z - 1, kNiftiDims.z))
        << version;
    EXPECT_EQ(tilted->info().spacing, glm::dvec3(1.0, 1.0, 2.0)) << version;
    EXPECT_EQ(tilted->info().origin, glm::dvec3(-90.0, 126.0, -72.0)) << version;
    EXPECT_TRUE(tilted->info().patientFrame) << version;
    ASSERT_EQ(tilted->info().notes.size(), 1u) << version;
    EXPECT_NE(tilted->info().notes[0].find("lie off their normal"), std::string::npos)
        << tilted->info().notes[0];
  }
}

TEST(SourceNifti, MalformedHeadersAndDataNameTheFile) {
  std::vector<RefusedHeader> cases;
  NiftiWriter good(1, 4, 16);
  auto with = [&](const std::string& what, auto change, const std::string& expected) {
    NiftiWriter writer = good;
    change(writer);
    cases.push_back({what, writer.header(), expected});
  };
  with(
      "size", [](NiftiWriter& w) { w.put<int32_t>(0, 349); }, "expected 348 (NIfTI-1) or 540");
  with(
      "ANALYZE", [](NiftiWriter& w) { w.put<int32_t>(344, 0); }, "an ANALYZE 7.5 header");
  with(
      "2D",
      [](NiftiWriter& w) {
        w.dims({2, 9, 6, 1});
      },
      "expected 3 to 7 dimensions");
  with(
      "8D",
      [](NiftiWriter& w) {
        w.dims({8, 9, 6, 5, 1, 1, 1, 1, 1});
      },
      "dim[0] is 8");
  with(
      "no time points",
      [](NiftiWriter& w) {
        w.dims({4, 9, 6, 5, 0});
      },
      "dim[4] is 0");
  with(
      "zero size",
      [](NiftiWriter& w) {
        w.dims({3, 9, 0, 5});
      },
      "dim[2] is 0");
  with(
      "complex", [](NiftiWriter& w) { w.put<int16_t>(70, 32); }, "complex64 (32) is not supported");
  with(
      "RGB", [](NiftiWriter& w) { w.put<int16_t>(70, 128); }, "RGB24 (128) is not supported");
  with(
      "int64", [](NiftiWriter& w) { w.put<int16_t>(70, 1024); }, "int64 (1024) is not supported");
  with(
      "bitpix", [](NiftiWriter& w) { w.put<int16_t>(72, 8); }, "bitpix is 8");
  with(
      "offset in header", [](NiftiWriter& w) { w.voxOffset(100); }, "lies within the 348-byte header");
  with(
      "fractional offset", [](NiftiWriter& w) { w.voxOffset(352.5); }, "is not a byte offset");
  with(
      "negative offset", [](NiftiWriter& w) { w.voxOffset(-4); }, "is not a byte offset");
  cases.push_back({"cut short", good.header().substr(0, 200), "ends after 200 bytes"});
  cases.push_back(
      {"NIfTI-2 cut short", NiftiWriter(2, 4, 16).header().substr(0, 400), "ends after 400 bytes"});
  expectHeadersRefused(cases, "/some/dir/bad.nii", [](const std::string& h, const std::string& f) {
    parseNiftiHeader(std::as_bytes(std::span(h.data(), h.size())), f);
  });

  TempDir dir;
  const std::string data = fileBytes(samplePattern<int16_t>(kNiftiSamples));
  const std::string truncated = dir.file("truncated.nii");
  writeFile(truncated, good.file(data.substr(0, data.size() - 1)));
  std::string message = errorOf(truncated);
  EXPECT_NE(message.find(truncated), std::string::npos) << message;
  EXPECT_NE(message.find("truncated"), std::string::npos) << message;

  const std::string gz = gzipOf(good.file(data));
  const std::string shortGz = dir.file("short.nii.gz");
  writeFile(shortGz, gz.substr(0, gz.size() * 2 / 3));
  std::vector<int16_t> all(kNiftiSamples);
  try {
    openVolumeSource(shortGz)->readSlab(0, 5, std::as_writable_bytes(std::span(all)));
    ADD_FAILURE() << "a gzip file cut short read without error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(shortGz), std::string::npos) << e.what();
  }
  const std::string tiny = dir.file("tiny.nii.gz");
  writeFile(tiny, gz.substr(0, 30));
  message = errorOf(tiny);
  EXPECT_NE(message.find(tiny), std::string::npos) << message;

  SourceOptions options;
  options.type = SampleType::UInt8;
  EXPECT_NE(errorOf(truncated, options).find("--type applies to raw files only"), std::string::npos);
}

}  // namespace
}  // namespace ropecast
