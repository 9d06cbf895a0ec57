// Tests of the NRRD header parser and the NRRD VolumeSource: attached and detached data, raw and gzip
// encodings, big-endian data, spacings and space directions, byte and line skips, gzip slabs read out of
// order, and each malformed header or data file giving an error that names the file and the field.
#include <bit>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "store/nrrd_header.h"
#include "store/source_nrrd.h"
#include "store/volume_source.h"
#include "tests/store/store_test_util.h"

namespace ropecast {
namespace {

namespace fs = std::filesystem;
using testing::errorOf;
using testing::expectVolume;
using testing::gzipOf;
using testing::readSlab;
using testing::samplePattern;
using testing::TempDir;
using testing::writeFile;

template <typename T>
std::string bytesOf(const std::vector<T>& values, bool bigEndian) {
  std::string bytes(values.size() * sizeof(T), '\0');
  std::memcpy(bytes.data(), values.data(), bytes.size());
  if (bigEndian != (std::endian::native == std::endian::big))
    for (size_t i = 0; i < bytes.size(); i += sizeof(T))
      std::reverse(bytes.begin() + i, bytes.begin() + i + sizeof(T));
  return bytes;
}

std::string headerFor(const std::string& type, const std::string& encoding, const std::string& extra = "") {
  return "NRRD0004\n# a comment\ntype: " + type + "\ndimension: 3\nsizes: 9 6 5\nencoding: " + encoding +
         "\nendian: little\nkinds: domain domain domain\ncontent:=ignored key value\n" + extra;
}

TEST(SourceNrrd, AttachedRawOfEveryType) {
  TempDir dir;
  auto check = [&](auto tag, const std::string& nrrdType, SampleType type) {
    using T = decltype(tag);
    const auto values = samplePattern<T>(9 * 6 * 5);
    const std::string path = dir.file(nrrdType + ".nrrd");
    writeFile(path, headerFor(nrrdType, "raw", "spacings: 0.5 0.75 2\n") + "\n" + bytesOf(values, false));
    expectVolume(*openVolumeSource(path), {{9, 6, 5}, type, {0.5, 0.75, 2.0}, "nrrd:" + path}, values);
  };
  check(uint8_t{}, "uchar", SampleType::UInt8);
  check(uint16_t{}, "unsigned short", SampleType::UInt16);
  check(int16_t{}, "short", SampleType::Int16);
  check(float{}, "float", SampleType::Float32);
  check(int8_t{}, "signed char", SampleType::Int8);
  check(uint32_t{}, "uint", SampleType::UInt32);
  check(int32_t{}, "int", SampleType::Int32);
  check(double{}, "double", SampleType::Float64);
}

TEST(SourceNrrd, TypeSpellingsOfTheSpec) {
  const std::pair<const char*, SampleType> spellings[] = {
      {"uint8", SampleType::UInt8},         {"unsigned char", SampleType::UInt8},
      {"uint8_t", SampleType::UInt8},       {"ushort", SampleType::UInt16},
      {"uint16_t", SampleType::UInt16},     {"unsigned short int", SampleType::UInt16},
      {"int16", SampleType::Int16},         {"signed short int", SampleType::Int16},
      {"short int", SampleType::Int16},     {"float", SampleType::Float32},
      {"int8", SampleType::Int8},           {"int8_t", SampleType::Int8},
      {"unsigned int", SampleType::UInt32}, {"uint32", SampleType::UInt32},
      {"uint32_t", SampleType::UInt32},     {"signed int", SampleType::Int32},
      {"int32", SampleType::Int32},         {"int32_t", SampleType::Int32},
      {"double", SampleType::Float64}};
  for (const auto& [name, type] : spellings)
    EXPECT_EQ(parseNrrdHeader(headerFor(name, "raw") + "\n", "t.nrrd").type, type) << name;
}

TEST(SourceNrrd, BigEndianIsSwapped) {
  TempDir dir;
  const auto u16 = samplePattern<uint16_t>(9 * 6 * 5);
  const std::string a = dir.file("big16.nrrd");
  std::string header = headerFor("uint16", "raw");
  header.replace(header.find("endian: little"), 14, "endian: big");
  writeFile(a, header + "\n" + bytesOf(u16, true));
  auto source = openVolumeSource(a);
  EXPECT_EQ(readSlab<uint16_t>(*source, 0, 5), u16);

  const auto f32 = samplePattern<float>(9 * 6 * 5);
  const std::string b = dir.file("bigf.nrrd");
  header = headerFor("float", "gzip");
  header.replace(header.find("endian: little"), 14, "endian: big");
  writeFile(b, header + "\n" + gzipOf(bytesOf(f32, true)));
  auto gz = openVolumeSource(b);
  EXPECT_EQ(readSlab<float>(*gz, 0, 5), f32);

  const auto f64 = samplePattern<double>(9 * 6 * 5);
  const std::string c = dir.file("bigd.nrrd");
  header = headerFor("double", "raw");
  header.replace(header.find("endian: little"), 14, "endian: big");
  writeFile(c, header + "\n" + bytesOf(f64, true));
  EXPECT_EQ(readSlab<double>(*openVolumeSource(c), 0, 5), f64);

  const auto i32 = samplePattern<int32_t>(9 * 6 * 5);
  const std::string d = dir.file("bigi.nrrd");
  header = headerFor("int32", "gzip");
  header.replace(header.find("endian: little"), 14, "endian: big");
  writeFile(d, header + "\n" + gzipOf(bytesOf(i32, true)));
  EXPECT_EQ(readSlab<int32_t>(*openVolumeSource(d), 0, 5), i32);
}

TEST(SourceNrrd, GzipSlabsInAnyOrder) {
  TempDir dir;
  const auto values = samplePattern<int16_t>(9 * 6 * 5);
  const std::string path = dir.file("gz.nrrd");
  // Byte skip with gzip applies to the decompressed data.
  writeFile(path,
            headerFor("int16", "gz", "byte skip: 6\n") + "\n" + gzipOf("HEADER" + bytesOf(values, false)));
  auto source = openVolumeSource(path);
  for (uint32_t z0 : {0u, 2u, 4u, 1u, 1u, 0u, 3u}) {  // forward, backward (restart), repeated
    const auto slab = readSlab<int16_t>(*source, z0, 1);
    EXPECT_TRUE(std::equal(slab.begin(), slab.end(), values.begin() + z0 * 54)) << "z0 " << z0;
  }
  EXPECT_EQ(readSlab<int16_t>(*source, 0, 5), values);
}

TEST(SourceNrrd, ConcatenatedGzipMembers) {
  TempDir dir;
  const auto values = samplePattern<uint8_t>(9 * 6 * 5);
  const std::string data = bytesOf(values, false);
  const std::string path = dir.file("members.nrrd");
  writeFile(path, headerFor("uchar", "gzip") + "\n" + gzipOf(data.substr(0, 100)) + gzipOf(data.substr(100)));
  auto source = openVolumeSource(path);
  EXPECT_EQ(readSlab<uint8_t>(*source, 0, 5), values);
}

TEST(SourceNrrd, DetachedDataWithSkips) {
  TempDir dir;
  const auto values = samplePattern<uint16_t>(9 * 6 * 5);
  fs::create_directories(dir.file("data"));
  // Line skip first (two text lines), then byte skip.
  writeFile(dir.file("data/vol.raw"), "line one\nline two\nXYZ" + bytesOf(values, false));
  const std::string nhdr = dir.file("vol.nhdr");
  writeFile(nhdr, headerFor("uint16", "raw",
                            "line skip: 2\nbyte skip: 3\ndata file: data/vol.raw\n"));  // no blank line
  auto source = openVolumeSource(nhdr);
  EXPECT_EQ(readSlab<uint16_t>(*source, 0, 5), values);
  EXPECT_EQ(source->info().description, "nrrd:" + nhdr);

  // byte skip -1: the data is the end of the file, whatever precedes it.
  writeFile(dir.file("tail.raw"), "some junk of any length" + bytesOf(values, false));
  const std::string tail = dir.file("tail.nhdr");
  writeFile(tail, headerFor("uint16", "raw", "byte skip: -1\ndatafile: tail.raw\n") + "\n");
  EXPECT_EQ(readSlab<uint16_t>(*openVolumeSource(tail), 0, 5), values);

  // Detached gzip.
  writeFile(dir.file("vol.raw.gz"), gzipOf(bytesOf(values, false)));
  const std::string gz = dir.file("gz.nhdr");
  writeFile(gz, headerFor("uint16", "gzip", "data file: " + dir.file("vol.raw.gz") + "\n"));
  EXPECT_EQ(readSlab<uint16_t>(*openVolumeSource(gz), 0, 5), values);
}

TEST(SourceNrrd, SpacingFromSpaceDirections) {
  const NrrdHeader h = parseNrrdHeader(
      headerFor("uchar", "raw",
                "space: RAS\nspace directions: (0,0.5,0) (3,4,0) (0, 0, -2.5)\nspacings: 7 7 7\n"),
      "t.nhdr");
  EXPECT_EQ(h.spacing, glm::dvec3(0.5, 5.0, 2.5));
  EXPECT_TRUE(h.directionsNotApplied);  // x and y not at right angles
  EXPECT_EQ(h.axes, AxisDirections(1.0));
  const auto directions = [](const std::string& value, const std::string& space = "") {
    return parseNrrdHeader(headerFor("uchar", "raw", space + "space directions: " + value + "\n"), "t.nhdr");
  };
  EXPECT_EQ(directions("(0.5,0,0) (0,1,-0) (0,0,2)").axes, AxisDirections(1.0));
  EXPECT_EQ(orientationCode(directions("(-0.5,0,0) (0,1,0) (0,0,2)").axes), "RPS");  // flipped
  const NrrdHeader turned = directions("(0.3,0.4,0) (-0.4,0.3,0) (0,0,2)");
  EXPECT_FALSE(turned.directionsNotApplied);
  EXPECT_EQ(turned.spacing, glm::dvec3(0.5, 0.5, 2.0));
  EXPECT_NEAR(turned.axes[0].x, 0.6, 1e-12);
  EXPECT_NEAR(turned.axes[1].x, -0.8, 1e-12);
  EXPECT_EQ(orientationCode(turned.axes), "PRS (oblique)");
  // An anatomical space: its directions turned into LPS (RAS and LAS negate x and y, or y).
  EXPECT_EQ(directions("(-1,0,0) (0,-1,0) (0,0,1)", "space: RAS\n").axes, AxisDirections(1.0));
  EXPECT_EQ(orientationCode(directions("(1,0,0) (0,1,0) (0,0,1)", "space: right-anterior-superior\n").axes),
            "RAS");
  EXPECT_EQ(orientationCode(directions("(1,0,0) (0,1,0) (0,0,1)", "space: LAS\n").axes), "LAS");
  EXPECT_EQ(orientationCode(directions("(0,1,0) (0,0,-1) (-1,0,0)", "space: left-posterior-superior\n").axes),
            "PIR");
  EXPECT_TRUE(directions("none (1,0,0) (0,1,0)").directionsNotApplied);
  const NrrdHeader n = parseNrrdHeader(headerFor("uchar", "raw", "spacings: nan 2 -3\n"), "t.nhdr");
  EXPECT_EQ(n.spacing, glm::dvec3(1.0, 2.0, 3.0));
  const NrrdHeader none =
      parseNrrdHeader(headerFor("uchar", "raw", "space directions: none (2,0,0) none\n"), "t");
  EXPECT_EQ(none.spacing, glm::dvec3(1.0, 2.0, 1.0));
  EXPECT_EQ(parseNrrdHeader(headerFor("uchar", "raw"), "t").spacing, glm::dvec3(1.0));
  EXPECT_FALSE(parseNrrdHeader(headerFor("uchar", "raw"), "t").endsWithBlankLine);
  const std::string withData = headerFor("uchar", "raw") + "\r\n\x01\x02";
  const NrrdHeader crlf = parseNrrdHeader(withData, "t");
  EXPECT_TRUE(crlf.endsWithBlankLine);
  EXPECT_EQ(crlf.headerBytes, withData.size() - 2);
}

// The space origin, turned into LPS as the directions are; an unknown one (Teem's nan) or a malformed one is
// no origin, the second said to the user.
TEST(SourceNrrd, SpaceOriginInLps) {
  const auto origin = [](const std::string& fields) {
    return parseNrrdHeader(headerFor("uchar", "raw", fields), "t.nhdr");
  };
  EXPECT_EQ(origin("space: LPS\nspace origin: (-120.5,88,30.25)\n").origin, glm::dvec3(-120.5, 88.0, 30.25));
  EXPECT_EQ(origin("space origin: ( 1, 2 ,3 )\nspace: right-anterior-superior\n").origin,
            glm::dvec3(-1.0, -2.0, 3.0));  // the space may come after it
  EXPECT_EQ(origin("space: LAS\nspace origin: (1,2,3)\n").origin, glm::dvec3(1.0, -2.0, 3.0));
  EXPECT_FALSE(origin("").origin);
  const NrrdHeader unknown = origin("space origin: (nan,nan,nan)\n");
  EXPECT_FALSE(unknown.origin);
  EXPECT_FALSE(unknown.originNotRead);
  for (const char* bad : {"(1,2)", "(1,2,3,4)", "1,2,3", "(1,inf,3)", "(1,x,3)"}) {
    const NrrdHeader h = origin("space origin: " + std::string(bad) + "\n");
    EXPECT_FALSE(h.origin) << bad;
    EXPECT_TRUE(h.originNotRead) << bad;
  }
}

// A space that names a patient's frame (NRRD's long and short names, with "-time") makes a patient's volume
// where its directions are applied; scanner-xyz, a 3D-handed space or none does not.
TEST(SourceNrrd, AnAnatomicalSpaceIsAPatientsFrame) {
  const auto header = [](const std::string& fields) {
    return parseNrrdHeader(headerFor("uchar", "raw", fields), "t.nhdr");
  };
  for (const char* space : {"RAS", "LAS", "LPS", "right-anterior-superior", "Left-Posterior-Superior",
                            "left-anterior-superior", "RAS-time", "left-posterior-superior-time"})
    EXPECT_TRUE(header("space: " + std::string(space) + "\n").anatomicalSpace) << space;
  for (const char* space : {"scanner-xyz", "3D-right-handed", "3D-left-handed-time"})
    EXPECT_FALSE(header("space: " + std::string(space) + "\n").anatomicalSpace) << space;
  EXPECT_FALSE(header("").anatomicalSpace);

  TempDir dir;
  const auto patientFrame = [&](const std::string& fields) {
    const std::string path = dir.file("p.nrrd");
    writeFile(path,
              headerFor("uchar", "raw", fields) + "\n" + bytesOf(samplePattern<uint8_t>(9 * 6 * 5), false));
    return openVolumeSource(path)->info().patientFrame;
  };
  EXPECT_TRUE(patientFrame("space: RAS\nspace directions: (-1,0,0) (0,-1,0) (0,0,1)\n"));
  EXPECT_FALSE(patientFrame("space: scanner-xyz\nspace directions: (1,0,0) (0,1,0) (0,0,1)\n"));
  EXPECT_FALSE(patientFrame("spacings: 1 1 1\n"));
  // Directions not at right angles are not applied: the volume is shown unturned, in no patient's frame.
  EXPECT_FALSE(patientFrame("space: RAS\nspace directions: (0,0.5,0) (3,4,0) (0,0,-2.5)\n"));
}

// Space directions whose third alone is off the slices' normal (a gantry's tilt kept in the file): the slices
// are placed where they lie. Here each lies a whole row further down than the one below, so the grid's
// samples are the file's, moved, and the bottom slice's smallest (1) where no slice reaches.
TEST(SourceNrrd, SkewedSpaceDirectionsArePlacedWhereTheSlicesLie) {
  TempDir dir;
  const std::string path = dir.file("tilted.nrrd");
  std::vector<float> values(4 * 3 * 3);
  for (size_t i = 0; i < values.size(); ++i) values[i] = float(i + 1);
  writeFile(
      path,
      "NRRD0004\ntype: float\ndimension: 3\nsizes: 4 3 3\nencoding: raw\nendian: little\n"
      "space: left-posterior-superior\nspace directions: (1,0,0) (0,1,0) (0,1,2)\nspace origin: (5,6,7)\n\n" +
          bytesOf(values, false));
  const auto source = openVolumeSource(path);
  const VolumeInfo& info = source->info();
  EXPECT_EQ(info.dims, glm::u32vec3(4, 5, 3));
  EXPECT_EQ(info.spacing, glm::dvec3(1.0, 1.0, 2.0));
  EXPECT_EQ(info.axes, AxisDirections(1.0));
  EXPECT_EQ(info.origin, glm::dvec3(5.0, 6.0, 7.0));
  EXPECT_TRUE(info.patientFrame);
  ASSERT_EQ(info.notes.size(), 1u);
  EXPECT_NE(info.notes[0].find("lie off their normal, by up to 2 samples"), std::string::npos)
      << info.notes[0];
  const std::vector<float> grid = readSlab<float>(*source, 0, 3);
  for (uint32_t k = 0; k < 3; ++k)
    for (uint32_t j = 0; j < 5; ++j)
      for (uint32_t i = 0; i < 4; ++i) {
        const float expected = j >= k && j - k < 3 ? values[(k * 3 + (j - k)) * 4 + i] : 1.0f;
        EXPECT_EQ(grid[(k * 5 + j) * 4 + i], expected) << i << "," << j << "," << k;
      }
  // --spacing stacks the file's slices as they are.
  SourceOptions options;
  options.spacing = glm::dvec3(1.0);
  EXPECT_EQ(openVolumeSource(path, options)->info().dims, glm::u32vec3(4, 3, 3));
}

struct BadHeader {
  const char* what;
  std::string header;
  const char* expected;  // text the message must contain, besides the file name
};

// Dimension 4: volumes one after another along a last axis of kind time (raw, and at the file's end) or list
// (gzip), and a vector's components interleaved along a first axis; each picked by --time or --channel.
// Volume v holds the pattern plus 1000 v.
TEST(SourceNrrd, FourDimensionsAreVolumesPickedByTimeOrChannel) {
  TempDir dir;
  const auto first = samplePattern<int16_t>(9 * 6 * 5);
  std::vector<int16_t> stacked, interleaved;
  for (int v = 0; v < 3; ++v)
    for (const int16_t value : first) stacked.push_back(int16_t(value + 1000 * v));
  for (const int16_t value : first)
    for (int v = 0; v < 3; ++v) interleaved.push_back(int16_t(value + 1000 * v));
  const auto volumeOf = [&](int v) {
    std::vector<int16_t> values;
    for (const int16_t value : first) values.push_back(int16_t(value + 1000 * v));
    return values;
  };
  const std::string common = "NRRD0005\ntype: short\ndimension: 4\nendian: little\n";
  const std::string series = dir.file("series.nrrd");
  writeFile(series, common +
                        "sizes: 9 6 5 3\nkinds: domain domain domain time\nencoding: raw\n"
                        "space directions: (0.5,0,0) (0,0.75,0) (0,0,2) none\n\n" +
                        bytesOf(stacked, false));
  const std::string atEnd = dir.file("at_end.nhdr");
  writeFile(dir.file("at_end.raw"), "some leading bytes" + bytesOf(stacked, false));
  writeFile(atEnd, common +
                       "sizes: 9 6 5 3\nkinds: space space space time\nencoding: raw\nbyte skip: -1\n"
                       "spacings: 0.5 0.75 2 nan\ndata file: at_end.raw\n");
  for (const std::string& path : {series, atEnd}) {
    const auto source = openVolumeSource(path);
    EXPECT_EQ(source->info().dims, glm::u32vec3(9, 6, 5));
    EXPECT_EQ(source->info().spacing, glm::dvec3(0.5, 0.75, 2.0));
    EXPECT_EQ(readSlab<int16_t>(*source, 0, 5), volumeOf(0)) << path;
    ASSERT_EQ(source->info().notes.size(), 1u);
    EXPECT_EQ(source->info().notes[0],
              "NRRD file " + path +
                  " holds 3 time points: time point 0 of 3 is read; --time T (0 to 2) picks another");
    SourceOptions options;
    options.timePoint = 2;
    const auto last = openVolumeSource(path, options);
    EXPECT_EQ(readSlab<int16_t>(*last, 0, 5), volumeOf(2)) << path;
    EXPECT_EQ(last->info().description, "nrrd:" + path + " (time point 2 of 3)");
    options.timePoint.reset();
    options.channel = 1;
    EXPECT_EQ(errorOf(path, options),
              "--channel 1: NRRD file " + path + " holds 1 channel (--channel 0 alone)");
  }

  const std::string list = dir.file("list.nrrd");
  writeFile(list, common + "sizes: 9 6 5 3\nkinds: domain domain domain list\nencoding: gzip\n\n" +
                      gzipOf(bytesOf(stacked, false)));
  const std::string vectors = dir.file("vectors.nrrd");
  writeFile(vectors, common +
                         "sizes: 3 9 6 5\nkinds: vector domain domain domain\nencoding: raw\n"
                         "space directions: none (0.5,0,0) (0,0.75,0) (0,0,2)\nspace origin: (1,2,3)\n\n" +
                         bytesOf(interleaved, false));
  for (const std::string& path : {list, vectors}) {
    const auto source = openVolumeSource(path);
    EXPECT_EQ(source->info().dims, glm::u32vec3(9, 6, 5)) << path;
    EXPECT_EQ(readSlab<int16_t>(*source, 0, 5), volumeOf(0)) << path;
    ASSERT_EQ(source->info().notes.size(), 1u);
    EXPECT_EQ(source->info().notes[0],
              "NRRD file " + path +
                  " holds 3 components: component 0 of 3 is read; --channel C (0 to 2) "
                  "picks another");
    SourceOptions options;
    options.channel = 1;
    const auto picked = openVolumeSource(path, options);
    for (const uint32_t z : {3u, 1u, 4u, 0u, 2u}) {
      const auto slab = readSlab<int16_t>(*picked, z, 1);
      EXPECT_TRUE(std::equal(slab.begin(), slab.end(), volumeOf(1).begin() + z * 54)) << path << " " << z;
    }
  }
  EXPECT_EQ(openVolumeSource(vectors)->info().spacing, glm::dvec3(0.5, 0.75, 2.0));
  EXPECT_EQ(openVolumeSource(vectors)->info().origin, glm::dvec3(1.0, 2.0, 3.0));

  // A series cut short is refused as truncated.
  const std::string cut = dir.file("cut.nrrd");
  writeFile(cut, common + "sizes: 9 6 5 3\nkinds: domain domain domain time\nencoding: raw\n\n" +
                     bytesOf(first, false));
  EXPECT_NE(errorOf(cut).find("truncated"), std::string::npos) << errorOf(cut);
}

TEST(SourceNrrd, MalformedHeadersNameFileAndField) {
  const std::string good = headerFor("uint16", "raw");
  auto without = [&](const std::string& line) {
    std::string h = good;
    h.erase(h.find(line), line.size() + 1);
    return h;
  };
  auto replaced = [&](const std::string& line, const std::string& by) {
    std::string h = good;
    h.replace(h.find(line), line.size(), by);
    return h;
  };
  // Dimension 4 with these sizes and kinds (none: no kinds field).
  auto fourD = [&](const std::string& sizes, const std::string& kinds) {
    std::string h = good;
    h.replace(h.find("dimension: 3"), 12, "dimension: 4");
    h.replace(h.find("sizes: 9 6 5"), 12, "sizes: " + sizes);
    const size_t at = h.find("kinds: domain domain domain\n");
    h.replace(at, 28, kinds.empty() ? "" : "kinds: " + kinds + "\n");
    return h;
  };
  const BadHeader cases[] = {
      {"bad magic", "NRRD\n" + good.substr(9), "magic line"},
      {"no newline", "NRRD0004", "magic line"},
      {"empty", "", "magic line"},
      {"missing type", without("type: uint16"), "missing field 'type'"},
      {"missing sizes", without("sizes: 9 6 5"), "missing field 'sizes'"},
      {"missing dimension", without("dimension: 3"), "missing field 'dimension'"},
      {"missing encoding", without("encoding: raw"), "missing field 'encoding'"},
      {"missing endian", without("endian: little"), "missing field 'endian'"},
      {"sizes two numbers", replaced("sizes: 9 6 5", "sizes: 9 6"), "field 'sizes'"},
      {"sizes four numbers", replaced("sizes: 9 6 5", "sizes: 9 6 5 1"), "field 'sizes'"},
      {"sizes not numbers", replaced("sizes: 9 6 5", "sizes: 9 six 5"), "field 'sizes'"},
      {"sizes zero", replaced("sizes: 9 6 5", "sizes: 9 0 5"), "field 'sizes'"},
      {"sizes negative", replaced("sizes: 9 6 5", "sizes: 9 -6 5"), "field 'sizes'"},
      {"sizes overflow", replaced("sizes: 9 6 5", "sizes: 4000000000 4000000000 4000000000"), "too large"},
      {"sizes huge", replaced("sizes: 9 6 5", "sizes: 99999999999999999999 1 1"), "field 'sizes'"},
      {"dimension 5", replaced("dimension: 3", "dimension: 5"), "field 'dimension'"},
      {"dimension 4, three sizes", fourD("9 6 5", "domain domain domain list"),
       "field 'sizes' (line 5): expected 4 entries"},
      {"dimension 4, three kinds", fourD("9 6 5 2", "domain domain domain"), "expected 4 kinds"},
      {"dimension 4, no kinds", fourD("9 6 5 2", ""), "neither kinds nor space directions"},
      {"dimension 4, five directions",
       fourD("3 9 6 5", "") + "space directions: none (1,0,0) (0,1,0) (0,0,1) none\n",
       "field 'space directions' (line 9): expected 4 entries"},
      {"dimension 4, a middle axis", fourD("9 2 6 5", "domain list domain domain"), "between spatial ones"},
      {"dimension 4, two lists", fourD("2 2 6 5", "list list domain domain"), "two axes (0 and 1)"},
      {"dimension 4, all spatial", fourD("9 6 5 2", "domain domain domain domain"), "every axis is domain"},
      {"dimension 4, no volumes", fourD("9 6 5 0", "domain domain domain time"), "expected positive sizes"},
      {"dimension 4, too many", fourD("1048576 1048576 512 65536", "domain domain domain list"),
       "2^62 bytes"},
      {"dimension text", replaced("dimension: 3", "dimension: three"), "field 'dimension'"},
      {"unknown encoding", replaced("encoding: raw", "encoding: lzma"), "unknown encoding 'lzma'"},
      {"unsupported encoding", replaced("encoding: raw", "encoding: ascii"), "unsupported encoding 'ascii'"},
      {"unsupported type", replaced("type: uint16", "type: int64"), "unsupported type 'int64'"},
      {"plain char", replaced("type: uint16", "type: char"), "unknown type 'char'"},
      {"not a NRRD spelling", replaced("type: uint16", "type: float64"), "unknown type 'float64'"},
      {"unknown type", replaced("type: uint16", "type: quaternion"), "unknown type 'quaternion'"},
      {"bad endian", replaced("endian: little", "endian: middle"), "field 'endian'"},
      {"bad spacings", good + "spacings: 1 x 1\n", "field 'spacings'"},
      {"zero spacing", good + "spacings: 1 0 1\n", "field 'spacings'"},
      {"bad directions", good + "space directions: (1,0,0) (0,1,0)\n", "field 'space directions'"},
      {"unclosed direction", good + "space directions: (1,0,0) (0,1,0) (0,0,1\n", "field 'space directions'"},
      {"zero direction", good + "space directions: (1,0,0) (0,0,0) (0,0,1)\n", "field 'space directions'"},
      {"bad byte skip", good + "byte skip: -2\n", "field 'byte skip'"},
      {"bad line skip", good + "line skip: many\n", "field 'line skip'"},
      {"gzip byte skip -1", replaced("encoding: raw", "encoding: gzip") + "byte skip: -1\n", "'byte skip'"},
      {"data file list", good + "data file: LIST\n", "field 'data file'"},
      {"data file format", good + "data file: slice%03d.raw 0 9 1\n", "field 'data file'"},
      {"duplicate field", good + "type: uint8\n", "given more than once"},
      {"not a field", good + "this is not a field\n", "line 10"},
  };
  for (const BadHeader& c : cases) {
    try {
      parseNrrdHeader(c.header, "/some/dir/bad.nrrd");
      ADD_FAILURE() << c.what << ": no error";
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("/some/dir/bad.nrrd"), std::string::npos) << c.what << ": " << message;
      EXPECT_NE(message.find(c.expected), std::string::npos) << c.what << ": " << message;
    }
  }
}

TEST(SourceNrrd, BadFilesNameTheFile) {
  TempDir dir;
  const auto values = samplePattern<uint16_t>(9 * 6 * 5);
  const std::string data = bytesOf(values, false);

  const std::string truncated = dir.file("truncated.nrrd");
  writeFile(truncated, headerFor("uint16", "raw") + "\n" + data.substr(0, data.size() - 1));
  std::string message = errorOf(truncated);
  EXPECT_NE(message.find(truncated), std::string::npos) << message;
  EXPECT_NE(message.find("truncated"), std::string::npos) << message;

  const std::string noBlank = dir.file("noblank.nrrd");
  writeFile(noBlank, headerFor("uint16", "raw"));
  message = errorOf(noBlank);
  EXPECT_NE(message.find(noBlank), std::string::npos) << message;
  EXPECT_NE(message.find("blank line"), std::string::npos) << message;

  const std::string missingData = dir.file("missing.nhdr");
  writeFile(missingData, headerFor("uint16", "raw", "data file: nothere.raw\n"));
  message = errorOf(missingData);
  EXPECT_NE(message.find(dir.file("nothere.raw")), std::string::npos) << message;

  const std::string lineSkip = dir.file("lineskip.nhdr");
  writeFile(dir.file("oneline.raw"), "only one line\n");
  writeFile(lineSkip, headerFor("uint16", "raw", "line skip: 5\ndata file: oneline.raw\n"));
  message = errorOf(lineSkip);
  EXPECT_NE(message.find(dir.file("oneline.raw")), std::string::npos) << message;
  EXPECT_NE(message.find("line skip"), std::string::npos) << message;

  // Gzip problems appear while reading, and name the data file.
  const std::string gz = gzipOf(data);
  const std::string shortGz = dir.file("short.nrrd");
  writeFile(shortGz, headerFor("uint16", "gzip") + "\n" + gz.substr(0, gz.size() / 2));
  auto shortSource = openVolumeSource(shortGz);
  std::vector<uint16_t> all(values.size());
  try {
    shortSource->readSlab(0, 5, std::as_writable_bytes(std::span(all)));
    ADD_FAILURE() << "truncated gzip read without error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(shortGz), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
  }
  std::string corruptBytes = gz;
  for (size_t i = 20; i < corruptBytes.size() - 10; i += 7) corruptBytes[i] = char(~corruptBytes[i]);
  const std::string corrupt = dir.file("corrupt.nrrd");
  writeFile(corrupt, headerFor("uint16", "gzip") + "\n" + corruptBytes);
  auto corruptSource = openVolumeSource(corrupt);
  try {
    corruptSource->readSlab(0, 5, std::as_writable_bytes(std::span(all)));
    ADD_FAILURE() << "corrupt gzip read without error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(corrupt), std::string::npos) << e.what();
  }
  // Every sample there, but the member's trailer (CRC32 and length, its last 8 bytes) cut off, or its CRC
  // wrong: the file is damaged, though the samples decompress.
  const std::string noTrailer = dir.file("notrailer.nrrd");
  writeFile(noTrailer, headerFor("uint16", "gzip") + "\n" + gz.substr(0, gz.size() - 8));
  std::string badCrcBytes = gz;
  badCrcBytes[gz.size() - 8] = char(~badCrcBytes[gz.size() - 8]);
  const std::string badCrc = dir.file("badcrc.nrrd");
  writeFile(badCrc, headerFor("uint16", "gzip") + "\n" + badCrcBytes);
  for (const std::string& damaged : {noTrailer, badCrc}) {
    try {
      openVolumeSource(damaged)->readSlab(0, 5, std::as_writable_bytes(std::span(all)));
      ADD_FAILURE() << damaged << " read without error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(damaged), std::string::npos) << e.what();
    }
  }
  // A header longer than what is read as one (its data file's name could be cut to another file's).
  const std::string longHeader = dir.file("long.nhdr");
  writeFile(longHeader, headerFor("uint16", "raw", "") + std::string(kMaxNrrdHeaderBytes, '#') +
                            "\ndata file: vol.raw\n");
  message = errorOf(longHeader);
  EXPECT_NE(message.find("longer than the 1048576 bytes read as a header"), std::string::npos) << message;
  // Dims and type come from the header, not from options.
  SourceOptions options;
  options.dims = glm::u32vec3(1, 2, 3);
  EXPECT_THROW(openVolumeSource(truncated, options), Error);
}

}  // namespace
}  // namespace ropecast
