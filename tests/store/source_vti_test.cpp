// Tests of the VTK XML image data (.vti) header parser and source: the point data's active scalars read from
// appended raw and base64 data and inline base64 data, plain and in zlib, LZ4 and LZMA blocks (slabs across
// blocks, in any order), both byte orders and header word sizes, files VTK wrote with each compressor, and
// each unsupported or damaged file giving an error that names the file.
#include <lz4.h>
#include <lzma.h>
#include <zlib.h>

#include <bit>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "store/source_vti.h"
#include "store/volume_source.h"
#include "store/vti_header.h"
#include "tests/store/store_test_util.h"

namespace ropecast {
namespace {

using testing::errorOf;
using testing::expectHeadersRefused;
using testing::expectVolume;
using testing::fileBytes;
using testing::readSlab;
using testing::RefusedHeader;
using testing::samplePattern;
using testing::TempDir;
using testing::writeFile;

constexpr size_t kVtiSamples = 9 * 6 * 5;

std::string base64Of(const std::string& bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const size_t n = std::min<size_t>(3, bytes.size() - i);
    uint32_t bits = 0;
    for (size_t k = 0; k < 3; ++k) bits = bits << 8 | (k < n ? uint8_t(bytes[i + k]) : 0u);
    for (size_t k = 0; k < 4; ++k) out += k <= n ? kAlphabet[bits >> (18 - 6 * k) & 63] : '=';
  }
  return out;
}

// How a writer stores the array: inline or appended, base64 or raw, plain or in compressed blocks of
// `blockBytes`.
struct VtiLayout {
  bool inlined = false, base64 = false;
  VtiCompressor compressor = VtiCompressor::None;
  bool bigEndian = false, wideHeader = false;
  size_t blockBytes = 100;
};

// One block as VTK's compressors store it: a zlib stream, an LZ4 block, an xz stream.
std::string compressedBlock(const std::string& block, VtiCompressor compressor) {
  std::string out;
  if (compressor == VtiCompressor::ZLib) {
    uLongf size = compressBound(uLong(block.size()));
    out.resize(size);
    EXPECT_EQ(compress2(reinterpret_cast<Bytef*>(out.data()), &size,
                        reinterpret_cast<const Bytef*>(block.data()), uLong(block.size()), 6),
              Z_OK);
    out.resize(size);
  } else if (compressor == VtiCompressor::LZ4) {
    out.resize(size_t(LZ4_compressBound(int(block.size()))));
    const int size = LZ4_compress_default(block.data(), out.data(), int(block.size()), int(out.size()));
    EXPECT_GT(size, 0);
    out.resize(size_t(size));
  } else {
    out.resize(lzma_stream_buffer_bound(block.size()));
    size_t size = 0;
    EXPECT_EQ(
        lzma_easy_buffer_encode(0, LZMA_CHECK_CRC32, nullptr, reinterpret_cast<const uint8_t*>(block.data()),
                                block.size(), reinterpret_cast<uint8_t*>(out.data()), &size, out.size()),
        LZMA_OK);
    out.resize(size);
  }
  return out;
}

const char* compressorAttribute(VtiCompressor compressor) {
  switch (compressor) {
    case VtiCompressor::ZLib:
      return " compressor=\"vtkZLibDataCompressor\"";
    case VtiCompressor::LZ4:
      return " compressor=\"vtkLZ4DataCompressor\"";
    case VtiCompressor::LZMA:
      return " compressor=\"vtkLZMADataCompressor\"";
    case VtiCompressor::None:
      break;
  }
  return "";
}

// `value` as a header word of the layout.
std::string word(uint64_t value, const VtiLayout& layout) {
  std::string bytes(layout.wideHeader ? 8 : 4, '\0');
  for (size_t i = 0; i < bytes.size(); ++i)
    bytes[layout.bigEndian ? bytes.size() - 1 - i : i] = char(value >> (8 * i));
  return bytes;
}

// The data as VTK's writer encodes it: a byte count and the samples in one run, or a compression header and
// the blocks in a run of their own (each run base64-encoded apart when base64).
std::string encodedData(const std::string& samples, const VtiLayout& layout) {
  const auto encode = [&](const std::string& run) { return layout.base64 ? base64Of(run) : run; };
  if (layout.compressor == VtiCompressor::None) return encode(word(samples.size(), layout) + samples);
  std::string header, blocks;
  const size_t count = (samples.size() + layout.blockBytes - 1) / layout.blockBytes;
  header += word(count, layout) + word(layout.blockBytes, layout) +
            word(samples.size() % layout.blockBytes, layout);
  for (size_t b = 0; b < count; ++b) {
    const std::string compressed =
        compressedBlock(samples.substr(b * layout.blockBytes, layout.blockBytes), layout.compressor);
    header += word(compressed.size(), layout);
    blocks += compressed;
  }
  return encode(header) + encode(blocks);
}

// A .vti of a 9x6x5 volume whose point data holds a float array "other" first and then `values` as
// "density", the active scalars.
template <typename T>
std::string vtiFile(const std::string& type, const std::vector<T>& values, const VtiLayout& layout) {
  const std::string other = encodedData(std::string(kVtiSamples * 4, 'o'), layout);
  const std::string data = encodedData(fileBytes(values, layout.bigEndian), layout);
  const auto array = [&](const std::string& name, const std::string& arrayType, const std::string& encoded,
                         size_t offset) {
    return "<DataArray type=\"" + arrayType + "\" Name=\"" + name + "\" format=\"" +
           (layout.inlined ? "binary\">\n          " + encoded + "\n        </DataArray>\n"
                           : "appended\" offset=\"" + std::to_string(offset) + "\"/>\n");
  };
  std::string xml =
      std::string("<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"") +
      (layout.bigEndian ? "BigEndian" : "LittleEndian") + "\" header_type=\"" +
      (layout.wideHeader ? "UInt64" : "UInt32") + "\"" + compressorAttribute(layout.compressor) +
      ">\n  <ImageData WholeExtent=\"-4 4 10 15 0 4\" Origin=\"0 0 0\" Spacing=\"0.5 0.75 2\">\n"
      "    <Piece Extent=\"-4 4 10 15 0 4\">\n      <PointData Scalars=\"density\">\n        " +
      array("other", "Float32", other, 0) + "        " + array("density", type, data, other.size()) +
      "      </PointData>\n      <CellData>\n      </CellData>\n    </Piece>\n  </ImageData>\n";
  if (!layout.inlined)
    xml += std::string("  <AppendedData encoding=\"") + (layout.base64 ? "base64" : "raw") + "\">\n   _" +
           other + data + "\n  </AppendedData>\n";
  return xml + "</VTKFile>\n";
}

TEST(SourceVti, EveryLayoutAWriterLeaves) {
  TempDir dir;
  const auto values = samplePattern<int16_t>(kVtiSamples);
  int file = 0;
  for (const bool inlined : {false, true})
    for (const bool base64 : {false, true})
      for (const VtiCompressor compressor :
           {VtiCompressor::None, VtiCompressor::ZLib, VtiCompressor::LZ4, VtiCompressor::LZMA})
        for (const bool bigEndian : {false, true})
          for (const bool wideHeader : {false, true}) {
            if (inlined && !base64) continue;  // inline binary data is base64
            const VtiLayout layout{inlined, base64, compressor, bigEndian, wideHeader};
            const std::string path = dir.file("v" + std::to_string(file++) + ".vti");
            writeFile(path, vtiFile("Int16", values, layout));
            SCOPED_TRACE(path + (inlined ? " inline" : " appended") + (base64 ? " base64" : " raw") +
                         compressorAttribute(compressor) + (bigEndian ? " big-endian" : "") +
                         (wideHeader ? " UInt64" : ""));
            auto source = openVolumeSource(path);
            expectVolume(*source,
                         {{9, 6, 5}, SampleType::Int16, {0.5, 0.75, 2.0}, "vti:" + path + " (density)"},
                         values);
            // Slabs out of order, across blocks of 100 bytes (a slice is 108).
            for (const uint32_t z : {3u, 1u, 4u, 0u, 2u}) {
              const auto slab = readSlab<int16_t>(*source, z, 1);
              EXPECT_TRUE(std::equal(slab.begin(), slab.end(), values.begin() + z * 54)) << "slice " << z;
            }
          }
}

// An array of 3 components per point (a vector field, VTK's interleaved tuples), appended in zlib blocks or
// inline in base64, big-endian: component 0 by default, with a warning; --channel picks another.
// Files VTK's own writer made (tests/data/vti/write_fixtures.py), one per compressor: the LZ4 one in blocks
// of 128 bytes, raw; the others in one block each, base64.
TEST(SourceVti, FilesVtkWroteWithEachCompressor) {
  std::vector<double> expected;
  for (uint32_t z = 0; z < 5; ++z)
    for (uint32_t y = 0; y < 7; ++y)
      for (uint32_t x = 0; x < 9; ++x) expected.push_back(x + 10.0 * y + 100.0 * z);
  for (const std::string name : {"vtk_zlib_uint16", "vtk_lz4_uint16_blocks", "vtk_lzma_float32"}) {
    SCOPED_TRACE(name);
    auto source = openVolumeSource(std::string(ROPECAST_TEST_DATA_DIR) + "/vti/" + name + ".vti");
    ASSERT_EQ(source->info().dims, glm::u32vec3(9, 7, 5));
    std::vector<double> got;
    if (source->info().type == SampleType::UInt16) {
      for (const uint16_t v : readSlab<uint16_t>(*source, 0, 5)) got.push_back(v);
    } else {
      ASSERT_EQ(source->info().type, SampleType::Float32);
      for (const float v : readSlab<float>(*source, 0, 5)) got.push_back(v);
    }
    EXPECT_EQ(got, expected);
  }
}

TEST(SourceVti, ComponentsArePickedByChannel) {
  TempDir dir;
  const auto tuples = samplePattern<float>(kVtiSamples * 3);
  const auto componentOf = [&](size_t c) {
    std::vector<float> values;
    for (size_t i = c; i < tuples.size(); i += 3) values.push_back(tuples[i]);
    return values;
  };
  for (const VtiLayout& layout :
       {VtiLayout{.compressor = VtiCompressor::ZLib, .bigEndian = true}, VtiLayout{true, true}}) {
    std::string xml = vtiFile("Float32", tuples, layout);
    const size_t at = xml.find("Name=\"density\"");
    ASSERT_NE(at, std::string::npos);
    xml.insert(at, "NumberOfComponents=\"3\" ");
    const std::string path = dir.file(layout.inlined ? "inline.vti" : "appended.vti");
    writeFile(path, xml);
    const auto first = openVolumeSource(path);
    EXPECT_EQ(first->info().dims, glm::u32vec3(9, 6, 5));
    EXPECT_EQ(readSlab<float>(*first, 0, 5), componentOf(0)) << path;
    ASSERT_EQ(first->info().notes.size(), 1u);
    EXPECT_EQ(first->info().notes[0],
              "VTK image data file " + path +
                  " holds 3 components: component 0 of 3 is read; --channel C (0 to 2) "
                  "picks another");
    SourceOptions options;
    options.channel = 2;
    const auto last = openVolumeSource(path, options);
    EXPECT_EQ(last->info().description, "vti:" + path + " (density) (component 2 of 3)");
    EXPECT_EQ(last->info().spacing, glm::dvec3(0.5, 0.75, 2.0));
    for (const uint32_t z : {3u, 1u, 4u, 0u, 2u}) {
      const auto slab = readSlab<float>(*last, z, 1);
      EXPECT_TRUE(std::equal(slab.begin(), slab.end(), componentOf(2).begin() + z * 54)) << path << " " << z;
    }
    options.channel = 3;
    EXPECT_EQ(errorOf(path, options),
              "--channel 3: VTK image data file " + path + " holds 3 components (--channel 0 to 2)");
  }
}

TEST(SourceVti, EveryType) {
  TempDir dir;
  auto check = [&](auto tag, const std::string& vtiType, SampleType type) {
    using T = decltype(tag);
    const auto values = samplePattern<T>(kVtiSamples);
    const std::string path = dir.file(vtiType + ".vti");
    writeFile(path, vtiFile(vtiType, values, {.compressor = VtiCompressor::ZLib}));
    expectVolume(*openVolumeSource(path), {{9, 6, 5}, type, {0.5, 0.75, 2.0}, "vti:" + path + " (density)"},
                 values);
  };
  check(int8_t{}, "Int8", SampleType::Int8);
  check(uint8_t{}, "UInt8", SampleType::UInt8);
  check(uint16_t{}, "UInt16", SampleType::UInt16);
  check(int32_t{}, "Int32", SampleType::Int32);
  check(uint32_t{}, "UInt32", SampleType::UInt32);
  check(float{}, "Float32", SampleType::Float32);
  check(double{}, "Float64", SampleType::Float64);
}

// Direction (VTK's row-major matrix): its columns are where x, y and z point; columns not at right angles are
// not applied, and said.
TEST(SourceVti, DirectionGivesTheAxes) {
  const auto values = samplePattern<int16_t>(kVtiSamples);
  const std::string good = vtiFile("Int16", values, {});
  const auto withDirection = [&](const std::string& matrix) {
    std::string text = good;
    const std::string spacing = "Spacing=\"0.5 0.75 2\"";
    return text.replace(text.find(spacing), spacing.size(), spacing + " Direction=\"" + matrix + "\"");
  };
  TempDir dir;
  writeFile(dir.file("turned.vti"), withDirection("0 -1 0 1 0 0 0 0 1"));
  const auto turned = openVolumeSource(dir.file("turned.vti"));
  EXPECT_EQ(turned->info().axes,
            AxisDirections(glm::dvec3(0, 1, 0), glm::dvec3(-1, 0, 0), glm::dvec3(0, 0, 1)));
  EXPECT_TRUE(turned->info().notes.empty());
  // The first sample is the WholeExtent's low corner (-4, 10, 0): Origin + Direction (low * Spacing).
  writeFile(dir.file("plain.vti"), good);
  EXPECT_EQ(openVolumeSource(dir.file("plain.vti"))->info().origin, glm::dvec3(-2.0, 7.5, 0.0));
  EXPECT_EQ(turned->info().origin, glm::dvec3(-7.5, -2.0, 0.0));
  writeFile(dir.file("sheared.vti"), withDirection("1 0.5 0 0 1 0 0 0 1"));
  const auto sheared = openVolumeSource(dir.file("sheared.vti"));
  EXPECT_EQ(sheared->info().axes, AxisDirections(1.0));
  ASSERT_EQ(sheared->info().notes.size(), 1u);
  EXPECT_NE(sheared->info().notes[0].find("its Direction does not keep the axes at right angles"),
            std::string::npos);
}

TEST(SourceVti, UnsupportedAndDamagedFilesNameTheFile) {
  const auto values = samplePattern<int16_t>(kVtiSamples);
  const std::string good = vtiFile("Int16", values, {});
  const auto replaced = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    EXPECT_NE(text.find(from), std::string::npos) << from;
    return text.replace(text.find(from), from.size(), to);
  };
  const std::vector<RefusedHeader> cases = {
      {"not XML", "this is not XML\n", "not well-formed XML at line 1"},
      {"another root", replaced("<VTKFile", "<VTKFiles"), "expected a VTKFile element first"},
      {"poly data", replaced("type=\"ImageData\"", "type=\"PolyData\""), "only ImageData (.vti) is read"},
      {"byte order", replaced("LittleEndian", "MiddleEndian"), "expected LittleEndian or BigEndian"},
      {"header type", replaced("UInt32", "UInt16"), "expected UInt32 or UInt64"},
      {"another compressor",
       replaced("header_type=\"UInt32\"", "header_type=\"UInt32\" compressor=\"vtkZstdDataCompressor\""),
       "compressor 'vtkZstdDataCompressor' is not read"},
      {"extent", replaced("WholeExtent=\"-4 4 10 15 0 4\"", "WholeExtent=\"-4 4 10 15 4 0\""),
       "each low <= high"},
      {"spacing", replaced("Spacing=\"0.5 0.75 2\"", "Spacing=\"0.5 0 2\""), "expected 3 non-zero numbers"},
      {"piece", replaced("Piece Extent=\"-4 4 10 15 0 4\"", "Piece Extent=\"-4 4 10 15 0 2\""),
       "the Piece's Extent is not the WholeExtent"},
      {"two pieces",
       replaced("    </Piece>\n", "    </Piece>\n    <Piece Extent=\"-4 4 10 15 0 4\"></Piece>\n"),
       "several Pieces"},
      {"no such scalars", replaced("Scalars=\"density\"", "Scalars=\"pressure\""),
       "no DataArray named 'pressure'"},
      {"components", replaced("Name=\"density\"", "Name=\"density\" NumberOfComponents=\"0\""),
       "NumberOfComponents '0' is not a count from 1 to 65536"},
      {"Int64", replaced("type=\"Int16\"", "type=\"Int64\""), "of type 'Int64' is not read"},
      {"ASCII", replaced("Name=\"density\" format=\"appended\"", "Name=\"density\" format=\"ascii\""),
       "ASCII data is not read"},
      {"no appended data", good.substr(0, good.find("  <AppendedData")), "no AppendedData element"},
  };
  expectHeadersRefused(cases, "/some/dir/bad.vti",
                       [](const std::string& h, const std::string& f) { parseVtiHeader(h, f); });

  TempDir dir;
  const auto expectFailure = [&](const std::string& name, const std::string& text,
                                 const std::string& expected, bool whenRead) {
    const std::string path = dir.file(name);
    writeFile(path, text);
    std::string message;
    try {
      auto source = openVolumeSource(path);
      if (!whenRead) ADD_FAILURE() << name << ": opened";
      readSlab<int16_t>(*source, 0, 5);
      ADD_FAILURE() << name << ": read without error";
    } catch (const Error& e) {
      message = e.what();
    }
    EXPECT_NE(message.find(path), std::string::npos) << name << ": " << message;
    EXPECT_NE(message.find(expected), std::string::npos) << name << ": " << message;
  };
  const std::string appendedEnd = "\n  </AppendedData>\n</VTKFile>\n";
  expectFailure("cut.vti", good.substr(0, good.size() - appendedEnd.size() - 3), "truncated", false);
  const std::string zlibFile = vtiFile("Int16", values, {.compressor = VtiCompressor::ZLib});
  expectFailure("cutblocks.vti", zlibFile.substr(0, zlibFile.size() - appendedEnd.size() - 3), "truncated",
                false);
  // A byte count for another size.
  std::string wrongCount = good;
  const size_t count = wrongCount.find("\n   _") + 5 + kVtiSamples * 4 + 4;  // past "other" and its count
  wrongCount[count] = char(wrongCount[count] + 2);
  expectFailure("count.vti", wrongCount, "says it holds 542 bytes", false);
  // A compression header counting more blocks than the file holds sizes for: 2^62 blocks of 1 byte, for a
  // float64 volume of 2^59 samples, whose size words alone would be 2^65 bytes.
  std::string manyBlocks = vtiFile("Float64", samplePattern<double>(kVtiSamples),
                                   {.compressor = VtiCompressor::ZLib, .wideHeader = true});
  for (const std::string extent : {"WholeExtent=", "Piece Extent="}) {
    const std::string small = "\"-4 4 10 15 0 4\"";
    manyBlocks.replace(manyBlocks.find(extent + small) + extent.size(), small.size(),
                       "\"0 1048575 0 1048575 0 524287\"");
  }
  const size_t offsetAt = manyBlocks.find("offset=\"", manyBlocks.find("Name=\"density\"")) + 8;
  const size_t density = manyBlocks.find("\n   _") + 5 + std::stoull(manyBlocks.substr(offsetAt));
  const std::string header = std::string(7, '\0') + '\x40' + '\x01' + std::string(15, '\0');  // 2^62, 1, 0
  manyBlocks.replace(density, header.size(), header);
  expectFailure("manyblocks.vti", manyBlocks, "more than the file holds", false);
  // A damaged block, and a base64 character that is none.
  std::string damaged = zlibFile;
  damaged[damaged.size() - appendedEnd.size() - 20] ^= 0x55;
  expectFailure("damaged.vti", damaged, "zlib block", true);
  for (const auto& [compressor, name] :
       {std::pair{VtiCompressor::LZ4, "LZ4 block"}, std::pair{VtiCompressor::LZMA, "LZMA block"}}) {
    // The density array's first block changed: past its compression header of 3 words and 6 block sizes.
    std::string changed = vtiFile("Int16", values, {.compressor = compressor});
    const size_t offset = changed.find("offset=\"", changed.find("Name=\"density\"")) + 8;
    const size_t blocksAt = changed.find("\n   _") + 5 + std::stoull(changed.substr(offset)) + 4 * (3 + 6);
    for (size_t i = 0; i < 8; ++i) changed[blocksAt + i] = char(0xff);
    expectFailure(std::string(name) + ".vti", changed,
                  std::string(name) + " 0 of the array 'density' is damaged", true);
  }
  std::string notBase64 = vtiFile("Int16", values, {.base64 = true});
  notBase64[notBase64.size() - appendedEnd.size() - 40] = '#';
  expectFailure("notbase64.vti", notBase64, "not base64 data", true);
}

}  // namespace
}  // namespace ropecast
