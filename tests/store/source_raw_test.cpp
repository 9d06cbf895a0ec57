// Tests of the raw VolumeSource and the dispatcher's choice of it: every type reads back what was written,
// slabs at any z, dims/type from options or an Open SciVis-style file name, big-endian samples after a
// header, and each bad input (truncated, too long, unknown type, no dims, missing file, layout options for
// another kind of input) gives an error naming the file or option and the problem.
#include "store/source_raw.h"

#include <bit>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "tests/store/store_test_util.h"

namespace ropecast {
namespace {

namespace fs = std::filesystem;
using testing::errorOf;
using testing::fileBytes;
using testing::readSlab;
using testing::samplePattern;
using testing::TempDir;
using testing::writeFile;

template <typename T>
void expectRoundTrip(const TempDir& dir, const std::string& typeName, SampleType type) {
  const glm::u32vec3 dims(13, 7, 11);
  const auto data = samplePattern<T>(dims);
  // From the file name alone.
  const std::string named = dir.file("vol_13x7x11_" + typeName + ".raw");
  writeFile(named, data.data(), data.size() * sizeof(T));
  auto source = openVolumeSource(named);
  EXPECT_EQ(source->info().dims, dims);
  EXPECT_EQ(source->info().type, type);
  EXPECT_EQ(source->info().spacing, glm::dvec3(1.0));
  EXPECT_EQ(readSlab<T>(*source, 0, dims.z), data) << typeName;
  for (uint32_t z0 : {10u, 3u, 0u, 6u}) {
    const auto slab = readSlab<T>(*source, z0, std::min(4u, dims.z - z0));
    EXPECT_TRUE(std::equal(slab.begin(), slab.end(), data.begin() + size_t(z0) * dims.x * dims.y))
        << typeName;
  }
  // From options, with an unhelpful name.
  const std::string plain = dir.file("plain_" + typeName + ".bin");
  writeFile(plain, data.data(), data.size() * sizeof(T));
  SourceOptions options;
  options.dims = dims;
  options.type = type;
  options.spacing = glm::dvec3(0.5, 1.0, 2.5);
  auto fromOptions = openVolumeSource(plain, options);
  EXPECT_EQ(fromOptions->info().spacing, glm::dvec3(0.5, 1.0, 2.5));
  EXPECT_EQ(readSlab<T>(*fromOptions, 0, dims.z), data) << typeName;
}

TEST(SourceRaw, EveryTypeReadsBackWhatWasWritten) {
  TempDir dir;
  expectRoundTrip<uint8_t>(dir, "uint8", SampleType::UInt8);
  expectRoundTrip<uint16_t>(dir, "uint16", SampleType::UInt16);
  expectRoundTrip<int16_t>(dir, "int16", SampleType::Int16);
  expectRoundTrip<float>(dir, "float32", SampleType::Float32);
  expectRoundTrip<int8_t>(dir, "int8", SampleType::Int8);
  expectRoundTrip<uint32_t>(dir, "uint32", SampleType::UInt32);
  expectRoundTrip<int32_t>(dir, "int32", SampleType::Int32);
  expectRoundTrip<double>(dir, "float64", SampleType::Float64);
}

template <typename T>
void expectBigEndianAfterHeader(const TempDir& dir, const std::string& typeName, size_t header) {
  const glm::u32vec3 dims(6, 5, 7);
  const auto data = samplePattern<T>(dims);
  const std::string path = dir.file("big_6x5x7_" + typeName + ".raw");
  const std::string bytes = fileBytes(data, true, header);
  writeFile(path, bytes.data(), bytes.size());
  SourceOptions options;
  options.byteOrder = ByteOrder::Big;
  options.headerBytes = header;
  auto source = openVolumeSource(path, options);
  EXPECT_EQ(source->info().type, parseSampleType(typeName));
  EXPECT_EQ(readSlab<T>(*source, 0, dims.z), data) << typeName;
  const auto slab = readSlab<T>(*source, 4, 3);
  EXPECT_TRUE(std::equal(slab.begin(), slab.end(), data.begin() + 4 * 30)) << typeName;
}

TEST(SourceRaw, BigEndianSamplesAfterAHeaderReadBackWhatWasWritten) {
  TempDir dir;
  expectBigEndianAfterHeader<int32_t>(dir, "int32", 37);
  expectBigEndianAfterHeader<uint32_t>(dir, "uint32", 1);
  expectBigEndianAfterHeader<double>(dir, "float64", 512);
  expectBigEndianAfterHeader<int16_t>(dir, "int16", 3);
  expectBigEndianAfterHeader<float>(dir, "float32", 0);
  expectBigEndianAfterHeader<int8_t>(dir, "int8", 5);  // one byte: the order changes nothing
  // Little-endian, the default, after a header.
  const auto data = samplePattern<uint16_t>({6, 5, 7});
  const std::string path = dir.file("little_6x5x7_uint16.raw");
  const std::string bytes = fileBytes(data, false, 100);
  writeFile(path, bytes.data(), bytes.size());
  SourceOptions options;
  options.headerBytes = 100;
  EXPECT_EQ(readSlab<uint16_t>(*openVolumeSource(path, options), 0, 7), data);
}

TEST(SourceRaw, TheExpectedSizeCountsTheHeader) {
  TempDir dir;
  const std::vector<uint8_t> bytes(2 * 10 * 10 * 10);
  const std::string path = dir.file("v_10x10x10_uint16.raw");
  writeFile(path, bytes.data(), bytes.size());
  SourceOptions options;
  options.headerBytes = 64;
  const std::string message = errorOf(path, options);
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(
      message.find("size is 2000 bytes, expected 2064 (64 header bytes + 10x10x10 uint16 = 2000 bytes)"),
      std::string::npos)
      << message;
  EXPECT_NE(message.find("truncated"), std::string::npos) << message;
  // A header longer than the whole file.
  options.headerBytes = 5000;
  EXPECT_NE(errorOf(path, options).find("expected 7000 (5000 header bytes"), std::string::npos)
      << errorOf(path, options);
  // The header given, the data too long for the dims.
  options.headerBytes = 16;
  options.dims = glm::u32vec3(10, 10, 9);
  EXPECT_NE(errorOf(path, options).find("too long"), std::string::npos) << errorOf(path, options);
}

// A NRRD states its byte order and where its data starts; a procedural volume or image stack has no raw
// layout at all: the options are a usage error naming the option and the input.
TEST(SourceRaw, LayoutOptionsAreRefusedForOtherInputs) {
  TempDir dir;
  const std::string nrrd = dir.file("v.nrrd");
  const std::string text = "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n12345678";
  writeFile(nrrd, text.data(), text.size());
  SourceOptions byteOrder;
  byteOrder.byteOrder = ByteOrder::Big;
  EXPECT_THROW(openVolumeSource(nrrd, byteOrder), UsageError);
  EXPECT_NE(errorOf(nrrd, byteOrder).find(nrrd + ": --byte-order applies to raw files only"),
            std::string::npos)
      << errorOf(nrrd, byteOrder);
  SourceOptions header;
  header.headerBytes = 0;  // given, even as 0
  EXPECT_NE(errorOf("procedural:sphere:8", header).find("procedural:sphere:8: --header-bytes applies to raw"),
            std::string::npos)
      << errorOf("procedural:sphere:8", header);
  SourceOptions both = byteOrder;
  both.headerBytes = 4;
  both.type = SampleType::UInt8;
  EXPECT_NE(errorOf(dir.path().string(), both).find("--type, --byte-order and --header-bytes apply to raw"),
            std::string::npos)
      << errorOf(dir.path().string(), both);
}

TEST(SourceRaw, ParsesOpenSciVisNames) {
  const auto bonsai = parseRawFileName("/data/bonsai_256x256x256_uint8.raw");
  ASSERT_TRUE(bonsai);
  EXPECT_EQ(bonsai->dims, glm::u32vec3(256));
  EXPECT_EQ(bonsai->type, SampleType::UInt8);
  const auto odd = parseRawFileName("dir_1x1x1_uint8.raw/duct_flow_193x194x1000_float32.raw");
  ASSERT_TRUE(odd);
  EXPECT_EQ(odd->dims, glm::u32vec3(193, 194, 1000));
  EXPECT_EQ(odd->type, SampleType::Float32);
  const auto alias = parseRawFileName("x_2x3x4_ushort.raw");
  ASSERT_TRUE(alias);
  EXPECT_EQ(alias->type, SampleType::UInt16);
  const auto wide = parseRawFileName("x_2x3x4_float64.raw");
  ASSERT_TRUE(wide);
  EXPECT_EQ(wide->type, SampleType::Float64);
  EXPECT_EQ(parseRawFileName("x_2x3x4_i8.raw")->type, SampleType::Int8);
  EXPECT_EQ(parseRawFileName("x_2x3x4_uint32.raw")->type, SampleType::UInt32);
  EXPECT_EQ(parseRawFileName("x_2x3x4_int32.raw")->type, SampleType::Int32);
  const auto unknown = parseRawFileName("x_2x3x4_int64.raw");
  ASSERT_TRUE(unknown);
  EXPECT_EQ(unknown->typeName, "int64");
  EXPECT_FALSE(unknown->type);
  const auto upper = parseRawFileName("SCAN_4x5x6_UINT16.RAW");
  ASSERT_TRUE(upper);
  EXPECT_EQ(upper->dims, glm::u32vec3(4, 5, 6));
  EXPECT_EQ(upper->type, SampleType::UInt16);
  EXPECT_FALSE(parseRawFileName("bonsai.raw"));
  EXPECT_FALSE(parseRawFileName("bonsai_256x256_uint8.raw"));
  EXPECT_FALSE(parseRawFileName("bonsai_99999999999x2x2_uint8.raw"));
  // A zero is the name's dimension, refused when the file opens (not "dimensions unknown").
  EXPECT_EQ(parseRawFileName("bonsai_0x256x256_uint8.raw")->dims, glm::u32vec3(0, 256, 256));
}

// Dims in the name beyond what a store holds are refused before their product is taken (it overflowed).
TEST(SourceRaw, DimsOfTheNameAreCheckedBeforeTheSize) {
  TempDir dir;
  for (const char* name : {"a_4294967295x4294967295x4294967295_uint8.raw",
                           "b_4194304x4194304x1048576_uint8.raw", "c_0x10x10_uint8.raw"}) {
    const std::string path = dir.file(name);
    writeFile(path, "", 0);
    const std::string message = errorOf(path);
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find("each must be 1 to 1048576"), std::string::npos) << message;
  }
}

TEST(SourceRaw, OptionsOverrideTheFileName) {
  TempDir dir;
  const auto data = samplePattern<uint16_t>({4, 5, 6});
  const std::string path = dir.file("misnamed_10x10x10_uint8.raw");
  writeFile(path, data.data(), data.size() * 2);
  SourceOptions options;
  options.dims = glm::u32vec3(4, 5, 6);
  options.type = SampleType::UInt16;
  auto source = openVolumeSource(path, options);
  EXPECT_EQ(readSlab<uint16_t>(*source, 0, 6), data);
}

TEST(SourceRaw, SizeMismatchNamesFileExpectedAndActual) {
  TempDir dir;
  const std::vector<uint8_t> bytes(1000);
  const std::string truncated = dir.file("short_10x10x11_uint8.raw");
  writeFile(truncated, bytes.data(), bytes.size());
  const std::string message = errorOf(truncated);
  EXPECT_NE(message.find(truncated), std::string::npos) << message;
  EXPECT_NE(message.find("1000 bytes"), std::string::npos) << message;
  EXPECT_NE(message.find("expected 1100"), std::string::npos) << message;
  EXPECT_NE(message.find("truncated"), std::string::npos) << message;

  const std::string tooLong = dir.file("long_10x10x9_uint8.raw");
  writeFile(tooLong, bytes.data(), bytes.size());
  EXPECT_NE(errorOf(tooLong).find("too long"), std::string::npos) << errorOf(tooLong);

  // Dims from options that do not match the size (uint16 doubles the bytes).
  SourceOptions options;
  options.dims = glm::u32vec3(10, 10, 10);
  options.type = SampleType::UInt16;
  const std::string wrongType = errorOf(dir.file("short_10x10x11_uint8.raw"), options);
  EXPECT_NE(wrongType.find("expected 2000"), std::string::npos) << wrongType;
}

TEST(SourceRaw, UnknownTypeOrDimsNameTheFile) {
  TempDir dir;
  const std::vector<uint8_t> bytes(64);
  const std::string unknownType = dir.file("v_2x2x2_int64.raw");
  writeFile(unknownType, bytes.data(), bytes.size());
  const std::string typeMessage = errorOf(unknownType);
  EXPECT_NE(typeMessage.find(unknownType), std::string::npos) << typeMessage;
  EXPECT_NE(typeMessage.find("'int64'"), std::string::npos) << typeMessage;
  EXPECT_NE(typeMessage.find("float64"), std::string::npos) << typeMessage;  // the types there are

  const std::string noDims = dir.file("volume.dat");
  writeFile(noDims, bytes.data(), bytes.size());
  const std::string dimsMessage = errorOf(noDims);
  EXPECT_NE(dimsMessage.find(noDims), std::string::npos) << dimsMessage;
  EXPECT_NE(dimsMessage.find("--dims"), std::string::npos) << dimsMessage;

  SourceOptions dimsOnly;
  dimsOnly.dims = glm::u32vec3(4, 4, 4);
  EXPECT_NE(errorOf(noDims, dimsOnly).find("--type"), std::string::npos);
  EXPECT_EQ(parseSampleType("int64"), std::nullopt);  // so the CLI rejects --type int64 before we get here
}

TEST(SourceRaw, MissingFileIsNamed) {
  const std::string missing = "/nonexistent/dir/bonsai_256x256x256_uint8.raw";
  const std::string message = errorOf(missing);
  EXPECT_NE(message.find(missing), std::string::npos) << message;
  EXPECT_NE(message.find("no such file"), std::string::npos) << message;
}

TEST(SourceRaw, SlabsOutsideTheVolumeAreRejected) {
  TempDir dir;
  const auto data = samplePattern<uint8_t>({3, 3, 3});
  const std::string path = dir.file("v_3x3x3_uint8.raw");
  writeFile(path, data.data(), data.size());
  auto source = openVolumeSource(path);
  std::vector<std::byte> two(18);
  EXPECT_THROW(source->readSlab(2, 2, two), Error);
  EXPECT_THROW(source->readSlab(0, 1, two), Error);  // wrong buffer size
  // The file shrinking after opening is a read error naming it, not garbage.
  fs::resize_file(path, 10);
  try {
    source->readSlab(1, 2, two);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST(SourceRaw, BigEndianSamplesAreSwappedToNative) {
  std::vector<uint8_t> bytes = {0x12, 0x34, 0xAB, 0xCD};
  samplesToNative(std::as_writable_bytes(std::span(bytes)), SampleType::UInt16, true);
  uint16_t values[2];
  std::memcpy(values, bytes.data(), 4);
  EXPECT_EQ(values[0], 0x1234);
  EXPECT_EQ(values[1], 0xABCD);
  std::vector<uint8_t> floatBytes = {0x3F, 0x80, 0x00, 0x00};  // 1.0f big-endian
  samplesToNative(std::as_writable_bytes(std::span(floatBytes)), SampleType::Float32, true);
  float f;
  std::memcpy(&f, floatBytes.data(), 4);
  EXPECT_EQ(f, 1.0f);
  std::vector<uint8_t> doubleBytes = {0xC0, 0x00, 0, 0, 0, 0, 0, 0};  // -2.0 big-endian
  samplesToNative(std::as_writable_bytes(std::span(doubleBytes)), SampleType::Float64, true);
  double d;
  std::memcpy(&d, doubleBytes.data(), 8);
  EXPECT_EQ(d, -2.0);
}

}  // namespace
}  // namespace ropecast
