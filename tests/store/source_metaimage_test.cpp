// Tests of the MetaImage header parser and the MetaImage VolumeSource: .mha with its data (LOCAL) and .mhd
// with a data file, every element type, big-endian and zlib-compressed data read in any order, header skips,
// the transform matrix's note, and each malformed header or data file giving an error that names the file
// and the key.
#include <zlib.h>

#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "store/metaimage_header.h"
#include "store/source_metaimage.h"
#include "store/volume_source.h"
#include "tests/store/store_test_util.h"

namespace ropecast {
namespace {

namespace fs = std::filesystem;
using testing::errorOf;
using testing::expectHeadersRefused;
using testing::expectVolume;
using testing::fileBytes;
using testing::readSlab;
using testing::RefusedHeader;
using testing::samplePattern;
using testing::TempDir;
using testing::writeFile;

constexpr size_t kMetaImageSamples = 9 * 6 * 5;

// `data` as one zlib stream, as MetaIO writes CompressedData.
std::string zlibOf(const std::string& data) {
  uLongf size = compressBound(uLong(data.size()));
  std::string out(size, '\0');
  EXPECT_EQ(compress2(reinterpret_cast<Bytef*>(out.data()), &size,
                      reinterpret_cast<const Bytef*>(data.data()), uLong(data.size()), 6),
            Z_OK);
  out.resize(size);
  return out;
}

// A header as ITK writes one, for a 9x6x5 volume; `extra` goes before ElementDataFile.
std::string metaImageHeader(const std::string& elementType, const std::string& extra = "",
                            const std::string& dataFile = "LOCAL") {
  return "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
         "CompressedData = False\nTransformMatrix = 1 0 0 0 1 0 0 0 1\nOffset = 0 0 0\n"
         "CenterOfRotation = 0 0 0\nAnatomicalOrientation = RAI\nElementSpacing = 0.5 0.75 2\n"
         "DimSize = 9 6 5\n" +
         extra + "ElementType = " + elementType + "\nElementDataFile = " + dataFile + "\n";
}

// Replaces the value of `key` in `header`.
std::string withValue(std::string header, const std::string& key, const std::string& value) {
  const size_t at = header.find(key + " = ");
  EXPECT_NE(at, std::string::npos) << key;
  const size_t start = at + key.size() + 3;
  return header.replace(start, header.find('\n', start) - start, value);
}

TEST(SourceMetaImage, LocalRawOfEveryType) {
  TempDir dir;
  auto check = [&](auto tag, const std::string& metaType, SampleType type) {
    using T = decltype(tag);
    const auto values = samplePattern<T>(kMetaImageSamples);
    const std::string path = dir.file(metaType + ".mha");
    writeFile(path, metaImageHeader(metaType) + fileBytes(values));
    expectVolume(*openVolumeSource(path), {{9, 6, 5}, type, {0.5, 0.75, 2.0}, "metaimage:" + path}, values);
  };
  check(int8_t{}, "MET_CHAR", SampleType::Int8);
  check(uint8_t{}, "MET_UCHAR", SampleType::UInt8);
  check(int16_t{}, "MET_SHORT", SampleType::Int16);
  check(uint16_t{}, "MET_USHORT", SampleType::UInt16);
  check(int32_t{}, "MET_INT", SampleType::Int32);
  check(uint32_t{}, "MET_UINT", SampleType::UInt32);
  check(int32_t{}, "MET_LONG", SampleType::Int32);
  check(uint32_t{}, "MET_ULONG", SampleType::UInt32);
  check(float{}, "MET_FLOAT", SampleType::Float32);
  check(double{}, "MET_DOUBLE", SampleType::Float64);
}

TEST(SourceMetaImage, DetachedBigEndianCompressedAndSkipped) {
  TempDir dir;
  const auto values = samplePattern<int16_t>(kMetaImageSamples);

  // A .mhd beside its data file, which starts with 7 bytes HeaderSize skips; big-endian; keys in other cases.
  writeFile(dir.file("data.raw"), fileBytes(values, true, 7));
  const std::string mhd = dir.file("detached.mhd");
  writeFile(mhd, withValue(metaImageHeader("MET_SHORT", "HeaderSize = 7\n", "data.raw"),
                           "BinaryDataByteOrderMSB", "True"));
  auto detached = openVolumeSource(mhd);
  EXPECT_EQ(readSlab<int16_t>(*detached, 0, 5), values);

  // HeaderSize -1: the samples end the file, whatever comes before them.
  writeFile(dir.file("tail.raw"), "some leading bytes" + fileBytes(values));
  const std::string tail = dir.file("tail.mhd");
  writeFile(tail, metaImageHeader("MET_SHORT", "HeaderSize = -1\n", "tail.raw"));
  EXPECT_EQ(readSlab<int16_t>(*openVolumeSource(tail), 0, 5), values);

  // ElementSize gives the spacing where ElementSpacing is missing; lower-case keys; CRLF line ends.
  std::string plain =
      "ndims = 3\r\ndimsize = 9 6 5\r\nelementsize = 3 2 1\r\nelementtype = MET_SHORT\r\n"
      "elementdatafile = LOCAL\r\n";
  const std::string lower = dir.file("lower.mha");
  writeFile(lower, plain + fileBytes(values));
  auto lowerSource = openVolumeSource(lower);
  EXPECT_EQ(lowerSource->info().spacing, glm::dvec3(3.0, 2.0, 1.0));
  EXPECT_EQ(readSlab<int16_t>(*lowerSource, 0, 5), values);

  // Compressed, big-endian float, slabs read out of order (the stream restarts).
  const auto floats = samplePattern<float>(kMetaImageSamples);
  const std::string compressed = dir.file("compressed.mha");
  writeFile(compressed, withValue(withValue(metaImageHeader("MET_FLOAT"), "CompressedData", "True"),
                                  "BinaryDataByteOrderMSB", "True") +
                            zlibOf(fileBytes(floats, true)));
  auto source = openVolumeSource(compressed);
  for (const uint32_t z : {3u, 1u, 4u, 0u, 2u}) {
    const auto slab = readSlab<float>(*source, z, 1);
    EXPECT_TRUE(std::equal(slab.begin(), slab.end(), floats.begin() + z * 54)) << "slice " << z;
  }
  EXPECT_EQ(readSlab<float>(*source, 0, 5), floats);
}

// Channels stored interleaved (ElementNumberOfChannels 3, as ITK writes a vector image), compressed and
// big-endian or not: the first read by default, with a warning; --channel picks another.
TEST(SourceMetaImage, ChannelsArePickedByChannel) {
  TempDir dir;
  const auto interleaved = samplePattern<int16_t>(kMetaImageSamples * 3);
  const auto channelOf = [&](size_t c) {
    std::vector<int16_t> values;
    for (size_t i = c; i < interleaved.size(); i += 3) values.push_back(interleaved[i]);
    return values;
  };
  const std::string plain = dir.file("vectors.mha");
  writeFile(plain, metaImageHeader("MET_SHORT", "ElementNumberOfChannels = 3\n") + fileBytes(interleaved));
  const std::string packed = dir.file("packed.mha");
  writeFile(packed, withValue(withValue(metaImageHeader("MET_SHORT", "ElementNumberOfChannels = 3\n"),
                                        "CompressedData", "True"),
                              "BinaryDataByteOrderMSB", "True") +
                        zlibOf(fileBytes(interleaved, true)));
  for (const std::string& path : {plain, packed}) {
    const auto first = openVolumeSource(path);
    EXPECT_EQ(first->info().dims, glm::u32vec3(9, 6, 5));
    EXPECT_EQ(first->info().type, SampleType::Int16);
    EXPECT_EQ(readSlab<int16_t>(*first, 0, 5), channelOf(0)) << path;
    ASSERT_EQ(first->info().notes.size(), 1u);
    EXPECT_EQ(first->info().notes[0],
              "MetaImage " + path +
                  " holds 3 channels: channel 0 of 3 is read; --channel C (0 to 2) picks "
                  "another");
    SourceOptions options;
    options.channel = 2;
    const auto last = openVolumeSource(path, options);
    EXPECT_EQ(readSlab<int16_t>(*last, 0, 5), channelOf(2)) << path;
    const auto slab = readSlab<int16_t>(*last, 3, 2);
    EXPECT_TRUE(std::equal(slab.begin(), slab.end(), channelOf(2).begin() + 3 * 54)) << path;
    EXPECT_EQ(last->info().description, "metaimage:" + path + " (channel 2 of 3)");
    EXPECT_TRUE(last->info().notes.empty());
    options.channel = 3;
    EXPECT_EQ(errorOf(path, options),
              "--channel 3: MetaImage " + path + " holds 3 channels (--channel 0 to 2)");
  }
  // The data of all three channels is needed: one channel's bytes are a file cut short.
  const std::string cut = dir.file("cut.mha");
  writeFile(cut, metaImageHeader("MET_SHORT", "ElementNumberOfChannels = 3\n") + fileBytes(channelOf(0)));
  EXPECT_NE(errorOf(cut).find("truncated"), std::string::npos) << errorOf(cut);
}

TEST(SourceMetaImage, TheTransformMatrixGivesTheAxes) {
  TempDir dir;
  const auto values = samplePattern<uint8_t>(kMetaImageSamples);
  const std::string path = dir.file("flip.mha");
  writeFile(path, withValue(metaImageHeader("MET_UCHAR"), "TransformMatrix", "-1 0 0 0 1 0 0 0 1") +
                      fileBytes(values));
  auto source = openVolumeSource(path);
  EXPECT_TRUE(source->info().notes.empty());
  EXPECT_EQ(orientationCode(source->info().axes), "RPS");
  EXPECT_TRUE(mirrors(source->info().axes));
  EXPECT_EQ(readSlab<uint8_t>(*source, 0, 5), values);  // read as stored: the converter turns x around
  const auto axesOf = [](const std::string& matrix) {
    return parseMetaImageHeader(withValue(metaImageHeader("MET_UCHAR"), "TransformMatrix", matrix), "t.mha");
  };
  // Rows are the axes' directions (as ITK writes them): x along y, y along -x, z along z.
  EXPECT_EQ(axesOf("0 2 0 -1 0 0 0 0 1").axes,
            AxisDirections(glm::dvec3(0, 1, 0), glm::dvec3(-1, 0, 0), glm::dvec3(0, 0, 1)));
  EXPECT_EQ(parseMetaImageHeader(metaImageHeader("MET_UCHAR"), "t.mha").axes, AxisDirections(1.0));
  // Axes not at right angles: not applied, and said.
  const MetaImageHeader sheared = axesOf("1 0 0 0.5 1 0 0 0 1");
  EXPECT_TRUE(sheared.matrixNotApplied);
  EXPECT_EQ(sheared.axes, AxisDirections(1.0));
  const std::string shearPath = dir.file("shear.mha");
  writeFile(shearPath, withValue(metaImageHeader("MET_UCHAR"), "TransformMatrix", "1 0 0 0.5 1 0 0 0 1") +
                           fileBytes(values));
  const auto shear = openVolumeSource(shearPath);
  ASSERT_EQ(shear->info().notes.size(), 1u);
  EXPECT_NE(shear->info().notes[0].find("TransformMatrix does not keep the axes at right angles"),
            std::string::npos);
  EXPECT_FALSE(shear->info().patientFrame);

  // A third row alone off the slices' normal (a gantry's tilt kept in the file): the slices placed where they
  // lie, 1.6 rows further a slice (z's row 0 0.6 1 at spacing 2: 1.2 along y, rows 0.75 apart).
  const std::string tiltPath = dir.file("tilt.mha");
  writeFile(tiltPath, withValue(metaImageHeader("MET_UCHAR"), "TransformMatrix", "1 0 0 0 1 0 0 0.6 1") +
                          fileBytes(values));
  const auto tilt = openVolumeSource(tiltPath);
  EXPECT_EQ(tilt->info().dims, glm::u32vec3(9, 6 + 7, 5));
  EXPECT_EQ(tilt->info().spacing, glm::dvec3(0.5, 0.75, 2.0));
  EXPECT_EQ(tilt->info().axes, AxisDirections(1.0));
  EXPECT_TRUE(tilt->info().patientFrame);  // AnatomicalOrientation = RAI
  ASSERT_EQ(tilt->info().notes.size(), 1u);
  EXPECT_NE(tilt->info().notes[0].find("lie off their normal, by up to 6.4 samples"), std::string::npos)
      << tilt->info().notes[0];
}

// Offset (or its other names, Origin and Position) is where the first sample lies, in LPS as ITK writes it.
TEST(SourceMetaImage, TheOffsetPlacesTheFirstSample) {
  const auto originOf = [](const std::string& header) {
    return parseMetaImageHeader(header, "t.mha").origin;
  };
  std::string header = metaImageHeader("MET_UCHAR");
  EXPECT_EQ(originOf(header), glm::dvec3(0.0));
  EXPECT_EQ(originOf(withValue(header, "Offset", "-120.5 88 30.25")), glm::dvec3(-120.5, 88.0, 30.25));
  header.erase(header.find("Offset = 0 0 0\n"), std::string("Offset = 0 0 0\n").size());
  EXPECT_FALSE(originOf(header));
  for (const char* key : {"Origin", "Position"})
    EXPECT_EQ(originOf(std::string(key) + " = 1 2 3\n" + header), glm::dvec3(1.0, 2.0, 3.0)) << key;
}

// AnatomicalOrientation makes a patient's volume where it is a patient orientation code (ITK writes "???"
// where it knows none) and the TransformMatrix is applied.
TEST(SourceMetaImage, AnAnatomicalOrientationIsAPatientsFrame) {
  const std::string header = metaImageHeader("MET_UCHAR");  // AnatomicalOrientation = RAI
  const auto oriented = [&](const std::string& code) {
    return withValue(header, "AnatomicalOrientation", code);
  };
  for (const char* code : {"RAI", "LPS", "SPL", "ras"})
    EXPECT_TRUE(parseMetaImageHeader(oriented(code), "t.mha").anatomicalOrientation) << code;
  for (const char* code : {"???", "RRI", "RA", "RAIS", "XYZ"})
    EXPECT_FALSE(parseMetaImageHeader(oriented(code), "t.mha").anatomicalOrientation) << code;
  std::string without = header;
  without.erase(without.find("AnatomicalOrientation = RAI\n"),
                std::string("AnatomicalOrientation = RAI\n").size());
  EXPECT_FALSE(parseMetaImageHeader(without, "t.mha").anatomicalOrientation);

  TempDir dir;
  const auto patientFrame = [&](const std::string& text) {
    const std::string path = dir.file("p.mha");
    writeFile(path, text + fileBytes(samplePattern<uint8_t>(kMetaImageSamples)));
    return openVolumeSource(path)->info().patientFrame;
  };
  EXPECT_TRUE(patientFrame(header));
  EXPECT_FALSE(patientFrame(oriented("???")));
  EXPECT_FALSE(patientFrame(without));
  EXPECT_FALSE(patientFrame(withValue(header, "TransformMatrix", "1 0 0 0.5 1 0 0 0 1")));
}

TEST(SourceMetaImage, MalformedHeadersNameFileAndKey) {
  const std::string good = metaImageHeader("MET_SHORT");
  const std::vector<RefusedHeader> cases = {
      {"no data file", "NDims = 3\nDimSize = 9 6 5\nElementType = MET_SHORT\n", "no ElementDataFile"},
      {"no sizes", "NDims = 3\nElementType = MET_SHORT\nElementDataFile = LOCAL\n", "missing key 'DimSize'"},
      {"no type", "NDims = 3\nDimSize = 9 6 5\nElementDataFile = LOCAL\n", "missing key 'ElementType'"},
      {"2D", withValue(good, "NDims", "2"), "only 3-dimensional"},
      {"two sizes", withValue(good, "DimSize", "9 6"), "key 'DimSize'"},
      {"zero size", withValue(good, "DimSize", "9 0 5"), "key 'DimSize'"},
      {"huge", withValue(good, "DimSize", "4294967295 4294967295 4294967295"), "too large"},
      {"64-bit type", withValue(good, "ElementType", "MET_LONG_LONG"), "unsupported element type"},
      {"vector type", withValue(good, "ElementType", "MET_FLOAT_ARRAY"), "unsupported element type"},
      {"channels", metaImageHeader("MET_UCHAR", "ElementNumberOfChannels = 0\n"), "ElementNumberOfChannels"},
      {"too many channels",
       withValue(metaImageHeader("MET_DOUBLE", "ElementNumberOfChannels = 65536\n"), "DimSize",
                 "1048576 1048576 512"),
       "more than 2^62 bytes"},
      {"ASCII", withValue(good, "BinaryData", "False"), "ASCII data"},
      {"not a boolean", withValue(good, "CompressedData", "maybe"), "expected True or False"},
      {"other object", withValue(good, "ObjectType", "Tube"), "expected Image"},
      {"zero spacing", withValue(good, "ElementSpacing", "1 0 1"), "spacing of axis 1 is zero"},
      {"NaN spacing", withValue(good, "ElementSpacing", "1 nan 1"), "key 'ElementSpacing'"},
      {"short matrix", withValue(good, "TransformMatrix", "1 0 0 1"), "key 'TransformMatrix'"},
      {"short offset", withValue(good, "Offset", "0 0"), "key 'Offset'"},
      {"NaN offset", withValue(good, "Offset", "0 nan 0"), "key 'Offset'"},
      {"twice", metaImageHeader("MET_SHORT", "dimsize = 1 1 1\n"), "given more than once"},
      {"byte orders disagree", metaImageHeader("MET_SHORT", "ElementByteOrderMSB = True\n"), "contradicts"},
      {"bad header size", metaImageHeader("MET_SHORT", "HeaderSize = -2\n"), "key 'HeaderSize'"},
      {"end of a compressed file",
       withValue(metaImageHeader("MET_SHORT", "HeaderSize = -1\n"), "CompressedData", "True"),
       "uncompressed"},
      {"list of none", metaImageHeader("MET_SHORT", "", "LIST"), "0 data files for 5 slices"},
      {"list of too few", metaImageHeader("MET_SHORT", "", "LIST") + "a.raw\nb.raw\n", "2 data files for 5"},
      {"list 3D", metaImageHeader("MET_SHORT", "", "LIST 3D"), "expected LIST or LIST 2D"},
      {"pattern of too many", metaImageHeader("MET_SHORT", "", "slice%03d.raw 1 6 1"), "6 data files for 5"},
      {"pattern without %d", metaImageHeader("MET_SHORT", "", "slice.raw 1 5 1"), "holds no %d"},
      {"pattern of two", metaImageHeader("MET_SHORT", "", "s%d_%d.raw 1 5 1"), "must hold one %d"},
      {"pattern of %s", metaImageHeader("MET_SHORT", "", "s%s.raw 1 5 1"), "must hold one %d"},
      {"pattern step 0", metaImageHeader("MET_SHORT", "", "s%d.raw 1 5 0"), "by a step that reaches it"},
      {"pattern backwards", metaImageHeader("MET_SHORT", "", "s%d.raw 5 1 1"), "by a step that reaches it"},
      {"no equals sign", "NDims 3\n" + good, "expected 'Key = Value'"},
  };
  expectHeadersRefused(cases, "/some/dir/bad.mha",
                       [](const std::string& h, const std::string& f) { parseMetaImageHeader(h, f); });
}

// A file per slice: LIST (big-endian, each file after a 4-byte header), LIST 2D of two interleaved channels,
// a pattern counting down (each slice ending its file, HeaderSize -1), and LIST of zlib-compressed slices:
// read as one file of them would be.
TEST(SourceMetaImage, AFilePerSliceListedOrByPattern) {
  TempDir dir;
  const auto values = samplePattern<int16_t>(kMetaImageSamples);
  const auto sliceOf = [&](const std::vector<int16_t>& all, size_t z, size_t per) {
    return std::vector<int16_t>(all.begin() + long(z * per), all.begin() + long((z + 1) * per));
  };
  std::string names;
  for (size_t z = 0; z < 5; ++z) {
    writeFile(dir.file("list_" + std::to_string(z) + ".raw"),
              "HEAD" + fileBytes(sliceOf(values, z, 54), true));
    names += "list_" + std::to_string(z) + ".raw\n";
  }
  const std::string listed = dir.file("listed.mhd");
  writeFile(listed, withValue(metaImageHeader("MET_SHORT", "HeaderSize = 4\n", "LIST"),
                              "BinaryDataByteOrderMSB", "True") +
                        names);
  auto source = openVolumeSource(listed);
  EXPECT_EQ(source->info().dims, glm::u32vec3(9, 6, 5));
  EXPECT_EQ(readSlab<int16_t>(*source, 0, 5), values);
  EXPECT_EQ(readSlab<int16_t>(*source, 2, 2),
            std::vector<int16_t>(values.begin() + 108, values.begin() + 216));

  const auto interleaved = samplePattern<int16_t>(kMetaImageSamples * 2);
  names.clear();
  for (size_t z = 0; z < 5; ++z) {
    writeFile(dir.file("two_" + std::to_string(z) + ".raw"), fileBytes(sliceOf(interleaved, z, 108)));
    names += "  two_" + std::to_string(z) + ".raw  \n\n";
  }
  const std::string channels = dir.file("channels.mhd");
  writeFile(channels, metaImageHeader("MET_SHORT", "ElementNumberOfChannels = 2\n", "LIST 2D") + names);
  SourceOptions second;
  second.channel = 1;
  std::vector<int16_t> expected;
  for (size_t i = 1; i < interleaved.size(); i += 2) expected.push_back(interleaved[i]);
  EXPECT_EQ(readSlab<int16_t>(*openVolumeSource(channels, second), 0, 5), expected);

  for (size_t z = 0; z < 5; ++z)
    writeFile(dir.file("img00" + std::to_string(9 - z) + ".raw"),
              std::string(z + 1, 'x') + fileBytes(sliceOf(values, z, 54)));
  const std::string pattern = dir.file("pattern.mhd");
  writeFile(pattern, metaImageHeader("MET_SHORT", "HeaderSize = -1\n", "img%03d.raw 9 5 -1"));
  EXPECT_EQ(readSlab<int16_t>(*openVolumeSource(pattern), 0, 5), values);

  // CompressedData with a file per slice: a zlib stream of its slice in each, as MetaIO writes them; one
  // damaged is named when its slice is read.
  names.clear();
  for (size_t z = 0; z < 5; ++z) {
    writeFile(dir.file("zlib_" + std::to_string(z) + ".raw"), zlibOf(fileBytes(sliceOf(values, z, 54))));
    names += "zlib_" + std::to_string(z) + ".raw\n";
  }
  const std::string compressed = dir.file("compressed.mhd");
  writeFile(compressed,
            withValue(metaImageHeader("MET_SHORT", "", "LIST"), "CompressedData", "True") + names);
  EXPECT_EQ(readSlab<int16_t>(*openVolumeSource(compressed), 0, 5), values);
  EXPECT_EQ(readSlab<int16_t>(*openVolumeSource(compressed), 3, 1),
            std::vector<int16_t>(values.begin() + 162, values.begin() + 216));
  std::string damaged = zlibOf(fileBytes(sliceOf(values, 2, 54)));
  damaged[damaged.size() - 2] ^= 0x40;  // the Adler-32 at its end
  writeFile(dir.file("zlib_2.raw"), damaged);
  std::string failure;
  try {
    readSlab<int16_t>(*openVolumeSource(compressed), 0, 5);
  } catch (const Error& e) {
    failure = e.what();
  }
  EXPECT_NE(failure.find("MetaImage data file " + dir.file("zlib_2.raw")), std::string::npos) << failure;

  // A missing or short slice file is named when the source opens.
  fs::remove(dir.file("list_3.raw"));
  EXPECT_NE(errorOf(listed).find("list_3.raw"), std::string::npos) << errorOf(listed);
  writeFile(dir.file("list_3.raw"), "HEAD" + fileBytes(sliceOf(values, 3, 53), true));
  const std::string message = errorOf(listed);
  EXPECT_NE(message.find("MetaImage data file " + dir.file("list_3.raw") +
                         " holds 110 bytes; a slice of 9x6x1 int16 "
                         "samples is 108 after 4 header bytes"),
            std::string::npos)
      << message;
}

TEST(SourceMetaImage, BadDataFilesNameTheFile) {
  TempDir dir;
  const auto values = samplePattern<uint16_t>(kMetaImageSamples);
  const std::string data = fileBytes(values);

  const std::string truncated = dir.file("truncated.mha");
  writeFile(truncated, metaImageHeader("MET_USHORT") + data.substr(0, data.size() - 1));
  std::string message = errorOf(truncated);
  EXPECT_NE(message.find(truncated), std::string::npos) << message;
  EXPECT_NE(message.find("truncated"), std::string::npos) << message;

  const std::string missing = dir.file("missing.mhd");
  writeFile(missing, metaImageHeader("MET_USHORT", "", "nothere.raw"));
  message = errorOf(missing);
  EXPECT_NE(message.find(missing), std::string::npos) << message;
  EXPECT_NE(message.find(dir.file("nothere.raw")), std::string::npos) << message;

  // Compressed data cut short or damaged: refused while reading, naming the file.
  const std::string z = zlibOf(data);
  const std::string compressedHeader = withValue(metaImageHeader("MET_USHORT"), "CompressedData", "True");
  std::string corruptBytes = z;
  for (size_t i = 10; i < corruptBytes.size() - 10; i += 7) corruptBytes[i] = char(~corruptBytes[i]);
  std::string badChecksum = z;
  badChecksum.back() = char(~badChecksum.back());
  const std::vector<std::pair<std::string, std::string>> damaged = {
      {"short.mha", z.substr(0, z.size() / 2)},
      {"corrupt.mha", corruptBytes},
      {"nochecksum.mha", z.substr(0, z.size() - 4)},  // every sample there, the stream's Adler-32 cut off
      {"badchecksum.mha", badChecksum}};
  for (const auto& [name, bytes] : damaged) {
    const std::string path = dir.file(name);
    writeFile(path, compressedHeader + bytes);
    std::vector<uint16_t> all(kMetaImageSamples);
    try {
      openVolumeSource(path)->readSlab(0, 5, std::as_writable_bytes(std::span(all)));
      ADD_FAILURE() << name << " read without error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }

  // A header longer than what is read as one (its data file's name could be cut to another file's).
  const std::string longHeader = dir.file("long.mhd");
  writeFile(longHeader, "Comment = " + std::string(kMaxMetaImageHeaderBytes, 'c') + "\n" +
                            metaImageHeader("MET_USHORT", "", "vol.raw"));
  message = errorOf(longHeader);
  EXPECT_NE(message.find("longer than the 1048576 bytes read as a header"), std::string::npos) << message;
  const std::string cutLine = dir.file("cut.mhd");
  const std::string before = "NDims = 3\nDimSize = 9 6 5\nElementType = MET_USHORT\nComment = ";
  const std::string padding(kMaxMetaImageHeaderBytes - 50 - before.size() - 1, 'c');
  writeFile(cutLine, before + padding + "\nElementDataFile = vol" + std::string(400, 'x') + ".raw\n");
  message = errorOf(cutLine);
  EXPECT_NE(message.find("longer than the 1048576 bytes read as a header"), std::string::npos) << message;

  // Dims and type come from the header, not from options.
  SourceOptions options;
  options.dims = glm::u32vec3(1, 2, 3);
  EXPECT_NE(errorOf(truncated, options).find("--dims applies to raw files only"), std::string::npos);
}

}  // namespace
}  // namespace ropecast
