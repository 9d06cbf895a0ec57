// Tests of the Zarr VolumeSource, its metadata parser and the array-axes rule it shares with HDF5: every
// sample type and compressor, edge chunks, chunks not stored, F order, big-endian samples and nested chunk
// keys, slabs across chunk layers and out of order, OME-Zarr images (named axes, scales), groups, and each
// refusal naming the folder or chunk file and why.
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "store/array_axes.h"
#include "store/source_zarr.h"
#include "store/volume_source.h"
#include "store/zarr_metadata.h"
#include "tests/common/temp_dir.h"
#include "tests/store/store_test_util.h"
#include "tests/store/testutil_zarr.h"

namespace ropecast {
namespace {

namespace fs = std::filesystem;
using testing::errorOf;
using testing::expectVolume;
using testing::readSlab;
using testing::samplePattern;
using testing::TempDir;
using testing::writeFile;
using testing::writeZarrArray;
using testing::writeZarrV3Array;
using testing::ZarrArraySpec;

// z, y, x = 5, 6, 9 in chunks of 2 x 4 x 4: edge chunks along every axis.
ZarrArraySpec smallSpec(const std::string& dtype, const std::string& compressor) {
  ZarrArraySpec spec;
  spec.shape = {5, 6, 9};
  spec.chunks = {2, 4, 4};
  spec.dtype = dtype;
  spec.compressor = compressor;
  return spec;
}

TEST(SourceZarr, EveryCompressorAndSampleType) {
  TempDir dir;
  const auto values = samplePattern<uint16_t>(9 * 6 * 5);
  for (const std::string compressor : {"none", "blosc", "zlib", "gzip", "zstd", "lz4", "lzma", "bz2"}) {
    const fs::path folder = dir / (compressor + ".zarr");
    writeZarrArray(folder, smallSpec("<u2", compressor), values.data(), 2);
    expectVolume(*openVolumeSource(folder.string()),
                 {{9, 6, 5}, SampleType::UInt16, {1.0, 1.0, 1.0}, "zarr:" + folder.string()}, values);
  }
  auto check = [&](auto tag, const std::string& dtype, SampleType type) {
    using T = decltype(tag);
    const auto typed = samplePattern<T>(9 * 6 * 5);
    const fs::path folder = dir / ("type" + dtype.substr(1) + ".zarr");
    writeZarrArray(folder, smallSpec(dtype, "blosc"), typed.data(), sizeof(T));
    expectVolume(*openVolumeSource(folder.string()),
                 {{9, 6, 5}, type, {1.0, 1.0, 1.0}, "zarr:" + folder.string()}, typed);
  };
  check(uint8_t{}, "|u1", SampleType::UInt8);
  check(int8_t{}, "|i1", SampleType::Int8);
  check(int16_t{}, "<i2", SampleType::Int16);
  check(uint32_t{}, "<u4", SampleType::UInt32);
  check(int32_t{}, "<i4", SampleType::Int32);
  check(float{}, "<f4", SampleType::Float32);
  check(double{}, "<f8", SampleType::Float64);
}

// Arrays numcodecs wrote (tests/data/zarr/write_fixtures.py) with the compressors ropecast decodes itself:
// LZ4 with numcodecs' size header, LZMA as .xz and as legacy .lzma, bzip2. Then their refusals: a chunk
// cut short, and LZMA's raw format, whose filters only the metadata would give.
TEST(SourceZarr, NumcodecsCompressorsAsNumcodecsWritesThem) {
  std::vector<uint16_t> expected;
  for (uint16_t z = 0; z < 5; ++z)
    for (uint16_t y = 0; y < 7; ++y)
      for (uint16_t x = 0; x < 9; ++x) expected.push_back(uint16_t(x + 10 * y + 100 * z));
  const fs::path data = fs::path(ROPECAST_TEST_DATA_DIR) / "zarr";
  for (const std::string name : {"lz4", "lzma", "lzma_alone", "bz2"}) {
    const fs::path folder = data / ("numcodecs_" + name + ".zarr");
    expectVolume(*openVolumeSource(folder.string()),
                 {{9, 7, 5}, SampleType::UInt16, {1.0, 1.0, 1.0}, "zarr:" + folder.string()}, expected);
  }

  TempDir dir;
  for (const std::string name : {"lz4", "lzma", "bz2"}) {
    const fs::path folder = dir / ("damaged_" + name + ".zarr");
    fs::copy(data / ("numcodecs_" + name + ".zarr"), folder);
    const fs::path chunk = folder / "1.0.1";
    std::string bytes = test::readBytes(chunk);
    writeFile(chunk, bytes.substr(0, bytes.size() / 2));  // LZ4 keeps no checksum: a changed byte may pass
    std::string message;
    try {
      readSlab<uint16_t>(*openVolumeSource(folder.string()), 0, 5);
    } catch (const Error& e) {
      message = e.what();
    }
    EXPECT_NE(message.find(chunk.string()), std::string::npos) << name << ": " << message;
    EXPECT_NE(message.find("is damaged (" + name + ":"), std::string::npos) << message;
  }
  const fs::path raw = dir / "raw_lzma.zarr";
  fs::copy(data / "numcodecs_lzma.zarr", raw);
  std::string metadata = test::readBytes(raw / ".zarray");
  const std::string xz = "\"format\": 1";
  metadata.replace(metadata.find(xz), xz.size(), "\"format\": 3");
  writeFile(raw / ".zarray", metadata);
  EXPECT_NE(errorOf(raw.string()).find("compressor lzma of format 3 is not read"), std::string::npos)
      << errorOf(raw.string());
}

// A plain array of two volumes along a fourth axis, which it does not name: refused, asking for --axes; read
// with --axes tzyx, its second time point; an NRRD takes no --axes.
TEST(SourceZarr, AxesNamedOnTheCommandLine) {
  TempDir dir;
  const auto values = samplePattern<uint16_t>(2 * 5 * 6 * 9);
  ZarrArraySpec spec = smallSpec("<u2", "zstd");
  spec.shape = {2, 5, 6, 9};
  spec.chunks = {1, 2, 4, 4};
  const fs::path folder = dir / "series.zarr";
  writeZarrArray(folder, spec, values.data(), 2);
  EXPECT_NE(errorOf(folder.string()).find("name them with --axes"), std::string::npos)
      << errorOf(folder.string());
  SourceOptions options;
  options.axes = "tzyx";
  options.timePoint = 1;
  const std::vector<uint16_t> second(values.begin() + 5 * 6 * 9, values.end());
  EXPECT_EQ(readSlab<uint16_t>(*openVolumeSource(folder.string(), options), 0, 5), second);

  const std::string nrrd = (dir / "a.nrrd").string();
  writeFile(nrrd,
            "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n" + std::string(8, '\0'));
  EXPECT_NE(errorOf(nrrd, options)
                .find(nrrd + ": --axes applies to HDF5 datasets, Zarr arrays and N5 datasets only"),
            std::string::npos)
      << errorOf(nrrd, options);
}

TEST(SourceZarr, BigEndianFortranOrderNestedKeysAndChunksNotStored) {
  TempDir dir;
  const auto values = samplePattern<int16_t>(9 * 6 * 5);
  ZarrArraySpec spec = smallSpec(">i2", "zlib");
  spec.fortranOrder = true;
  spec.separator = '/';
  spec.fill = -7;
  spec.unwritten = {{1, 0, 1}, {2, 1, 2}};  // z 2..3, y 0..3, x 4..7; and z 4, y 4..5, x 8
  const fs::path folder = dir / "nested.zarr";
  writeZarrArray(folder, spec, values.data(), 2);
  ASSERT_TRUE(fs::exists(folder / "0" / "1" / "2"));
  std::vector<int16_t> expected = values;
  for (uint32_t z = 0; z < 5; ++z)
    for (uint32_t y = 0; y < 6; ++y)
      for (uint32_t x = 0; x < 9; ++x)
        if ((z / 2 == 1 && y / 4 == 0 && x / 4 == 1) || (z / 2 == 2 && y / 4 == 1 && x / 4 == 2))
          expected[(z * 6 + y) * 9 + x] = -7;
  const auto source = openVolumeSource(folder.string());
  expectVolume(*source, {{9, 6, 5}, SampleType::Int16, {1.0, 1.0, 1.0}, "zarr:" + folder.string()}, expected);
  // Slabs within a layer, across two, and out of order; and the same with room for one slice at a time (each
  // chunk decoded again per slice).
  const size_t slice = 9 * 6;
  const auto banded = openZarrSource(folder.string(), {}, slice * 2);
  expectVolume(*banded, {{9, 6, 5}, SampleType::Int16, {1.0, 1.0, 1.0}, "zarr:" + folder.string()}, expected);
  for (const auto& [z0, count] :
       std::vector<std::pair<uint32_t, uint32_t>>{{3, 1}, {1, 3}, {0, 1}, {4, 1}, {2, 2}}) {
    for (VolumeSource* s : {source.get(), banded.get()}) {
      const auto got = readSlab<int16_t>(*s, z0, count);
      EXPECT_TRUE(std::equal(got.begin(), got.end(), expected.begin() + z0 * slice)) << z0 << "+" << count;
    }
  }
}

TEST(SourceZarr, OmeZarrImagesReadTheirFirstDatasetWithNamedAxesAndScale) {
  TempDir dir;
  const auto values = samplePattern<uint16_t>(9 * 6 * 5);
  const fs::path image = dir / "image.ome.zarr";
  ZarrArraySpec spec;
  spec.shape = {1, 1, 5, 6, 9};
  spec.chunks = {1, 1, 3, 3, 3};
  spec.compressor = "blosc";
  writeZarrArray(image / "0", spec, values.data(), 2);
  ZarrArraySpec coarse = spec;
  coarse.shape = {1, 1, 3, 3, 5};
  const std::vector<uint16_t> ones(3 * 3 * 5, 1);
  writeZarrArray(image / "1", coarse, ones.data(), 2);
  writeFile(image / ".zgroup", R"({"zarr_format": 2})");
  writeFile(image / ".zattrs", R"({"multiscales": [{"version": "0.4", "name": "cells",
    "axes": [{"name": "t", "type": "time"}, {"name": "c", "type": "channel"},
             {"name": "z", "type": "space", "unit": "micrometer"}, {"name": "y", "type": "space"},
             {"name": "x", "type": "space"}],
    "datasets": [{"path": "0", "coordinateTransformations": [{"type": "scale", "scale": [1, 1, 1, 0.25, 0.125]},
                                                             {"type": "translation", "translation": [0, 0, 5, 1, -3]}]},
                 {"path": "1", "coordinateTransformations": [{"type": "scale", "scale": [1, 1, 2, 0.5, 0.25]}]}],
    "coordinateTransformations": [{"type": "scale", "scale": [1, 1, 2, 2, 2]},
                                  {"type": "translation", "translation": [0, 0, 10, 20, 30]}]}]})");
  expectVolume(*openVolumeSource(image.string()),
               {{9, 6, 5}, SampleType::UInt16, {0.25, 0.5, 2.0}, "zarr:" + (image / "0").string()}, values);
  // The first sample: the dataset's translation, scaled and moved by the image's (x -3 * 2 + 30, ...).
  EXPECT_EQ(openVolumeSource(image.string())->info().origin, glm::dvec3(24.0, 22.0, 20.0));
  // A level named by its folder: its scale in the image, the level's times the image's, and the image's
  // place.
  const auto level = openVolumeSource((image / "1").string());
  EXPECT_EQ(level->info().dims, glm::u32vec3(5, 3, 3));
  EXPECT_EQ(level->info().spacing, glm::dvec3(0.5, 1.0, 4.0));
  EXPECT_EQ(level->info().origin, glm::dvec3(30.0, 20.0, 10.0));
  EXPECT_EQ(openVolumeSource((image / "1").string() + "/")->info().spacing, glm::dvec3(0.5, 1.0, 4.0));

  // Axes named in another order than t, c, z, y, x: x, y, z by name, wherever they lie; of 2 channels the
  // first, with a warning, or the one --channel picks.
  const fs::path swapped = dir / "czyx.zarr";
  ZarrArraySpec two = spec;
  two.shape = {2, 5, 6, 9};
  two.chunks = {1, 5, 6, 9};
  std::vector<uint16_t> channels(values);
  for (const uint16_t v : values) channels.push_back(uint16_t(v + 1));
  writeZarrArray(swapped / "0", two, channels.data(), 2);
  writeFile(swapped / ".zattrs",
            R"({"multiscales": [{"axes": ["c", "z", "y", "x"], "datasets": [{"path": "0"}]}]})");
  const auto first = openVolumeSource(swapped.string());
  EXPECT_EQ(readSlab<uint16_t>(*first, 0, 5), values);
  ASSERT_EQ(first->info().notes.size(), 1u);
  EXPECT_EQ(first->info().notes[0],
            "OME-Zarr image " + swapped.string() +
                " holds 2 channels: channel 0 of 2 is read; --channel C (0 to 1) picks "
                "another");
  SourceOptions second;
  second.channel = 1;
  const auto picked = openVolumeSource(swapped.string(), second);
  EXPECT_EQ(readSlab<uint16_t>(*picked, 0, 5), std::vector<uint16_t>(channels.begin() + 270, channels.end()));
  EXPECT_EQ(picked->info().description, "zarr:" + (swapped / "0").string() + " (channel 1 of 2)");
  second.timePoint = 1;
  EXPECT_EQ(errorOf(swapped.string(), second),
            "--time 1: OME-Zarr image " + swapped.string() + " holds 1 time point (--time 0 alone)");
  // The omero block's labels name the channels, where it labels every one.
  second.timePoint.reset();
  writeFile(swapped / ".zattrs",
            R"({"multiscales": [{"axes": ["c", "z", "y", "x"], "datasets": [{"path": "0"}]}],
                "omero": {"channels": [{"label": "DAPI", "color": "0000FF"}, {"label": "GFP"}]}})");
  EXPECT_EQ(openVolumeSource(swapped.string(), second)->info().description,
            "zarr:" + (swapped / "0").string() + " (channel 1 of 2: 'GFP')");
  writeFile(swapped / ".zattrs",
            R"({"multiscales": [{"axes": ["c", "z", "y", "x"], "datasets": [{"path": "0"}]}],
                "omero": {"channels": [{"label": "DAPI"}, {"color": "00FF00"}]}})");
  EXPECT_EQ(openVolumeSource(swapped.string(), second)->info().description,
            "zarr:" + (swapped / "0").string() + " (channel 1 of 2)");

  // Another axis longer than 1 is refused.
  const fs::path other = dir / "qzyx.zarr";
  writeZarrArray(other / "0", two, channels.data(), 2);
  writeFile(other / ".zattrs",
            R"({"multiscales": [{"axes": ["q", "z", "y", "x"], "datasets": [{"path": "0"}]}]})");
  const std::string refused = errorOf(other.string());
  for (const char* word : {"qzyx.zarr/0", "not a volume", "axis q has 2 entries", "named t (time) and c"})
    EXPECT_NE(refused.find(word), std::string::npos) << word << " in: " << refused;
}

// Time points of an OME-Zarr image, picked by --time and --channel: in v2 chunks of two time points (the
// picked one second in its chunk), and in v3 shards of two time points, inner chunks of one. Time point t,
// channel c holds the pattern plus 100 (2 t + c).
TEST(SourceZarr, TimePointsAndChannelsArePickedWithinChunksAndShards) {
  TempDir dir;
  const auto values = samplePattern<uint16_t>(9 * 6 * 5);
  std::vector<uint16_t> series;
  for (int t = 0; t < 3; ++t)
    for (int c = 0; c < 2; ++c)
      for (const uint16_t v : values) series.push_back(uint16_t(v + 100 * (2 * t + c)));
  const auto volumeOf = [&](int t, int c) {
    const auto begin = series.begin() + (2 * t + c) * 270;
    return std::vector<uint16_t>(begin, begin + 270);
  };
  const char* axes = R"("axes": [{"name": "t", "type": "time"}, {"name": "c", "type": "channel"},
      {"name": "z", "type": "space"}, {"name": "y", "type": "space"}, {"name": "x", "type": "space"}])";

  ZarrArraySpec spec = smallSpec("<u2", "zlib");
  spec.shape = {3, 2, 5, 6, 9};
  spec.chunks = {2, 2, 2, 4, 4};
  const fs::path v2 = dir / "v2.ome.zarr";
  writeZarrArray(v2 / "0", spec, series.data(), 2);
  writeFile(v2 / ".zattrs",
            std::string(R"({"multiscales": [{)") + axes + R"(, "datasets": [{"path": "0"}]}]})");

  spec.dtype = "uint16";
  spec.compressor = "zstd";
  spec.chunks = {2, 2, 4, 4, 8};
  testing::ZarrV3Options sharded;
  sharded.innerChunks = {1, 1, 2, 2, 4};
  const fs::path v3 = dir / "v3.ome.zarr";
  writeZarrV3Array(v3 / "s0", spec, sharded, series.data(), 2);
  writeFile(v3 / "zarr.json",
            std::string(R"({"zarr_format": 3, "node_type": "group", "attributes": {"ome": {"version": "0.5",
    "multiscales": [{)") +
                axes + R"(, "datasets": [{"path": "s0"}]}]}}})");

  for (const fs::path& image : {v2, v3}) {
    const auto first = openVolumeSource(image.string());
    EXPECT_EQ(readSlab<uint16_t>(*first, 0, 5), volumeOf(0, 0)) << image;
    ASSERT_EQ(first->info().notes.size(), 1u);
    EXPECT_NE(first->info().notes[0].find("holds 3 time points and 2 channels"), std::string::npos);
    for (const auto& [t, c] : std::vector<std::pair<uint32_t, uint32_t>>{{1, 1}, {2, 0}, {1, 0}, {2, 1}}) {
      SourceOptions options;
      options.timePoint = t;
      options.channel = c;
      const auto source = openVolumeSource(image.string(), options);
      EXPECT_EQ(readSlab<uint16_t>(*source, 0, 5), volumeOf(int(t), int(c)))
          << image << " t " << t << " c " << c;
      EXPECT_TRUE(source->info().notes.empty());
    }
  }
}

// zarr-python 3 writes numcodecs' compressors into v3 chains by numcodecs.zarr3's names; its filters are
// refused, naming them.
TEST(SourceZarr, V3ArraysWithNumcodecsCompressors) {
  TempDir dir;
  const auto values = samplePattern<uint16_t>(9 * 6 * 5);
  for (const std::string name : {"zlib", "gzip", "zstd", "blosc", "lz4", "lzma", "bz2"}) {
    const fs::path folder = dir / (name + ".zarr");
    writeZarrV3Array(folder, smallSpec("uint16", "numcodecs." + name), {}, values.data(), 2);
    expectVolume(*openVolumeSource(folder.string()),
                 {{9, 6, 5}, SampleType::UInt16, {1.0, 1.0, 1.0}, "zarr:" + folder.string()}, values);
  }
  const fs::path filtered = dir / "delta.zarr";
  writeZarrV3Array(filtered, smallSpec("uint16", "numcodecs.delta"), {}, values.data(), 2);
  EXPECT_NE(errorOf(filtered.string()).find("codec 'numcodecs.delta' is not read"), std::string::npos)
      << errorOf(filtered.string());
}

TEST(SourceZarr, V3ArraysShardedOrNotAndOmeZarr05Images) {
  TempDir dir;
  const auto values = samplePattern<int16_t>(9 * 6 * 5);
  ZarrArraySpec spec = smallSpec("int16", "zstd");
  testing::ZarrV3Options options;
  options.bigEndian = true;
  options.dimensionNames = {"z", "y", "x"};
  const fs::path plain = dir / "plain.zarr";
  writeZarrV3Array(plain, spec, options, values.data(), 2);
  ASSERT_TRUE(fs::exists(plain / "c" / "2" / "1" / "2"));
  expectVolume(*openVolumeSource(plain.string()),
               {{9, 6, 5}, SampleType::Int16, {1.0, 1.0, 1.0}, "zarr:" + plain.string()}, values);

  // Shards of 4 x 4 x 8 holding inner chunks of 2 x 2 x 4 (edge shards past the array's end), an inner chunk
  // and a shard not stored.
  spec.compressor = "blosc";
  spec.chunks = {4, 4, 8};
  spec.fill = -3;
  // Inner chunk (1, 0, 1): z 2..3, y 0..1, x 4..7; and the whole shard (1, 1, 1), whose part inside the
  // array is z 4, y 4..5, x 8.
  spec.unwritten = {{1, 0, 1}, {2, 2, 2}, {2, 2, 3}, {2, 3, 2}, {2, 3, 3},
                    {3, 2, 2}, {3, 2, 3}, {3, 3, 2}, {3, 3, 3}};
  testing::ZarrV3Options sharded;
  sharded.innerChunks = {2, 2, 4};
  const fs::path shards = dir / "sharded.zarr";
  writeZarrV3Array(shards, spec, sharded, values.data(), 2);
  ASSERT_FALSE(fs::exists(shards / "c" / "1" / "1" / "1"));
  std::vector<int16_t> expected = values;
  for (uint32_t z = 0; z < 5; ++z)
    for (uint32_t y = 0; y < 6; ++y)
      for (uint32_t x = 0; x < 9; ++x)
        if ((z / 2 == 1 && y / 2 == 0 && x / 4 == 1) || (z / 2 == 2 && y / 2 == 2 && x / 4 == 2))
          expected[(z * 6 + y) * 9 + x] = -3;
  expectVolume(*openVolumeSource(shards.string()),
               {{9, 6, 5}, SampleType::Int16, {1.0, 1.0, 1.0}, "zarr:" + shards.string()}, expected);
  const auto banded = openZarrSource(shards.string(), {}, 9 * 6 * 2);
  expectVolume(*banded, {{9, 6, 5}, SampleType::Int16, {1.0, 1.0, 1.0}, "zarr:" + shards.string()}, expected);

  // A damaged shard: refused, naming it.
  fs::resize_file(shards / "c" / "0" / "0" / "0", 30);
  try {
    const auto source = openVolumeSource(shards.string());
    readSlab<int16_t>(*source, 0, 1);
    ADD_FAILURE() << "a damaged shard read without error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("Zarr shard " + (shards / "c/0/0/0").string()), std::string::npos)
        << e.what();
  }

  // OME-NGFF 0.5: the image's metadata in its group's zarr.json.
  const fs::path image = dir / "image.ome.zarr";
  ZarrArraySpec five = smallSpec("int16", "gzip");
  five.shape = {1, 1, 5, 6, 9};
  five.chunks = {1, 1, 2, 4, 4};
  writeZarrV3Array(image / "s0", five, {}, values.data(), 2);
  writeFile(image / "zarr.json",
            R"({"zarr_format": 3, "node_type": "group", "attributes": {"ome": {"version": "0.5",
    "multiscales": [{"axes": [{"name": "t", "type": "time"}, {"name": "c", "type": "channel"},
      {"name": "z", "type": "space"}, {"name": "y", "type": "space"}, {"name": "x", "type": "space"}],
      "datasets": [{"path": "s0", "coordinateTransformations": [{"type": "scale", "scale": [1, 1, 3, 2, 0.5]}]}]}]}}})");
  expectVolume(*openVolumeSource(image.string()),
               {{9, 6, 5}, SampleType::Int16, {0.5, 2.0, 3.0}, "zarr:" + (image / "s0").string()}, values);

  // Dimension names that do not name z, y and x say nothing of the axes: chosen by length.
  const fs::path unnamed = dir / "unnamed.zarr";
  testing::ZarrV3Options other;
  other.dimensionNames = {"dim_0", "dim_1", "dim_2"};
  writeZarrV3Array(unnamed, smallSpec("int16", "none"), other, values.data(), 2);
  EXPECT_EQ(openVolumeSource(unnamed.string())->info().dims, glm::u32vec3(9, 6, 5));

  // A v3 group without an image lists its arrays.
  const fs::path group = dir / "group3.zarr";
  fs::create_directories(group);
  writeFile(group / "zarr.json", R"({"zarr_format": 3, "node_type": "group", "attributes": {}})");
  writeZarrV3Array(group / "labels", smallSpec("uint16", "none"), {}, values.data(), 2);
  const std::string refused = errorOf(group.string());
  EXPECT_NE(refused.find("give one of its arrays' folders: labels"), std::string::npos) << refused;
}

TEST(ZarrMetadata, FillValuesOrdersAndOmeVersions) {
  const std::string head = R"({"zarr_format": 2, "shape": [2, 3, 4], "chunks": [1, 3, 4], "dtype": ">f4", )";
  const ZarrArray a = parseZarrArray(head + R"("compressor": null, "fill_value": "NaN", "order": "F"})", "a");
  EXPECT_TRUE(std::isnan(a.fillValue));
  EXPECT_TRUE(a.fortranOrder);
  EXPECT_TRUE(a.bigEndian);
  EXPECT_EQ(a.type, SampleType::Float32);
  EXPECT_EQ(a.separator, '.');
  EXPECT_EQ(a.chunkSamples(), 12u);
  EXPECT_EQ(parseZarrArray(head + R"("compressor": null, "fill_value": null})", "b").fillValue, 0.0);
  EXPECT_EQ(
      parseZarrArray(head + R"("compressor": {"id": "zstd", "level": 3}, "fill_value": 5})", "c").codecs,
      std::vector<ZarrCodec>{ZarrCodec::Zstd});

  EXPECT_FALSE(parseOmeMultiscale(R"({"name": "no image"})", "x"));
  // 0.3: axes as names; 0.1: no axes.
  const auto v3 = parseOmeMultiscale(
      R"({"multiscales": [{"axes": ["T", "Z", "Y", "X"], "datasets": [{"path": "s0"}]}]})", "x");
  ASSERT_TRUE(v3);
  EXPECT_EQ(v3->datasetPath, "s0");
  EXPECT_EQ(v3->axisNames, (std::vector<std::string>{"t", "z", "y", "x"}));
  EXPECT_FALSE(v3->scale);
  EXPECT_FALSE(v3->translation);
  const auto v1 =
      parseOmeMultiscale(R"({"multiscales": [{"datasets": [{"path": "0"}, {"path": "1"}]}]})", "x");
  ASSERT_TRUE(v1);
  EXPECT_TRUE(v1->axisNames.empty());
  try {
    parseOmeMultiscale(R"({"multiscales": [{"datasets": []}]})", "img/.zattrs");
    ADD_FAILURE() << "no datasets accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("img/.zattrs"), std::string::npos) << e.what();
  }
}

TEST(ArrayAxes, LengthOneAxesFallAwayAroundZyx) {
  const auto zyx = [](std::vector<uint64_t> extent) {
    const ArrayAxes axes = volumeAxes(extent);
    return axes.problem.empty()
               ? std::to_string(axes.zyx[0]) + std::to_string(axes.zyx[1]) + std::to_string(axes.zyx[2])
               : axes.problem;
  };
  EXPECT_EQ(zyx({5, 6, 9}), "012");
  EXPECT_EQ(zyx({1, 6, 9}), "012");
  EXPECT_EQ(zyx({1, 1, 5, 6, 9}), "234");
  EXPECT_EQ(zyx({5, 6, 9, 1}), "012");
  EXPECT_EQ(zyx({1, 5, 1, 6, 9}), "134");
  EXPECT_EQ(zyx({1, 1, 1, 6, 9}), "234");
  EXPECT_EQ(zyx({9, 1, 1, 1}), "012");
  EXPECT_EQ(zyx({6, 9}), "it has 2 axes (6x9); a volume has three");
  EXPECT_NE(zyx({2, 5, 6, 9}).find("4 axes longer than 1"), std::string::npos);
  EXPECT_NE(zyx({2, 5, 6, 9}).find("--axes"), std::string::npos);

  // --axes: letters for an array that names none; refused for one that names its own, or of another count.
  const std::vector<uint64_t> fourAxes{3, 5, 6, 9};
  const ArrayAxes given = arrayAxesOf(fourAxes, {}, "czyx");
  EXPECT_EQ(given.zyx, (std::array<int, 3>{1, 2, 3}));
  EXPECT_EQ(given.channel, 0);
  EXPECT_EQ(given.time, -1);
  EXPECT_EQ(arrayAxesOf(fourAxes, {}, "zyxt").time, 3);
  EXPECT_EQ(arrayAxesOf(fourAxes, {"t", "z", "y", "x"}, "czyx").problem,
            "it names its axes itself (t, z, y, x); --axes is for arrays that do not");
  EXPECT_EQ(arrayAxesOf(fourAxes, {}, "tczyx").problem, "--axes tczyx names 5 axes; it has 4 (3x5x6x9)");
  EXPECT_EQ(arrayAxesOf(fourAxes, {"t", "z", "y", "x"}, "").time, 0);
  EXPECT_EQ(axisNamesOf("tqyx").problem, "'q' is not an axis: expected t, c, z, y or x for each");
  EXPECT_EQ(axisNamesOf("zyxz").problem, "'z' is named twice");
  EXPECT_EQ(axisNamesOf("tcyx").problem, "no axis is named z (z, y and x are needed)");
  EXPECT_TRUE(axisNamesOf("tczyx").problem.empty());
  EXPECT_NE(zyx({0, 6, 9}).find("empty"), std::string::npos);

  EXPECT_EQ(volumeAxesNamed(std::vector<uint64_t>{9, 6, 5}, {"x", "y", "z"}).zyx,
            (std::array<int, 3>{2, 1, 0}));
  EXPECT_NE(volumeAxesNamed(std::vector<uint64_t>{9, 6}, {"x", "y"}).problem.find("no axis named z"),
            std::string::npos);
  const ArrayAxes tczyx = volumeAxesNamed(std::vector<uint64_t>{3, 2, 5, 6, 9}, {"t", "c", "z", "y", "x"});
  EXPECT_EQ(tczyx.zyx, (std::array<int, 3>{2, 3, 4}));
  EXPECT_EQ(tczyx.time, 0);
  EXPECT_EQ(tczyx.channel, 1);
  EXPECT_TRUE(tczyx.problem.empty());
  const ArrayAxes named = volumeAxesNamed(std::vector<uint64_t>{5, 6, 9}, {"z", "y", "x"});
  EXPECT_EQ(named.time, -1);
  EXPECT_EQ(named.channel, -1);
  EXPECT_NE(volumeAxesNamed(std::vector<uint64_t>{3, 3, 5, 6, 9}, {"t", "t", "z", "y", "x"})
                .problem.find("axis t has 3 entries"),
            std::string::npos);
}

}  // namespace
}  // namespace ropecast
