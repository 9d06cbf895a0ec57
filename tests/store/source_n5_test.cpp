// Tests of the N5 VolumeSource and its metadata: datasets zarr-python's N5 store wrote (tests/data/n5), every
// compression and sample type as N5's Java implementation writes them (edge blocks cut, lz4-java's block
// stream, blocks that count their samples), blocks not stored, slabs in bands and out of order, groups and
// their multiscale datasets, the calibrations N5 writers leave, more than three axes, and each refusal naming
// the folder or block file and why.
#include <xxhash.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "store/n5_metadata.h"
#include "store/source_n5.h"
#include "store/volume_source.h"
#include "tests/common/temp_dir.h"
#include "tests/store/store_test_util.h"
#include "tests/store/testutil_zarr.h"

namespace ropecast {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using testing::compressedChunk;
using testing::errorOf;
using testing::expectVolume;
using testing::readSlab;
using testing::samplePattern;
using testing::TempDir;
using testing::writeFile;

// lz4-java's LZ4BlockOutputStream: blocks of at most `blockBytes`, each after its 21-byte header, then an
// empty block.
std::string lz4JavaBlocksOf(const std::string& raw, size_t blockBytes = 64) {
  std::string out;
  const auto header = [&](int method, uint32_t stored, uint32_t size, uint32_t checksum) {
    out += "LZ4Block";
    out += char(method | 6);  // the compression level's bits: log2 of the block size, less 10
    for (const uint32_t v : {stored, size, checksum})
      for (int i = 0; i < 4; ++i) out += char(v >> (8 * i));
  };
  for (size_t at = 0; at < raw.size(); at += blockBytes) {
    const std::string block = raw.substr(at, blockBytes);
    const uint32_t checksum = XXH32(block.data(), block.size(), 0x9747b28c) & 0x0fffffff;
    std::string packed(size_t(LZ4_compressBound(int(block.size()))), '\0');
    packed.resize(
        size_t(LZ4_compress_default(block.data(), packed.data(), int(block.size()), int(packed.size()))));
    if (packed.size() >= block.size()) {  // incompressible: stored raw, as lz4-java does
      header(0x10, uint32_t(block.size()), uint32_t(block.size()), checksum);
      out += block;
    } else {
      header(0x20, uint32_t(packed.size()), uint32_t(block.size()), checksum);
      out += packed;
    }
  }
  header(0x10, 0, 0, 0);
  return out;
}

std::string n5Compressed(const std::string& compression, const std::string& raw, size_t typeSize) {
  if (compression == "raw") return raw;
  if (compression == "lz4") return lz4JavaBlocksOf(raw);
  if (compression == "xz") return compressedChunk("lzma", raw, typeSize);
  if (compression == "bzip2") return compressedChunk("bz2", raw, typeSize);
  return compressedChunk(compression, raw, typeSize);  // gzip, zlib, blosc, zstd
}

struct N5Spec {
  std::vector<uint64_t> shape, blockSize;  // slowest first (the attributes list them fastest first)
  std::string dataType = "uint16";
  std::string compression = "gzip";  // raw, gzip, zlib (gzip with useZlib), bzip2, xz, lz4, blosc, zstd
  bool edgeBlocksWhole = false;      // zarr-python's way; N5's Java implementation cuts them at the edge
  bool countSamples = false;         // mode 1 headers
  std::set<std::vector<uint64_t>> unwritten;  // block indices (slowest first) left out: zeros
  json attributes = json::object();           // more attributes
};

// Writes an N5 dataset of `values` (C order, native bytes of `typeSize`) to `folder`.
void writeN5Dataset(const fs::path& folder, const N5Spec& spec, const void* values, size_t typeSize) {
  const size_t rank = spec.shape.size();
  json a = spec.attributes;
  a["dimensions"] = json(std::vector<uint64_t>(spec.shape.rbegin(), spec.shape.rend()));
  a["blockSize"] = json(std::vector<uint64_t>(spec.blockSize.rbegin(), spec.blockSize.rend()));
  a["dataType"] = spec.dataType;
  a["compression"] = spec.compression == "zlib" ? json{{"type", "gzip"}, {"useZlib", true}}
                                                : json{{"type", spec.compression}};
  fs::create_directories(folder);
  writeFile(folder / "attributes.json", a.dump());
  std::vector<uint64_t> grid(rank), index(rank, 0);
  uint64_t blocks = 1;
  for (size_t d = 0; d < rank; ++d)
    blocks *= grid[d] = (spec.shape[d] + spec.blockSize[d] - 1) / spec.blockSize[d];
  for (uint64_t b = 0; b < blocks; ++b) {
    for (uint64_t d = rank, rest = b; d-- > 0;) index[d] = rest % grid[d], rest /= grid[d];
    if (spec.unwritten.count(index)) continue;
    std::vector<uint64_t> size(rank);
    uint64_t samples = 1;
    for (size_t d = 0; d < rank; ++d) {
      size[d] = spec.edgeBlocksWhole
                    ? spec.blockSize[d]
                    : std::min(spec.blockSize[d], spec.shape[d] - index[d] * spec.blockSize[d]);
      samples *= size[d];
    }
    std::string raw(samples * typeSize, '\0');  // big-endian samples, the first axis slowest
    std::vector<uint64_t> at(rank);
    for (uint64_t s = 0; s < samples; ++s) {
      bool inside = true;
      uint64_t offset = 0;
      for (uint64_t d = rank, rest = s; d-- > 0;) at[d] = rest % size[d], rest /= size[d];
      for (size_t d = 0; d < rank; ++d) {
        const uint64_t p = index[d] * spec.blockSize[d] + at[d];
        inside = inside && p < spec.shape[d];
        offset = offset * spec.shape[d] + p;
      }
      if (!inside) continue;
      for (size_t k = 0; k < typeSize; ++k)
        raw[s * typeSize + k] = static_cast<const char*>(values)[offset * typeSize + typeSize - 1 - k];
    }
    std::string block;
    const auto put = [&](uint64_t v, int bytes) {
      for (int i = bytes - 1; i >= 0; --i) block += char(v >> (8 * i));
    };
    put(spec.countSamples ? 1 : 0, 2);
    put(rank, 2);
    for (size_t d = rank; d-- > 0;) put(size[d], 4);
    if (spec.countSamples) put(samples, 4);
    block += n5Compressed(spec.compression, raw, typeSize);
    fs::path file = folder;
    for (size_t d = rank; d-- > 0;) file /= std::to_string(index[d]);
    fs::create_directories(file.parent_path());
    writeFile(file, block);
  }
}

// z, y, x = 5, 6, 9 in blocks of 2 x 4 x 4: edge blocks along every axis.
N5Spec smallN5Spec(const std::string& dataType, const std::string& compression) {
  N5Spec spec;
  spec.shape = {5, 6, 9};
  spec.blockSize = {2, 4, 4};
  spec.dataType = dataType;
  spec.compression = compression;
  return spec;
}

TEST(SourceN5, DatasetsZarrPythonWroteInEveryCompression) {
  std::vector<uint16_t> expected;
  for (uint16_t z = 0; z < 5; ++z)
    for (uint16_t y = 0; y < 7; ++y)
      for (uint16_t x = 0; x < 9; ++x) expected.push_back(uint16_t(x + 10 * y + 100 * z));
  const fs::path container = fs::path(ROPECAST_TEST_DATA_DIR) / "n5" / "zarr.n5";
  for (const std::string name : {"raw", "gzip", "zlib", "bzip2", "xz", "blosc", "zstd", "lz4"}) {
    const fs::path folder = container / name;
    expectVolume(*openVolumeSource(folder.string()),
                 {{9, 7, 5}, SampleType::UInt16, {1.0, 1.0, 1.0}, "n5:" + folder.string()}, expected);
  }
}

TEST(SourceN5, EveryCompressionAndSampleTypeAsJavaWritesThem) {
  TempDir dir;
  const auto values = samplePattern<uint16_t>(9 * 6 * 5);
  for (const std::string compression : {"raw", "gzip", "zlib", "bzip2", "xz", "lz4", "blosc", "zstd"})
    for (const bool whole : {false, true}) {
      const fs::path folder = dir / (compression + (whole ? "_whole" : "_cut"));
      N5Spec spec = smallN5Spec("uint16", compression);
      spec.edgeBlocksWhole = whole;
      spec.countSamples = compression == "gzip";
      writeN5Dataset(folder, spec, values.data(), 2);
      expectVolume(*openVolumeSource(folder.string()),
                   {{9, 6, 5}, SampleType::UInt16, {1.0, 1.0, 1.0}, "n5:" + folder.string()}, values);
    }
  auto check = [&](auto tag, const std::string& dataType, SampleType type) {
    using T = decltype(tag);
    const auto typed = samplePattern<T>(9 * 6 * 5);
    const fs::path folder = dir / dataType;
    writeN5Dataset(folder, smallN5Spec(dataType, "lz4"), typed.data(), sizeof(T));
    expectVolume(*openVolumeSource(folder.string()),
                 {{9, 6, 5}, type, {1.0, 1.0, 1.0}, "n5:" + folder.string()}, typed);
  };
  check(uint8_t{}, "uint8", SampleType::UInt8);
  check(int8_t{}, "int8", SampleType::Int8);
  check(int16_t{}, "int16", SampleType::Int16);
  check(uint32_t{}, "uint32", SampleType::UInt32);
  check(int32_t{}, "int32", SampleType::Int32);
  check(float{}, "float32", SampleType::Float32);
  check(double{}, "float64", SampleType::Float64);
}

TEST(SourceN5, BlocksNotStoredHoldZerosAndSlabsReadInBands) {
  TempDir dir;
  auto values = samplePattern<uint16_t>(9 * 6 * 5);
  N5Spec spec = smallN5Spec("uint16", "gzip");
  spec.unwritten = {{1, 0, 1}, {2, 1, 2}};  // z 2-3, y 0-3, x 4-7; z 4, y 4-5, x 8
  for (uint32_t z = 0; z < 5; ++z)
    for (uint32_t y = 0; y < 6; ++y)
      for (uint32_t x = 0; x < 9; ++x)
        if ((z / 2 == 1 && y / 4 == 0 && x / 4 == 1) || (z / 2 == 2 && y / 4 == 1 && x / 4 == 2))
          values[(z * 6 + y) * 9 + x] = 0;
  const fs::path folder = dir / "sparse.n5";
  writeN5Dataset(folder, spec, values.data(), 2);
  // A buffer of one slice: each block layer decoded in bands.
  const auto source = openN5Source(folder.string(), {}, 9 * 6 * 2);
  for (const uint32_t z0 : {3u, 0u, 4u, 1u}) {
    const std::vector<uint16_t> slab = readSlab<uint16_t>(*source, z0, 1);
    EXPECT_EQ(slab, std::vector<uint16_t>(values.begin() + z0 * 54, values.begin() + (z0 + 1) * 54)) << z0;
  }
  EXPECT_EQ(readSlab<uint16_t>(*source, 0, 5), values);
}

TEST(SourceN5, GroupsReadTheirFirstMultiscaleDatasetAndItsCalibration) {
  TempDir dir;
  const auto values = samplePattern<uint16_t>(9 * 6 * 5);
  // N5 Viewer's pyramid: s0, s1 below a group that states the pixel's size, x first.
  const fs::path viewer = dir / "viewer.n5";
  writeN5Dataset(viewer / "s0", smallN5Spec("uint16", "gzip"), values.data(), 2);
  writeFile(viewer / "attributes.json",
            R"({"n5": "2.5.1", "pixelResolution": {"unit": "um", "dimensions": [0.5, 0.25, 2.0]},
                "scales": [[1, 1, 1], [2, 2, 2]]})");
  expectVolume(*openVolumeSource(viewer.string()),
               {{9, 6, 5}, SampleType::UInt16, {0.5, 0.25, 2.0}, "n5:" + (viewer / "s0").string()}, values);
  // A level given alone: its group's full-resolution pixel times its downsamplingFactors (x, y, z).
  N5Spec level = smallN5Spec("uint16", "gzip");
  level.attributes = {{"downsamplingFactors", {2, 2, 1}}};
  writeN5Dataset(viewer / "s1", level, values.data(), 2);
  EXPECT_EQ(openVolumeSource((viewer / "s1").string())->info().spacing, glm::dvec3(1.0, 0.5, 2.0));
  EXPECT_EQ(openVolumeSource((viewer / "s1").string() + "/")->info().spacing, glm::dvec3(1.0, 0.5, 2.0));
  // COSEM's: `multiscales` names the first dataset; its transform names the axes, in C order.
  const fs::path cosem = dir / "cosem.n5";
  N5Spec named = smallN5Spec("uint16", "raw");
  named.attributes["transform"] = {{"axes", {"z", "y", "x"}},
                                   {"ordering", "C"},
                                   {"scale", {3.0, 2.0, 1.5}},
                                   {"translate", {30.0, 20.0, 10.0}},
                                   {"units", {"nm", "nm", "nm"}}};
  writeN5Dataset(cosem / "fibsem" / "s0", named, values.data(), 2);
  writeFile(cosem / "fibsem" / "attributes.json", R"({"multiscales": [{"datasets": [{"path": "s0"}]}]})");
  const auto cosemSource = openVolumeSource((cosem / "fibsem").string());
  EXPECT_EQ(cosemSource->info().spacing, glm::dvec3(1.5, 2.0, 3.0));
  EXPECT_EQ(cosemSource->info().origin, glm::dvec3(10.0, 20.0, 30.0));
  // Paintera's resolution and offset on the dataset, x first; --spacing overrides.
  const fs::path paintera = dir / "paintera";
  N5Spec painted = smallN5Spec("uint16", "raw");
  painted.attributes = {{"resolution", {4.0, 4.0, 40.0}}, {"offset", {8.0, 0.0, 80.0}}};
  writeN5Dataset(paintera, painted, values.data(), 2);
  const auto painteraSource = openVolumeSource(paintera.string());
  EXPECT_EQ(painteraSource->info().spacing, glm::dvec3(4.0, 4.0, 40.0));
  EXPECT_EQ(painteraSource->info().origin, glm::dvec3(8.0, 0.0, 80.0));
  SourceOptions spaced;
  spaced.spacing = glm::dvec3(1.0, 1.0, 2.0);
  EXPECT_EQ(openVolumeSource(paintera.string(), spaced)->info().spacing, glm::dvec3(1.0, 1.0, 2.0));
  // A calibration of another length than the axes is set aside with a note.
  const fs::path odd = dir / "odd";
  N5Spec oddSpec = smallN5Spec("uint16", "raw");
  oddSpec.attributes = {{"pixelResolution", {0.5, 0.5}}};
  writeN5Dataset(odd, oddSpec, values.data(), 2);
  const auto oddSource = openVolumeSource(odd.string());
  EXPECT_EQ(oddSource->info().spacing, glm::dvec3(1.0));
  ASSERT_EQ(oddSource->info().notes.size(), 1u);
  EXPECT_NE(oddSource->info().notes[0].find("its pixelResolution has 2 values for 3 axes"),
            std::string::npos);
  // A group of datasets that is no pyramid lists them.
  const fs::path plain = dir / "plain.n5";
  writeN5Dataset(plain / "raw", smallN5Spec("uint16", "raw"), values.data(), 2);
  writeN5Dataset(plain / "labels" / "cells", smallN5Spec("uint16", "raw"), values.data(), 2);
  writeFile(plain / "attributes.json", R"({"n5": "2.5.1"})");
  EXPECT_EQ(errorOf(plain.string()),
            plain.string() +
                ": an N5 group that is no multiscale image (no 'multiscales', no s0 dataset); give one "
                "of its datasets' folders: labels/cells, raw");
}

TEST(SourceN5, TimePointsAndChannelsAlongMoreAxes) {
  TempDir dir;
  // t, z, y, x = 2, 3, 4, 5 in blocks of 1 x 2 x 3 x 4.
  const auto values = samplePattern<uint16_t>(2 * 3 * 4 * 5);
  N5Spec spec;
  spec.shape = {2, 3, 4, 5};
  spec.blockSize = {1, 2, 3, 4};
  const fs::path folder = dir / "series.n5";
  writeN5Dataset(folder, spec, values.data(), 2);
  EXPECT_NE(errorOf(folder.string()).find("N5 dataset " + folder.string() + ": not a volume: "),
            std::string::npos)
      << errorOf(folder.string());
  SourceOptions options;
  options.axes = "tzyx";
  options.timePoint = 1;
  const auto source = openVolumeSource(folder.string(), options);
  EXPECT_EQ(source->info().dims, glm::u32vec3(5, 4, 3));
  EXPECT_EQ(readSlab<uint16_t>(*source, 0, 3), std::vector<uint16_t>(values.begin() + 60, values.end()));
  options.axes = "zyx";
  EXPECT_NE(errorOf(folder.string(), options).find("--axes zyx names 3 axes; it has 4"), std::string::npos)
      << errorOf(folder.string(), options);
}

// BigStitcher's N5 export: an XML beside an N5 container of setupS/timepointT/sL datasets.
TEST(SourceN5, ABigDataViewerXmlReadsItsViewFromItsN5Container) {
  TempDir dir;
  const auto first = samplePattern<uint16_t>(9 * 6 * 5);
  std::vector<uint16_t> last(first.rbegin(), first.rend());
  const fs::path container = dir / "dataset.n5";
  for (const std::string setup : {"0", "3"})
    for (const std::string timepoint : {"0", "1"}) {
      const bool isLast = setup == "3" && timepoint == "1";
      writeN5Dataset(container / ("setup" + setup) / ("timepoint" + timepoint) / "s0",
                     smallN5Spec("uint16", "gzip"), (isLast ? last : first).data(), 2);
    }
  const std::string xml = (dir / "dataset.xml").string();
  const auto writeXml = [&](const std::string& n5) {
    writeFile(xml, R"(<?xml version="1.0" encoding="UTF-8"?>
<SpimData version="0.2"><BasePath type="relative">.</BasePath><SequenceDescription>
<ImageLoader format="bdv.n5" version="1.0"><n5 type="relative">)" +
                       n5 + R"(</n5></ImageLoader>
<ViewSetups>
<ViewSetup><id>0</id><name>tile 0</name><voxelSize><unit>um</unit><size>0.5 0.5 2</size></voxelSize></ViewSetup>
<ViewSetup><id>3</id><name>tile 3</name><voxelSize><unit>um</unit><size>0.25 0.25 1</size></voxelSize></ViewSetup>
</ViewSetups><Timepoints type="range"><first>0</first><last>1</last></Timepoints>
</SequenceDescription></SpimData>)");
  };
  writeXml("dataset.n5");
  SourceOptions options;
  options.timePoint = 1;
  options.channel = 1;
  const auto source = openVolumeSource(xml, options);
  const fs::path view = container / "setup3" / "timepoint1" / "s0";
  EXPECT_EQ(source->info().spacing, glm::dvec3(0.25, 0.25, 1.0));
  EXPECT_EQ(source->info().description,
            "bdv:" + xml + " (n5:" + view.string() + ") (time point 1 of 2, view setup 1 of 2: 'tile 3')");
  EXPECT_EQ(readSlab<uint16_t>(*source, 0, 5), last);
  EXPECT_EQ(openVolumeSource(xml)->info().spacing, glm::dvec3(0.5, 0.5, 2.0));
  fs::remove_all(view);
  EXPECT_EQ(
      errorOf(xml, options),
      "BigDataViewer XML " + xml + ": its view (time point 1, setup 3) has no N5 dataset " + view.string());
  writeXml("");
  EXPECT_EQ(errorOf(xml), "BigDataViewer XML " + xml + ": its ImageLoader names no n5 container");
}

// Reads the whole volume of `folder`; the error's message, or "".
std::string n5ReadError(const fs::path& folder) {
  try {
    const auto source = openVolumeSource(folder.string());
    readSlab<uint16_t>(*source, 0, source->info().dims.z);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(SourceN5, DamagedBlocksAndAttributesNameTheFileAndWhy) {
  TempDir dir;
  const auto values = samplePattern<uint16_t>(9 * 6 * 5);
  const auto dataset = [&](const std::string& name, const std::string& compression) {
    const fs::path folder = dir / name;
    writeN5Dataset(folder, smallN5Spec("uint16", compression), values.data(), 2);
    return folder;
  };
  const auto bytesOf = [](const fs::path& file) {
    std::string bytes(fs::file_size(file), '\0');
    std::ifstream(file, std::ios::binary).read(bytes.data(), std::streamsize(bytes.size()));
    return bytes;
  };
  // A block whose header says fewer samples than its place in the dataset (0/0/0: 4 x 4 x 2).
  const fs::path shrunk = dataset("shrunk", "raw");
  std::string block = bytesOf(shrunk / "0/0/0");
  block[7] = 3;  // x: 3 samples
  writeFile(shrunk / "0/0/0", block);
  EXPECT_EQ(n5ReadError(shrunk),
            "N5 block " + (shrunk / "0/0/0").string() +
                ": holds 2x4x3 samples; expected 2x4x4 (the dataset's part there) up to 2x4x4 "
                "(its block size)");
  // Another number of axes.
  block = bytesOf(shrunk / "1/0/0");
  block[3] = 2;
  writeFile(shrunk / "1/0/0", block);
  writeFile(shrunk / "0/0/0", bytesOf(dataset("fine", "raw") / "0/0/0"));
  EXPECT_EQ(n5ReadError(shrunk),
            "N5 block " + (shrunk / "1/0/0").string() + ": has 2 axes; the dataset has 3");
  // Raw samples cut short; a gzip stream damaged; an lz4-java block whose checksum fails.
  const fs::path cut = dataset("cut", "raw");
  block = bytesOf(cut / "0/0/0");
  writeFile(cut / "0/0/0", block.substr(0, block.size() - 2));
  EXPECT_EQ(n5ReadError(cut),
            "N5 block " + (cut / "0/0/0").string() + ": holds 62 bytes of samples; expected 64");
  const fs::path gzip = dataset("gzip", "gzip");
  block = bytesOf(gzip / "0/0/0");
  block[block.size() - 6] ^= 0x40;  // the CRC
  writeFile(gzip / "0/0/0", block);
  EXPECT_NE(n5ReadError(gzip).find("N5 block " + (gzip / "0/0/0").string() +
                                   ": is damaged or of another size (gzip)"),
            std::string::npos)
      << n5ReadError(gzip);
  const fs::path lz4 = dataset("lz4", "lz4");
  const std::string lz4Block = bytesOf(lz4 / "0/0/0");
  block = lz4Block;
  block[16 + 17] ^= 0x01;  // the first block's checksum, after the N5 header of 16 bytes
  writeFile(lz4 / "0/0/0", block);
  EXPECT_EQ(n5ReadError(lz4), "N5 block " + (lz4 / "0/0/0").string() +
                                  ": is damaged (lz4: a block's checksum does not match its bytes)");
  writeFile(lz4 / "0/0/0", lz4Block.substr(0, lz4Block.size() - 21));  // no end block
  EXPECT_NE(n5ReadError(lz4).find("is damaged (lz4: cut short"), std::string::npos) << n5ReadError(lz4);
  // Attributes: 64-bit integers, an unknown compression, a block size of another length.
  const fs::path attributes = dataset("attributes", "raw");
  const auto refused = [&](const std::string& text, const std::string& message) {
    writeFile(attributes / "attributes.json", text);
    EXPECT_EQ(errorOf(attributes.string()), (attributes / "attributes.json").string() + ": " + message);
  };
  refused(
      R"({"dimensions": [9, 6, 5], "blockSize": [4, 4, 2], "dataType": "uint64"})",
      "'dataType' \"uint64\" is not read; read are 8-, 16- and 32-bit integers and 32- and 64-bit floats");
  refused(R"({"dimensions": [9, 6, 5], "blockSize": [4, 4, 2], "dataType": "uint16",
              "compression": {"type": "jpeg"}})",
          "compression 'jpeg' is not read (raw, gzip, bzip2, xz, lz4, blosc and zstd are)");
  refused(R"({"dimensions": [9, 6, 5], "blockSize": [4, 4], "dataType": "uint16"})",
          "'blockSize' has 2 axes and 'dimensions' 3");
  refused(R"({"dimensions": [9, 6, 5], "blockSize": [4, 0, 2], "dataType": "uint16"})",
          "'blockSize' has an axis of 0 samples");
  refused(R"({"dimensions": [9, 6, 5], "blockSize": [65536, 65536, 1], "dataType": "uint8"})",
          "blocks of more than 2 GiB are not read");
  refused("[1, 2]", "not a JSON object of attributes");
  refused(R"({"dimensions": [9, 6, 5], "blockSize": [4, 4, 2], "dataType": "uint16",
              "compression": {"type": "gzip", "useZlib": "yes"}})",
          "'compression' 'useZlib' must be true or false, got \"yes\"");
  refused(R"({"dimensions": [9, 6, 5], "blockSize": [4, 4, 2], "dataType": "uint16",
              "transform": {"axes": ["z", "y", "x"], "ordering": [1], "scale": [1, 1, 1]}})",
          "'transform' 'ordering' must be \"C\" or \"F\", got [1]");
  // N5 before 1.0 named its compression alone.
  writeFile(
      attributes / "attributes.json",
      R"({"dimensions": [9, 6, 5], "blockSize": [4, 4, 2], "dataType": "uint16", "compressionType": "raw"})");
  EXPECT_EQ(n5ReadError(attributes), "");
}

TEST(N5Metadata, BlockHeaders) {
  const auto bytes = [](std::initializer_list<int> values) {
    std::vector<std::byte> b;
    for (const int v : values) b.push_back(std::byte(v));
    return b;
  };
  N5BlockHeader header;
  EXPECT_EQ(parseN5BlockHeader(bytes({0, 0, 0, 2, 0, 0, 0, 5, 0, 0, 1, 0}), 2, header), "");
  EXPECT_EQ(header.size, (std::vector<uint64_t>{256, 5}));
  EXPECT_EQ(header.bytes, 12u);
  EXPECT_EQ(parseN5BlockHeader(bytes({0, 1, 0, 1, 0, 0, 0, 6, 0, 0, 0, 6}), 1, header), "");
  EXPECT_EQ(header.bytes, 12u);
  EXPECT_EQ(parseN5BlockHeader(bytes({0, 1, 0, 1, 0, 0, 0, 6, 0, 0, 0, 5}), 1, header),
            "holds 5 samples in a block of 6");
  EXPECT_EQ(parseN5BlockHeader(bytes({0, 2, 0, 1}), 1, header), "is an object block (mode 2), not samples");
  EXPECT_EQ(parseN5BlockHeader(bytes({0, 0, 0, 3, 0, 0}), 3, header),
            "is too short for a block header of 3 axes (6 bytes)");
  EXPECT_EQ(parseN5BlockHeader(bytes({0, 0}), 3, header), "is too short for a block header (2 bytes)");
}

}  // namespace
}  // namespace ropecast
