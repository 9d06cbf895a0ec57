// Tests of the image-stack VolumeSource (OpenImageIO): PNG and TIFF stacks from a directory or a glob,
// multi-page TIFFs, every supported pixel type (int8, uint32, int32 and float64 converted and read back
// through the store's mapping), bit depths narrower than it (bilevel PNG, 12-bit TIFF, 24-bit TIFF),
// MinIsWhite TIFFs, gray slices saved as RGB, RGBA or palette images, slab reads at any z, name ordering,
// and each bad slice (different size or type, unreadable, two channels, color that is not gray, a TIFF cut
// short, one OpenImageIO would read as zeros) or bad spec giving an error that names the file.
#include "store/source_images.h"
#include "store/tiff_directories.h"
#include "store/tiff_page_reader.h"

#include <Imath/half.h>
#include <OpenImageIO/imageio.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <zlib.h>

#include "core/error.h"
#include "tests/store/store_test_util.h"
#include "tests/store/testutil_round_trip.h"

namespace ropecast {
namespace {

namespace fs = std::filesystem;
using testing::convertAndOpen;
using testing::errorOf;
using testing::expectKept;
using testing::level0Data;
using testing::readSlab;
using testing::TempDir;

template <typename T>
OIIO::TypeDesc typeDescOf() {
  if constexpr (std::is_same_v<T, uint8_t>) return OIIO::TypeDesc::UINT8;
  if constexpr (std::is_same_v<T, int8_t>) return OIIO::TypeDesc::INT8;
  if constexpr (std::is_same_v<T, uint16_t>) return OIIO::TypeDesc::UINT16;
  if constexpr (std::is_same_v<T, int16_t>) return OIIO::TypeDesc::INT16;
  if constexpr (std::is_same_v<T, uint32_t>) return OIIO::TypeDesc::UINT32;
  if constexpr (std::is_same_v<T, int32_t>) return OIIO::TypeDesc::INT32;
  if constexpr (std::is_same_v<T, float>) return OIIO::TypeDesc::FLOAT;
  if constexpr (std::is_same_v<T, double>) return OIIO::TypeDesc::DOUBLE;
}

// Slice z of a w x h stack: distinct in x, y and z.
template <typename T>
std::vector<T> slicePattern(uint32_t w, uint32_t h, uint32_t z) {
  std::vector<T> v(size_t(w) * h);
  for (size_t i = 0; i < v.size(); ++i) {
    if constexpr (std::is_floating_point_v<T>)
      v[i] = T(double(i) * 0.5 - double(z) * 100.0);
    else
      v[i] = T((i * 2654435761u >> 5) + z * 31u);
  }
  return v;
}

// An image of `pixels`; tiled in tiles of `tile` x `tile` pixels when `tile` > 0.
template <typename T>
void writeImage(const std::string& path, uint32_t w, uint32_t h, const std::vector<T>& pixels,
                int channels = 1, int tile = 0) {
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out) << OIIO::geterror();
  OIIO::ImageSpec spec(int(w), int(h), channels, typeDescOf<T>());
  spec.tile_width = spec.tile_height = tile;
  spec.attribute("oiio:UnassociatedAlpha", 1);  // alpha as given, not divided out of the color
  ASSERT_TRUE(out->open(path, spec)) << out->geterror();
  ASSERT_TRUE(out->write_image(typeDescOf<T>(), pixels.data())) << out->geterror();
  ASSERT_TRUE(out->close());
}

// A single-channel image whose file holds `bits` bits per sample; `pixels` are the file's values.
void writeNarrowImage(const std::string& path, uint32_t w, uint32_t h, const std::vector<uint16_t>& pixels,
                      int bits) {
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out) << OIIO::geterror();
  OIIO::ImageSpec spec(int(w), int(h), 1, bits <= 8 ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::UINT16);
  spec.attribute("oiio:BitsPerSample", bits);
  ASSERT_TRUE(out->open(path, spec)) << out->geterror();
  // OpenImageIO writes the high bits of the samples it is given, of the spec's type (a conversion between
  // types would round).
  const int typeBits = bits <= 8 ? 8 : 16;
  std::vector<uint16_t> widened16(pixels.size());
  std::vector<uint8_t> widened8(pixels.size());
  for (size_t i = 0; i < pixels.size(); ++i) {
    widened16[i] = uint16_t(pixels[i] << (typeBits - bits));
    widened8[i] = uint8_t(widened16[i]);
  }
  ASSERT_TRUE(typeBits == 8 ? out->write_image(OIIO::TypeDesc::UINT8, widened8.data())
                            : out->write_image(OIIO::TypeDesc::UINT16, widened16.data()))
      << out->geterror();
  ASSERT_TRUE(out->close());
}

// How writePages stores the pages: OpenImageIO's defaults where a field is left empty.
struct PageStorage {
  std::string compression;  // "none", "lzw", "zip", "packbits", ...
  int rowsPerStrip = 0;
  int tile = 0;  // tiles of tile x tile pixels
};

// A multi-page TIFF of w x h pages of `channels` samples a pixel.
template <typename T>
void writePages(const std::string& path, uint32_t w, uint32_t h, const std::vector<std::vector<T>>& pages,
                int channels = 1, const PageStorage& storage = {}) {
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out && out->supports("multiimage"));
  std::vector<OIIO::ImageSpec> specs(pages.size(),
                                     OIIO::ImageSpec(int(w), int(h), channels, typeDescOf<T>()));
  for (OIIO::ImageSpec& spec : specs) {
    if (!storage.compression.empty()) spec.attribute("compression", storage.compression);
    if (storage.rowsPerStrip) spec.attribute("tiff:RowsPerStrip", storage.rowsPerStrip);
    spec.tile_width = spec.tile_height = storage.tile;
  }
  ASSERT_TRUE(out->open(path, int(pages.size()), specs.data())) << out->geterror();
  for (size_t z = 0; z < pages.size(); ++z) {
    if (z > 0) {
      ASSERT_TRUE(out->open(path, specs[z], OIIO::ImageOutput::AppendSubimage)) << out->geterror();
    }
    ASSERT_TRUE(out->write_image(typeDescOf<T>(), pages[z].data())) << out->geterror();
  }
  ASSERT_TRUE(out->close());
}

template <typename T>
void writeMultiPage(const std::string& path, uint32_t w, uint32_t h, uint32_t pages) {
  std::vector<std::vector<T>> patterns;
  for (uint32_t z = 0; z < pages; ++z) patterns.push_back(slicePattern<T>(w, h, z));
  writePages(path, w, h, patterns);
}

// A single-channel page of a TIFF written byte by byte (writeTiff), its rows packed as the file stores them.
struct TiffPage {
  uint32_t width = 0, height = 0;
  uint16_t bits = 8;
  uint16_t photometric = 1;  // 0: MinIsWhite, 1: MinIsBlack
  std::vector<uint8_t> data;
  uint16_t sampleFormat = 1;  // 1: unsigned, 2: signed, 3: floating point (tagged only when not 1)
  // A palette page's ColorMap (photometric 3): the reds, greens, then blues of its 2^bits entries.
  std::vector<uint16_t> colorMap{};
  uint16_t compression = 1;  // 1: none; 32773: PackBits, which writeTiff encodes
};

// Rows of `rowBytes` bytes in PackBits (TIFF 6.0, Sect. 9): each row as runs of up to 128 literal bytes.
std::vector<uint8_t> packBits(const std::vector<uint8_t>& data, size_t rowBytes) {
  std::vector<uint8_t> packed;
  for (size_t row = 0; row < data.size(); row += rowBytes)
    for (size_t at = row; at < row + rowBytes; at += 128) {
      const size_t run = std::min<size_t>(128, row + rowBytes - at);
      packed.push_back(uint8_t(run - 1));
      packed.insert(packed.end(), data.begin() + long(at), data.begin() + long(at + run));
    }
  return packed;
}

template <typename T>
TiffPage tiffPage(uint32_t w, uint32_t h, const std::vector<T>& samples, uint16_t photometric = 1) {
  TiffPage page{w, h, uint16_t(8 * sizeof(T)), photometric, std::vector<uint8_t>(samples.size() * sizeof(T))};
  page.sampleFormat = std::is_floating_point_v<T> ? 3 : std::is_signed_v<T> ? 2 : 1;
  std::memcpy(page.data.data(), samples.data(), page.data.size());  // little-endian, as the file says
  return page;
}

// The directory entries of a page whose data starts at `dataAt` (and its color map at `colorMapAt`): tag,
// type (3: 16 bits, 4: 32 bits), count, value (or where the values are, for more than one). SampleFormat only
// for samples that are not unsigned, so that the directories of unsigned pages are 114 bytes (9 entries).
std::vector<std::array<uint32_t, 4>> tiffEntries(const TiffPage& page, uint32_t dataAt,
                                                 uint32_t colorMapAt = 0) {
  std::vector<std::array<uint32_t, 4>> entries = {{256, 4, 1, page.width},
                                                  {257, 4, 1, page.height},
                                                  {258, 3, 1, page.bits},
                                                  {259, 3, 1, page.compression},
                                                  {262, 3, 1, page.photometric},
                                                  {273, 4, 1, dataAt},
                                                  {277, 3, 1, 1},
                                                  {278, 4, 1, page.height},
                                                  {279, 4, 1, uint32_t(page.data.size())}};
  if (!page.colorMap.empty()) entries.push_back({320, 3, uint32_t(page.colorMap.size()), colorMapAt});
  if (page.sampleFormat != 1) entries.push_back({339, 3, 1, page.sampleFormat});
  return entries;
}

uint32_t tiffDirectoryBytes(const TiffPage& page) {
  return uint32_t(2 + tiffEntries(page, 0).size() * 12 + 4);
}

// A TIFF, little-endian unless `bigEndian`, for what OpenImageIO does not write: MinIsWhite pages, palette
// pages with the color maps given, half floats, big-endian files, and every page's directory ahead of all the
// image data (OpenImageIO writes each page's data, then its directory; then no page may have a color map).
void writeTiff(const std::string& path, std::vector<TiffPage> pages, bool directoriesFirst = false,
               bool bigEndian = false) {
  std::vector<uint8_t> file = bigEndian ? std::vector<uint8_t>{'M', 'M', 0, 42, 0, 0, 0, 0}
                                        : std::vector<uint8_t>{'I', 'I', 42, 0, 0, 0, 0, 0};
  const auto put = [&](uint32_t at, uint32_t value, int bytes) {
    for (int i = 0; i < bytes; ++i) file[at + (bigEndian ? bytes - 1 - i : i)] = uint8_t(value >> (8 * i));
  };
  for (TiffPage& page : pages) {
    if (bigEndian)
      for (size_t i = 0, width = page.bits / 8; width > 1 && i + width <= page.data.size(); i += width)
        std::reverse(page.data.begin() + long(i), page.data.begin() + long(i + width));
    if (page.compression == 32773) page.data = packBits(page.data, page.data.size() / page.height);
  }
  uint32_t dataAt = 8;
  if (directoriesFirst)
    for (const TiffPage& page : pages) dataAt += tiffDirectoryBytes(page);
  uint32_t linkAt = 4;  // where the offset of the next directory goes
  for (const TiffPage& page : pages) {
    uint32_t colorMapAt = 0;
    if (!directoriesFirst) {
      dataAt = uint32_t(file.size());
      file.insert(file.end(), page.data.begin(), page.data.end());
      if (file.size() % 2) file.push_back(0);  // directories start on a word boundary
      colorMapAt = uint32_t(file.size());
      file.resize(file.size() + 2 * page.colorMap.size());
      for (size_t i = 0; i < page.colorMap.size(); ++i)
        put(colorMapAt + uint32_t(2 * i), page.colorMap[i], 2);
    }
    const uint32_t directoryAt = uint32_t(file.size());
    const std::vector<std::array<uint32_t, 4>> entries = tiffEntries(page, dataAt, colorMapAt);
    put(linkAt, directoryAt, 4);
    file.resize(file.size() + tiffDirectoryBytes(page));
    put(directoryAt, uint32_t(entries.size()), 2);
    for (uint32_t e = 0; e < entries.size(); ++e) {
      const uint32_t at = directoryAt + 2 + 12 * e;
      put(at, entries[e][0], 2);
      put(at + 2, entries[e][1], 2);
      put(at + 4, entries[e][2], 4);
      put(at + 8, entries[e][3], entries[e][1] == 3 && entries[e][2] == 1 ? 2 : 4);
    }
    linkAt = directoryAt + 2 + uint32_t(entries.size()) * 12;
    if (directoriesFirst) dataAt += uint32_t(page.data.size());
  }
  if (directoriesFirst)
    for (const TiffPage& page : pages) file.insert(file.end(), page.data.begin(), page.data.end());
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(file.data()), file.size());
}

template <typename T>
void expectSlices(VolumeSource& source, uint32_t w, uint32_t h, uint32_t depth) {
  ASSERT_EQ(source.info().dims, glm::u32vec3(w, h, depth));
  const auto all = readSlab<T>(source, 0, depth);
  for (uint32_t z = 0; z < depth; ++z) {
    const auto expected = slicePattern<T>(w, h, z);
    ASSERT_TRUE(std::equal(expected.begin(), expected.end(), all.begin() + size_t(z) * w * h))
        << "slice " << z;
  }
  for (uint32_t z0 : {depth - 1, depth / 2, 0u}) {  // slabs out of order
    const auto slab = readSlab<T>(source, z0, 1);
    EXPECT_EQ(slab, slicePattern<T>(w, h, z0)) << "slab at " << z0;
  }
}

TEST(SourceImages, PngStackInADirectoryInNameOrder) {
  TempDir dir;
  // Unpadded numbers: slice_2 must come before slice_10.
  for (uint32_t z = 0; z < 12; ++z)
    writeImage(dir.file("slice_" + std::to_string(z) + ".png"), 17, 9, slicePattern<uint8_t>(17, 9, z));
  std::ofstream(dir.file("notes.txt")) << "not a slice";
  auto source = openVolumeSource(dir.path().string());
  EXPECT_EQ(source->info().type, SampleType::UInt8);
  expectSlices<uint8_t>(*source, 17, 9, 12);
}

TEST(SourceImages, Uint16PngAndTiffStacksByGlob) {
  TempDir dir;
  for (uint32_t z = 0; z < 5; ++z) {
    writeImage(dir.file("a_" + std::to_string(z) + ".png"), 8, 11, slicePattern<uint16_t>(8, 11, z));
    writeImage(dir.file("b_" + std::to_string(z) + ".tif"), 8, 11, slicePattern<int16_t>(8, 11, z));
    writeImage(dir.file("c_" + std::to_string(z) + ".tiff"), 8, 11, slicePattern<float>(8, 11, z));
  }
  SourceOptions options;
  options.spacing = glm::dvec3(0.3, 0.3, 1.2);
  auto png = openVolumeSource(dir.file("a_*.png"), options);
  EXPECT_EQ(png->info().type, SampleType::UInt16);
  EXPECT_EQ(png->info().spacing, glm::dvec3(0.3, 0.3, 1.2));
  expectSlices<uint16_t>(*png, 8, 11, 5);
  auto tif = openVolumeSource(dir.file("b_?.tif"));
  EXPECT_EQ(tif->info().type, SampleType::Int16);
  expectSlices<int16_t>(*tif, 8, 11, 5);
  // A bracket expression alone makes a pattern too.
  expectSlices<int16_t>(*openVolumeSource(dir.file("b_[0-4].tif")), 8, 11, 5);
  auto flt = openVolumeSource(dir.file("c_*"));
  EXPECT_EQ(flt->info().type, SampleType::Float32);
  expectSlices<float>(*flt, 8, 11, 5);
}

TEST(SourceImages, MultiPageTiff) {
  TempDir dir;
  writeMultiPage<float>(dir.file("pages.tif"), 10, 7, 6);
  writeMultiPage<int16_t>(dir.file("pages16.tiff"), 5, 12, 3);
  EXPECT_EQ(countImagePages(dir.file("pages.tif")), 6);
  auto source = openVolumeSource(dir.file("pages.tif"));
  EXPECT_EQ(source->info().type, SampleType::Float32);
  EXPECT_EQ(source->info().description, "tiff:" + dir.file("pages.tif"));
  expectSlices<float>(*source, 10, 7, 6);
  auto i16 = openVolumeSource(dir.file("pages16.tiff"));
  expectSlices<int16_t>(*i16, 5, 12, 3);
}

// A multi-page TIFF's pages are read through libtiff at their directories' offsets (TiffPageReader), not
// through OpenImageIO (whose TIFF reader walks every directory before a page to reach it), in each type as
// written: 4 pages of w x h stored as `storage` says.
template <typename T>
void expectPagesReadAtTheirDirectories(const std::string& path, const PageStorage& storage,
                                       uint64_t compression, uint32_t w = 10, uint32_t h = 7) {
  std::vector<std::vector<T>> patterns;
  for (uint32_t z = 0; z < 4; ++z) patterns.push_back(slicePattern<T>(w, h, z));
  writePages(path, w, h, patterns, 1, storage);
  const auto layouts = tiffPageLayouts(path);
  ASSERT_TRUE(layouts);
  ASSERT_EQ((*layouts)[2].compression, compression) << path;
  ASSERT_EQ((*layouts)[2].tiled, storage.tile > 0) << path;
  if (storage.rowsPerStrip) {
    ASSERT_EQ((*layouts)[2].rowsPerStrip, uint64_t(storage.rowsPerStrip)) << path;
  }
  ASSERT_TRUE(TiffPageReader::reads((*layouts)[2])) << path;
  expectSlices<T>(*openVolumeSource(path), w, h, 4);
}

// Uncompressed, in strips of 3 rows of 7 (OpenImageIO's writer), and big-endian (ImageJ's).
TEST(SourceImages, UncompressedPagesAreReadAsStoredInEitherByteOrder) {
  TempDir dir;
  const PageStorage stripsOf3{.compression = "none", .rowsPerStrip = 3};
  expectPagesReadAtTheirDirectories<uint8_t>(dir.file("u8.tif"), stripsOf3, 1);
  expectPagesReadAtTheirDirectories<int16_t>(dir.file("i16.tif"), stripsOf3, 1);
  expectPagesReadAtTheirDirectories<uint32_t>(dir.file("u32.tif"), stripsOf3, 1);
  expectPagesReadAtTheirDirectories<float>(dir.file("f32.tif"), stripsOf3, 1);
  expectPagesReadAtTheirDirectories<double>(dir.file("f64.tif"), stripsOf3, 1);

  std::vector<TiffPage> u16, f32;
  for (uint32_t z = 0; z < 3; ++z) {
    u16.push_back(tiffPage<uint16_t>(5, 4, slicePattern<uint16_t>(5, 4, z)));
    f32.push_back(tiffPage<float>(5, 4, slicePattern<float>(5, 4, z)));
  }
  writeTiff(dir.file("big16.tif"), u16, false, /*bigEndian=*/true);
  writeTiff(dir.file("big32.tif"), f32, true, /*bigEndian=*/true);
  ASSERT_TRUE((*tiffPageLayouts(dir.file("big16.tif")))[0].bigEndian);
  expectSlices<uint16_t>(*openVolumeSource(dir.file("big16.tif")), 5, 4, 3);
  expectSlices<float>(*openVolumeSource(dir.file("big32.tif")), 5, 4, 3);
}

// LZW, Deflate (with OpenImageIO's predictors), PackBits, in strips and in 16 x 16 tiles that overhang the
// page; big-endian PackBits, written byte by byte.
TEST(SourceImages, CompressedAndTiledPagesAreReadAtTheirDirectories) {
  TempDir dir;
  expectPagesReadAtTheirDirectories<uint8_t>(dir.file("lzw8.tif"), {.compression = "lzw", .rowsPerStrip = 2},
                                             5);
  expectPagesReadAtTheirDirectories<int16_t>(dir.file("zip16.tif"), {.compression = "zip"}, 8);
  expectPagesReadAtTheirDirectories<float>(dir.file("lzwf.tif"), {.compression = "lzw"}, 5);
  expectPagesReadAtTheirDirectories<double>(dir.file("zipd.tif"), {.compression = "zip"}, 8);
  expectPagesReadAtTheirDirectories<uint16_t>(dir.file("packbits16.tif"), {.compression = "packbits"}, 32773);
  expectPagesReadAtTheirDirectories<uint16_t>(dir.file("tiled16.tif"), {.compression = "zip", .tile = 16}, 8,
                                              40, 20);
  expectPagesReadAtTheirDirectories<uint8_t>(dir.file("tiled8.tif"), {.compression = "none", .tile = 16}, 1,
                                             20, 33);

  std::vector<TiffPage> pages;
  for (uint32_t z = 0; z < 3; ++z) {
    pages.push_back(tiffPage<int32_t>(70, 3, slicePattern<int32_t>(70, 3, z)));
    pages.back().compression = 32773;
  }
  writeTiff(dir.file("big_packbits.tif"), pages, false, /*bigEndian=*/true);
  ASSERT_EQ((*tiffPageLayouts(dir.file("big_packbits.tif")))[1].compression, 32773u);
  expectSlices<int32_t>(*openVolumeSource(dir.file("big_packbits.tif")), 70, 3, 3);
}

// A page whose compressed data does not decode is an error naming the file and page, with libtiff's message.
TEST(SourceImages, APageThatDoesNotDecodeIsNamed) {
  TempDir dir;
  const std::string path = dir.file("pages.tif");
  // Noise, which Deflate leaves about as large as it is.
  std::mt19937 random(7);
  std::vector<std::vector<uint16_t>> pages(4, std::vector<uint16_t>(30 * 20));
  for (auto& page : pages)
    for (uint16_t& v : page) v = uint16_t(random());
  writePages(path, 30, 20, pages, 1, {.compression = "zip"});
  // OpenImageIO writes each page's directory, then its data: page 2's data fills most of the bytes from its
  // directory to page 3's.
  const auto layouts = tiffPageLayouts(path);
  ASSERT_TRUE(layouts);
  const uint64_t start = (*layouts)[2].directoryOffset, end = (*layouts)[3].directoryOffset;
  ASSERT_LT(start + 1000, end);
  {
    std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(std::streamoff((start + end) / 2 - 32));
    const std::string garbage(64, char(0xA5));
    file.write(garbage.data(), std::streamsize(garbage.size()));
  }
  const auto source = openVolumeSource(path);
  EXPECT_EQ(readSlab<uint16_t>(*source, 1, 1), pages[1]);
  try {
    readSlab<uint16_t>(*source, 2, 1);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot read image slice " + path + " (page 2): "),
              std::string::npos)
        << e.what();
  }
}

// Pages of w x h uint16 samples, the first described by `description` (ImageJ's or OME's) and, where
// `resolution` > 0, that many pixels per unit along x and y.
void writeDescribedPages(const std::string& path, int w, int h,
                         const std::vector<std::vector<uint16_t>>& pages, const std::string& description,
                         float resolution = 0.0f) {
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out);
  std::vector<OIIO::ImageSpec> specs(pages.size(), OIIO::ImageSpec(w, h, 1, OIIO::TypeDesc::UINT16));
  specs[0].attribute("ImageDescription", description);
  if (resolution > 0.0f) {
    specs[0].attribute("XResolution", resolution);
    specs[0].attribute("YResolution", resolution);
    specs[0].attribute("ResolutionUnit", "none");
  }
  ASSERT_TRUE(out->open(path, int(pages.size()), specs.data())) << out->geterror();
  for (size_t z = 0; z < pages.size(); ++z) {
    if (z > 0) {
      ASSERT_TRUE(out->open(path, specs[z], OIIO::ImageOutput::AppendSubimage)) << out->geterror();
    }
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT16, pages[z].data())) << out->geterror();
  }
  ASSERT_TRUE(out->close());
}

// A folder of slices ImageJ saved (an image sequence): each file's resolution tags, vouched for by its ImageJ
// description, give the pixel's size; the spacing between slices is the pixel's width unless a description
// says it (`spacing=`), which a note says; --spacing overrides; resolution tags without an ImageJ description
// (a scanner's 72 dots per inch) say nothing.
TEST(SourceImages, AnImageJSliceFoldersCalibration) {
  TempDir dir;
  const auto sequence = [&](const std::string& name, const std::string& description, float resolution) {
    const fs::path folder = dir / name;
    fs::create_directories(folder);
    for (uint32_t z = 0; z < 3; ++z)
      writeDescribedPages((folder / ("slice" + std::to_string(z) + ".tif")).string(), 5, 4,
                          {slicePattern<uint16_t>(5, 4, z)}, description, resolution);
    return folder.string();
  };
  const std::string calibrated = sequence("calibrated", "ImageJ=1.54f\nunit=micron\nloop=false\n", 4.0f);
  const auto source = openVolumeSource(calibrated);
  EXPECT_EQ(source->info().spacing, glm::dvec3(0.25, 0.25, 0.25));
  EXPECT_NE(source->info().description.find("(ImageJ calibration: 0.25,0.25,0.25 micron)"), std::string::npos)
      << source->info().description;
  ASSERT_EQ(source->info().notes.size(), 1u);
  EXPECT_NE(source->info().notes[0].find("no slice says how far apart they lie"), std::string::npos)
      << source->info().notes[0];

  const std::string spaced = sequence("spaced", "ImageJ=1.54f\nunit=micron\nspacing=2\nloop=false\n", 4.0f);
  const auto withSpacing = openVolumeSource(spaced);
  EXPECT_EQ(withSpacing->info().spacing, glm::dvec3(0.25, 0.25, 2.0));
  EXPECT_TRUE(withSpacing->info().notes.empty());

  SourceOptions given;
  given.spacing = glm::dvec3(1.0, 1.0, 3.0);
  const auto overridden = openVolumeSource(calibrated, given);
  EXPECT_EQ(overridden->info().spacing, glm::dvec3(1.0, 1.0, 3.0));
  EXPECT_TRUE(overridden->info().notes.empty());

  const std::string scanned = sequence("scanned", "a scanner's page", 72.0f);
  EXPECT_EQ(openVolumeSource(scanned)->info().spacing, glm::dvec3(1.0));
}

// An OME-TIFF of 2 named channels of 3 slices (XYZCT: a channel's slices one after another): the names are
// said in the warning and the description; --channel 1 reads the second channel's pages.
TEST(SourceImages, AnOmeTiffsNamedChannels) {
  TempDir dir;
  const std::string path = dir.file("cells.ome.tif");
  std::vector<std::vector<uint16_t>> pages;
  for (uint32_t page = 0; page < 6; ++page) pages.push_back(slicePattern<uint16_t>(5, 4, page));
  writeDescribedPages(
      path, 5, 4, pages,
      "<?xml version=\"1.0\"?><OME xmlns=\"http://www.openmicroscopy.org/Schemas/OME/2016-06\"><Image "
      "ID=\"Image:0\"><Pixels ID=\"Pixels:0\" DimensionOrder=\"XYZCT\" Type=\"uint16\" SizeX=\"5\" "
      "SizeY=\"4\" SizeZ=\"3\" SizeC=\"2\" SizeT=\"1\"><Channel ID=\"Channel:0:0\" Name=\"DAPI\"/><Channel "
      "ID=\"Channel:0:1\" Name=\"GFP\"/><TiffData/></Pixels></Image></OME>");
  const auto first = openVolumeSource(path);
  ASSERT_EQ(first->info().notes.size(), 1u);
  EXPECT_EQ(first->info().notes[0], "OME-TIFF image " + path +
                                        " holds 2 channels ('DAPI', 'GFP'): channel 0 of 2: 'DAPI' is read; "
                                        "--channel C (0 to 1) picks another");
  SourceOptions second;
  second.channel = 1;
  const auto gfp = openVolumeSource(path, second);
  EXPECT_EQ(gfp->info().description, "tiff:" + path + " (channel 1 of 2: 'GFP')");
  std::vector<uint16_t> expected;
  for (uint32_t page : {3u, 4u, 5u}) expected.insert(expected.end(), pages[page].begin(), pages[page].end());
  EXPECT_EQ(readSlab<uint16_t>(*gfp, 0, 3), expected);
}

// An ImageJ hyperstack of 2 channels, 3 slices and 2 frames (pages c0 z0 t0, c1 z0 t0, c0 z1 t0, ..., c0 z0
// t1, ...), calibrated: its first channel's first frame is read, at its calibration, said in the description;
// --channel and --time pick another; --spacing overrides the calibration.
TEST(SourceImages, AnImageJHyperstacksChannelAndFrameAtItsCalibration) {
  TempDir dir;
  const std::string path = dir.file("stack.tif");
  std::vector<std::vector<uint16_t>> pages;
  for (uint32_t page = 0; page < 12; ++page) pages.push_back(slicePattern<uint16_t>(5, 4, page));
  writeDescribedPages(path, 5, 4, pages,
                      "ImageJ=1.54f\nimages=12\nchannels=2\nslices=3\nframes=2\nhyperstack=true\nunit="
                      "micron\nspacing=2\n",
                      4.0f);
  const auto pagesOf = [&](std::initializer_list<uint32_t> numbers) {
    std::vector<uint16_t> expected;
    for (const uint32_t page : numbers)
      for (const uint16_t v : pages[page]) expected.push_back(v);
    return expected;
  };
  const auto source = openVolumeSource(path);
  const VolumeInfo& info = source->info();
  EXPECT_EQ(info.dims, glm::u32vec3(5, 4, 3));
  EXPECT_EQ(info.spacing, glm::dvec3(0.25, 0.25, 2.0));
  EXPECT_EQ(info.description,
            "tiff:" + path + " (ImageJ calibration: 0.25,0.25,2 micron) (time point 0 of 2, channel 0 of 2)");
  ASSERT_EQ(info.notes.size(), 1u);
  EXPECT_EQ(info.notes[0],
            "ImageJ hyperstack " + path +
                " holds 2 time points and 2 channels: time point 0 of 2, channel 0 of 2 is read; "
                "--time T (0 to 1) or --channel C (0 to 1) picks another");
  EXPECT_EQ(readSlab<uint16_t>(*source, 0, 3), pagesOf({0, 2, 4}));

  SourceOptions options;
  options.channel = 1;
  EXPECT_EQ(readSlab<uint16_t>(*openVolumeSource(path, options), 0, 3), pagesOf({1, 3, 5}));
  options.timePoint = 1;
  const auto picked = openVolumeSource(path, options);
  EXPECT_EQ(readSlab<uint16_t>(*picked, 0, 3), pagesOf({7, 9, 11}));
  EXPECT_TRUE(picked->info().notes.empty());
  options.channel = 0;
  EXPECT_EQ(readSlab<uint16_t>(*openVolumeSource(path, options), 1, 2), pagesOf({8, 10}));
  options.channel = 2;
  EXPECT_EQ(errorOf(path, options),
            "--channel 2: ImageJ hyperstack " + path + " holds 2 channels (--channel 0 to 1)");

  SourceOptions spacing;
  spacing.spacing = glm::dvec3(1.0, 1.0, 1.0);
  const auto given = openVolumeSource(path, spacing);
  EXPECT_EQ(given->info().spacing, glm::dvec3(1.0));
  EXPECT_EQ(given->info().description, "tiff:" + path + " (time point 0 of 2, channel 0 of 2)");
}

// `values` (w x h slices, x fastest) as a folder of TIFF slices and as a multi-page TIFF, each converted and
// read back through the store's mapping: kept as a raw file of the same type keeps them (expectKept).
template <typename T>
void expectKeptThroughTiffs(SampleType type, uint32_t w, uint32_t h, const std::vector<T>& values,
                            bool exact) {
  TempDir dir;
  const size_t sliceSamples = size_t(w) * h;
  std::vector<std::vector<T>> slices;
  for (size_t at = 0; at < values.size(); at += sliceSamples)
    slices.emplace_back(values.begin() + at, values.begin() + at + sliceSamples);
  std::filesystem::create_directories(dir.file("stack"));
  for (size_t z = 0; z < slices.size(); ++z)
    writeImage(dir.file("stack/s" + std::to_string(z) + ".tif"), w, h, slices[z]);
  writePages(dir.file("pages.tif"), w, h, slices);
  for (const std::string& spec : {dir.file("stack"), dir.file("pages.tif")}) {
    EXPECT_EQ(openVolumeSource(spec)->info().type, type) << spec;
    expectKept(*convertAndOpen(dir, spec), values, type, exact, spec);
  }
}

constexpr uint32_t kWideW = 9, kWideH = 7, kWideDepth = 5, kWideSamples = kWideW * kWideH * kWideDepth;

// int8 slices are stored as value + 128, as int8 raw files are.
TEST(SourceImages, Int8SlicesAreKeptExactly) {
  std::vector<int8_t> values(kWideSamples);
  for (size_t i = 0; i < values.size(); ++i) values[i] = int8_t(int(i * 37 % 256) - 128);
  values[0] = -128;
  values[1] = 127;
  expectKeptThroughTiffs<int8_t>(SampleType::Int8, kWideW, kWideH, values, true);
}

// uint32 and int32 slices (label masks, say) whose values span at most 65535 are stored as value - min,
// exactly: here at the ends of their type, with the widest such span.
TEST(SourceImages, ThirtyTwoBitIntegerSlicesWhoseRangeFits16BitsAreKeptExactly) {
  std::vector<uint32_t> unsignedValues(kWideSamples);
  for (size_t i = 0; i < unsignedValues.size(); ++i)
    unsignedValues[i] = 4294901760u + uint32_t(i * 7919 % 65536);
  unsignedValues[0] = 4294901760u;
  unsignedValues[1] = 4294967295u;
  expectKeptThroughTiffs<uint32_t>(SampleType::UInt32, kWideW, kWideH, unsignedValues, true);

  std::vector<int32_t> signedValues(kWideSamples);
  for (size_t i = 0; i < signedValues.size(); ++i) signedValues[i] = INT32_MIN + int32_t(i * 7919 % 65536);
  signedValues[0] = INT32_MIN;
  signedValues[1] = INT32_MIN + 65535;
  expectKeptThroughTiffs<int32_t>(SampleType::Int32, kWideW, kWideH, signedValues, true);
}

// Wider ranges are quantized over [min, max]: within half a step.
TEST(SourceImages, ThirtyTwoBitIntegerSlicesOverWiderRangesAreQuantizedWithinHalfAStep) {
  std::vector<int32_t> signedValues(kWideSamples);
  for (size_t i = 0; i < signedValues.size(); ++i) signedValues[i] = int32_t(uint32_t(i * 2654435761u));
  signedValues[0] = INT32_MIN;
  signedValues[1] = INT32_MAX;
  expectKeptThroughTiffs<int32_t>(SampleType::Int32, kWideW, kWideH, signedValues, false);

  std::vector<uint32_t> unsignedValues(kWideSamples);
  for (size_t i = 0; i < unsignedValues.size(); ++i) unsignedValues[i] = uint32_t(i * 2654435761u);
  unsignedValues[1] = 4294967295u;
  expectKeptThroughTiffs<uint32_t>(SampleType::UInt32, kWideW, kWideH, unsignedValues, false);
}

// float64 slices are quantized over their range, here one beyond what a float holds.
TEST(SourceImages, Float64SlicesAreQuantizedWithinHalfAStep) {
  std::vector<double> values(kWideSamples);
  for (size_t i = 0; i < values.size(); ++i)
    values[i] = -3e40 + 7e40 * std::fmod(double(i) * 0.6180339887, 1.0);
  expectKeptThroughTiffs<double>(SampleType::Float64, kWideW, kWideH, values, false);
}

// 16-bit float slices (half; OpenImageIO writes none, writeTiff does), single- and multi-page: read as
// float32, which holds every half value exactly; the pattern's values are all halves.
TEST(SourceImages, HalfFloatSlicesAreReadExactlyAsFloat32) {
  TempDir dir;
  const auto halfPage = [](uint32_t z) {
    const std::vector<float> values = slicePattern<float>(20, 18, z);
    std::vector<uint16_t> bits(values.size());
    for (size_t i = 0; i < values.size(); ++i) bits[i] = Imath::half(values[i]).bits();
    TiffPage page = tiffPage(20, 18, bits);
    page.sampleFormat = 3;
    return page;
  };
  for (uint32_t z = 0; z < 3; ++z) writeTiff(dir.file("half_" + std::to_string(z) + ".tif"), {halfPage(z)});
  auto source = openVolumeSource(dir.file("half_*.tif"));
  EXPECT_EQ(source->info().type, SampleType::Float32);
  expectSlices<float>(*source, 20, 18, 3);
  writeTiff(dir.file("pages.tif"), {halfPage(0), halfPage(1)});
  expectSlices<float>(*openVolumeSource(dir.file("pages.tif")), 20, 18, 2);
  // Float32 slices beside half ones: the same values either way.
  writeImage(dir.file("half_3.tif"), 20, 18, slicePattern<float>(20, 18, 3));
  expectSlices<float>(*openVolumeSource(dir.file("half_*.tif")), 20, 18, 4);
}

// Slices of one width but another signedness are of another type.
TEST(SourceImages, AStackMixingUint32AndInt32SlicesNamesBoth) {
  TempDir dir;
  for (uint32_t z = 0; z < 3; ++z)
    writeImage(dir.file("s" + std::to_string(z) + ".tif"), 5, 4, slicePattern<uint32_t>(5, 4, z));
  writeImage(dir.file("s3.tif"), 5, 4, slicePattern<int32_t>(5, 4, 3));
  const std::string message = errorOf(dir.path().string());
  EXPECT_NE(message.find(dir.file("s3.tif") + " has type int32, but " + dir.file("s0.tif") + " has uint32"),
            std::string::npos)
      << message;
}

// OpenImageIO reads 64-bit samples as zeros, and reports no error, from a tiled TIFF or one a single row high
// (it reads those a tile or a row at a time), and so 17- to 31-bit samples from a tiled TIFF: such slices
// are refused, naming the file. Tiled 8- and 32-bit TIFFs read as they should.
TEST(SourceImages, TiffsWhoseSamplesOpenImageIOReadsAsZerosAreRefused) {
  TempDir dir;
  writeImage(dir.file("tiled64.tif"), 20, 18, slicePattern<double>(20, 18, 0), 1, 16);
  writeImage(dir.file("row64_0.tif"), 20, 1, slicePattern<double>(20, 1, 0));
  writeImage(dir.file("row64_1.tif"), 20, 1, slicePattern<double>(20, 1, 1));
  {
    auto out = OIIO::ImageOutput::create(dir.file("tiled24.tif"));
    OIIO::ImageSpec spec(20, 18, 1, OIIO::TypeDesc::UINT32);
    spec.attribute("oiio:BitsPerSample", 24);
    spec.tile_width = spec.tile_height = 16;
    const std::vector<uint32_t> samples(20 * 18, 0x12345600u);
    ASSERT_TRUE(out->open(dir.file("tiled24.tif"), spec)) << out->geterror();
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT32, samples.data())) << out->geterror();
    ASSERT_TRUE(out->close());
  }
  for (const std::string bits : {"64", "24"}) {
    const std::string message = errorOf(dir.file("tiled" + bits + "*"));
    EXPECT_NE(message.find(dir.file("tiled" + bits + ".tif") + " is a tiled TIFF of " + bits +
                           "-bit samples, which OpenImageIO reads as zeros"),
              std::string::npos)
        << message;
  }
  const std::string message = errorOf(dir.file("row64_*.tif"));
  EXPECT_NE(message.find(dir.file("row64_0.tif") +
                         " is a TIFF of 64-bit samples one row high, which OpenImageIO reads as zeros"),
            std::string::npos)
      << message;

  writeImage(dir.file("tiled32_0.tif"), 20, 18, slicePattern<int32_t>(20, 18, 0), 1, 16);
  writeImage(dir.file("tiled32_1.tif"), 20, 18, slicePattern<int32_t>(20, 18, 1), 1, 16);
  expectSlices<int32_t>(*openVolumeSource(dir.file("tiled32_*.tif")), 20, 18, 2);
  writeImage(dir.file("tiled8_0.tif"), 20, 18, slicePattern<int8_t>(20, 18, 0), 1, 16);
  expectSlices<int8_t>(*openVolumeSource(dir.file("tiled8_*.tif")), 20, 18, 1);
}

// Samples of `bits` bits (1, 2 or 4), w x h, packed as PNG and TIFF store them: the first sample in the high
// bits, each row starting on a byte.
std::vector<uint8_t> packRows(const std::vector<uint8_t>& samples, uint32_t w, uint32_t h, int bits) {
  const size_t rowBytes = (size_t(w) * bits + 7) / 8;
  std::vector<uint8_t> packed(rowBytes * h);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x)
      packed[y * rowBytes + x * bits / 8] |= uint8_t(samples[y * w + x] << (8 - bits - x * bits % 8));
  return packed;
}

// A PNG written byte by byte: `packed` rows as the file stores them (packRows), of `bits` bits per sample and
// PNG color type `colorType` (0: grayscale, 3: palette), after the chunks `before` (PLTE, tRNS).
void writePng(const std::string& path, uint32_t w, uint32_t h, int bits, uint8_t colorType,
              const std::vector<uint8_t>& packed,
              const std::vector<std::pair<std::string, std::vector<uint8_t>>>& before = {}) {
  const size_t rowBytes = packed.size() / h;
  std::vector<uint8_t> rows;
  for (uint32_t y = 0; y < h; ++y) {
    rows.push_back(0);  // filter: none
    rows.insert(rows.end(), packed.begin() + y * rowBytes, packed.begin() + (y + 1) * rowBytes);
  }
  uLongf zipped = compressBound(uLong(rows.size()));
  std::vector<uint8_t> idat(zipped);
  ASSERT_EQ(compress(idat.data(), &zipped, rows.data(), uLong(rows.size())), Z_OK);
  idat.resize(zipped);
  std::vector<uint8_t> file{0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  const auto put32 = [&](uint32_t v) {
    for (int i = 3; i >= 0; --i) file.push_back(uint8_t(v >> (8 * i)));
  };
  const auto chunk = [&](const std::string& type, const std::vector<uint8_t>& data) {
    put32(uint32_t(data.size()));
    const size_t start = file.size();
    file.insert(file.end(), type.begin(), type.end());
    file.insert(file.end(), data.begin(), data.end());
    put32(uint32_t(crc32(0, file.data() + start, uInt(file.size() - start))));
  };
  std::vector<uint8_t> header;
  for (uint32_t v : {w, h})
    for (int i = 3; i >= 0; --i) header.push_back(uint8_t(v >> (8 * i)));
  header.insert(header.end(), {uint8_t(bits), colorType, 0, 0, 0});  // deflate, no filter, no interlace
  chunk("IHDR", header);
  for (const auto& [type, data] : before) chunk(type, data);
  chunk("IDAT", idat);
  chunk("IEND", {});
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(file.data()), file.size());
}

// A grayscale PNG of 1-, 2- or 4-bit samples (OpenImageIO writes none narrower than 8).
void writeNarrowPng(const std::string& path, uint32_t w, uint32_t h, int bits,
                    const std::vector<uint8_t>& samples) {
  writePng(path, w, h, bits, 0, packRows(samples, w, h, bits));
}

// Four 8 x 6 pages of slicePattern<uint8_t>.
std::vector<TiffPage> fourPages() {
  std::vector<TiffPage> pages;
  for (uint32_t z = 0; z < 4; ++z) pages.push_back(tiffPage(8, 6, slicePattern<uint8_t>(8, 6, z)));
  return pages;
}

// OpenImageIO takes a TIFF cut short for one of fewer pages, and reads image data past the end as zeros
// (read_image succeeds): a cut file is refused, naming the page where it is cut.
TEST(SourceImages, ACutMultiPageTiffNamesTheFileAndPage) {
  TempDir dir;
  for (bool directoriesFirst : {false, true}) {
    const std::string path = dir.file(directoriesFirst ? "ahead.tif" : "behind.tif");
    writeTiff(path, fourPages(), directoriesFirst);
    expectSlices<uint8_t>(*openVolumeSource(path), 8, 6, 4);
    // Cut in the middle of page 2's image data: its directory is lost too when it follows the data.
    const uint32_t pageBytes = 8 * 6, cut = directoriesFirst ? 8 + 4 * 114 + 2 * pageBytes + pageBytes / 2
                                                             : 8 + 2 * (pageBytes + 114) + pageBytes / 2;
    std::filesystem::resize_file(path, cut);
    const std::string message = errorOf(path);
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find("page 2"), std::string::npos) << message;
    EXPECT_NE(message.find("cut short"), std::string::npos) << message;
  }
  // Cut in page 1: not taken for a single-page TIFF.
  writeTiff(dir.file("one.tif"), fourPages());
  std::filesystem::resize_file(dir.file("one.tif"), 8 + (48 + 114) + 20);
  const std::string message = errorOf(dir.file("one.tif"));
  EXPECT_NE(message.find("page 1"), std::string::npos) << message;
  EXPECT_EQ(message.find("single-page"), std::string::npos) << message;
}

// A file cut after the source opened it fails the read of the page it lost, naming it, rather than giving
// zeros; a single-page slice cut short is refused when the stack opens.
TEST(SourceImages, ATiffCutAfterOpeningOrASliceCutShortIsAnError) {
  TempDir dir;
  writeTiff(dir.file("pages.tif"), fourPages(), /*directoriesFirst=*/true);
  const auto source = openVolumeSource(dir.file("pages.tif"));
  EXPECT_EQ(readSlab<uint8_t>(*source, 1, 1), slicePattern<uint8_t>(8, 6, 1));
  std::filesystem::resize_file(dir.file("pages.tif"), 8 + 4 * 114 + 2 * 48 + 20);
  try {
    readSlab<uint8_t>(*source, 2, 1);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(dir.file("pages.tif") + " (page 2)"), std::string::npos) << e.what();
  }

  std::filesystem::create_directories(dir.file("stack"));
  for (uint32_t z = 0; z < 3; ++z)
    writeTiff(dir.file("stack/s" + std::to_string(z) + ".tif"),
              {tiffPage(8, 6, slicePattern<uint8_t>(8, 6, z))},
              /*directoriesFirst=*/true);
  std::filesystem::resize_file(dir.file("stack/s1.tif"), 8 + 114 + 30);
  const std::string message = errorOf(dir.file("stack"));
  EXPECT_NE(message.find(dir.file("stack/s1.tif")), std::string::npos) << message;
  EXPECT_NE(message.find("cut short"), std::string::npos) << message;
}

// OpenImageIO widens 12-bit and 4-bit TIFF samples to the type's range; the volume keeps the file's
// values, and slices of different bit depths are refused.
TEST(SourceImages, NarrowBitDepthsKeepTheFilesValues) {
  TempDir dir;
  std::filesystem::create_directories(dir.file("tiff12"));
  std::vector<uint16_t> values12(6 * 4);
  for (size_t i = 0; i < values12.size(); ++i) values12[i] = uint16_t(i * 170 + 3);  // up to 3913
  for (int z = 0; z < 2; ++z)
    writeNarrowImage(dir.file("tiff12/s" + std::to_string(z) + ".tif"), 6, 4, values12, 12);
  auto tiff12 = openVolumeSource(dir.file("tiff12"));
  EXPECT_EQ(tiff12->info().type, SampleType::UInt16);
  EXPECT_EQ(readSlab<uint16_t>(*tiff12, 1, 1), values12);

  std::filesystem::create_directories(dir.file("tiff4"));
  std::vector<uint16_t> values4(8 * 2);
  for (size_t i = 0; i < values4.size(); ++i) values4[i] = uint16_t(i % 16);
  writeNarrowImage(dir.file("tiff4/a.tif"), 8, 2, values4, 4);
  auto tiff4 = openVolumeSource(dir.file("tiff4"));
  EXPECT_EQ(tiff4->info().type, SampleType::UInt8);
  EXPECT_EQ(tiff4->info().valueMax, 15.0);
  const auto read4 = readSlab<uint8_t>(*tiff4, 0, 1);
  EXPECT_EQ(std::vector<uint16_t>(read4.begin(), read4.end()), values4);

  std::filesystem::create_directories(dir.file("tiff24"));
  std::vector<uint32_t> values24(5 * 3);
  for (size_t i = 0; i < values24.size(); ++i) values24[i] = uint32_t(i * 1118481 + 7);  // up to 15658741
  values24[1] = 0xffffff;
  {
    // OpenImageIO writes the high 24 bits of the uint32 samples it is given.
    auto out = OIIO::ImageOutput::create(dir.file("tiff24/a.tif"));
    OIIO::ImageSpec spec(5, 3, 1, OIIO::TypeDesc::UINT32);
    spec.attribute("oiio:BitsPerSample", 24);
    std::vector<uint32_t> widened(values24.size());
    for (size_t i = 0; i < values24.size(); ++i) widened[i] = values24[i] << 8;
    ASSERT_TRUE(out->open(dir.file("tiff24/a.tif"), spec)) << out->geterror();
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT32, widened.data())) << out->geterror();
    ASSERT_TRUE(out->close());
  }
  auto tiff24 = openVolumeSource(dir.file("tiff24"));
  EXPECT_EQ(tiff24->info().type, SampleType::UInt32);
  EXPECT_EQ(readSlab<uint32_t>(*tiff24, 0, 1), values24);

  // Signed samples narrower than their type: a 4-bit int8 TIFF.
  writeTiff(dir.file("signed4.tif"), {TiffPage{4, 1, 4, 1, {0x1f, 0x7a}, 2}});
  std::string message = errorOf(dir.file("signed4*.tif"));
  EXPECT_NE(message.find(dir.file("signed4.tif") + " has signed 4-bit samples"), std::string::npos)
      << message;

  writeImage(dir.file("tiff12/s2.tif"), 6, 4, slicePattern<uint16_t>(6, 4, 2));  // 16 bits
  message = errorOf(dir.file("tiff12"));
  EXPECT_NE(message.find("16-bit samples, but " + dir.file("tiff12/s0.tif") + " has 12-bit ones"),
            std::string::npos)
      << message;
}

// A MinIsWhite TIFF (photometric 0: viewers show 0 as white) keeps its stored values, whatever its bit
// depth (OpenImageIO inverts 8-bit and narrower samples only), with a note; a stack mixing MinIsWhite and
// MinIsBlack slices is refused.
TEST(SourceImages, MinIsWhiteTiffsKeepTheirStoredValues) {
  TempDir dir;
  std::filesystem::create_directories(dir.file("white8"));
  for (uint32_t z = 0; z < 3; ++z)
    writeTiff(dir.file("white8/s" + std::to_string(z) + ".tif"),
              {tiffPage(7, 5, slicePattern<uint8_t>(7, 5, z), /*photometric=*/0)});
  const auto white8 = openVolumeSource(dir.file("white8"));
  expectSlices<uint8_t>(*white8, 7, 5, 3);
  EXPECT_EQ(white8->info().notes.size(), 1u);
  for (const std::string& note : white8->info().notes)
    EXPECT_NE(note.find("MinIsWhite"), std::string::npos) << note;

  std::vector<TiffPage> pages16;
  for (uint32_t z = 0; z < 3; ++z) pages16.push_back(tiffPage(6, 4, slicePattern<uint16_t>(6, 4, z), 0));
  writeTiff(dir.file("white16.tif"), pages16);
  expectSlices<uint16_t>(*openVolumeSource(dir.file("white16.tif")), 6, 4, 3);

  // 1-bit: the stored bits 1011 0000.
  std::vector<TiffPage> pages1(2, TiffPage{8, 1, 1, 0, {0b10110000}});
  writeTiff(dir.file("white1.tif"), pages1);
  const auto white1 = openVolumeSource(dir.file("white1.tif"));
  EXPECT_EQ(white1->info().valueMax, 1.0);
  EXPECT_EQ(readSlab<uint8_t>(*white1, 1, 1), (std::vector<uint8_t>{1, 0, 1, 1, 0, 0, 0, 0}));

  // Signed and floating-point samples, which OpenImageIO does not invert either.
  std::vector<TiffPage> pagesInt8, pagesFloat64;
  for (uint32_t z = 0; z < 3; ++z) {
    pagesInt8.push_back(tiffPage(6, 4, slicePattern<int8_t>(6, 4, z), 0));
    pagesFloat64.push_back(tiffPage(6, 4, slicePattern<double>(6, 4, z), 0));
  }
  writeTiff(dir.file("white_int8.tif"), pagesInt8);
  expectSlices<int8_t>(*openVolumeSource(dir.file("white_int8.tif")), 6, 4, 3);
  writeTiff(dir.file("white_float64.tif"), pagesFloat64);
  expectSlices<double>(*openVolumeSource(dir.file("white_float64.tif")), 6, 4, 3);

  writeTiff(dir.file("white8/s3.tif"), {tiffPage(7, 5, slicePattern<uint8_t>(7, 5, 3), /*photometric=*/1)});
  std::string message = errorOf(dir.file("white8"));
  EXPECT_NE(message.find(dir.file("white8/s3.tif") + " is MinIsBlack"), std::string::npos) << message;
  EXPECT_NE(message.find(dir.file("white8/s0.tif") + " is MinIsWhite"), std::string::npos) << message;
  pages16[1].photometric = 1;
  writeTiff(dir.file("mixed16.tif"), pages16);
  message = errorOf(dir.file("mixed16.tif"));
  EXPECT_NE(message.find(dir.file("mixed16.tif") + " (page 1) is MinIsBlack"), std::string::npos) << message;
}

// OpenImageIO widens 1-, 2- and 4-bit PNGs to 8 bits (a bilevel slice reads 0 and 255) and does not say so;
// they keep the file's values as narrow TIFFs do, and a bilevel PNG stacks with a bilevel TIFF.
TEST(SourceImages, BilevelAndNarrowPngsKeepTheFilesValues) {
  TempDir dir;
  std::filesystem::create_directories(dir.file("bilevel"));
  std::vector<std::vector<uint8_t>> masks;
  for (uint32_t z = 0; z < 3; ++z) {
    std::vector<uint8_t> mask(13 * 3);  // 13 wide: rows end inside a byte
    for (size_t i = 0; i < mask.size(); ++i) mask[i] = uint8_t((i * 7 + z) % 3 == 0);
    masks.push_back(mask);
    writeNarrowPng(dir.file("bilevel/m" + std::to_string(z) + ".png"), 13, 3, 1, mask);
  }
  writeTiff(dir.file("bilevel/m3.tif"), {TiffPage{13, 3, 1, 1, packRows(masks[0], 13, 3, 1)}});
  masks.push_back(masks[0]);
  const auto bilevel = openVolumeSource(dir.file("bilevel"));
  EXPECT_EQ(bilevel->info().type, SampleType::UInt8);
  EXPECT_EQ(bilevel->info().valueMax, 1.0);
  for (uint32_t z = 0; z < 4; ++z) EXPECT_EQ(readSlab<uint8_t>(*bilevel, z, 1), masks[z]) << "slice " << z;

  for (int bits : {2, 4}) {
    std::vector<uint8_t> values(5 * 2);
    for (size_t i = 0; i < values.size(); ++i) values[i] = uint8_t((i * 3) % (1u << bits));
    const std::string path = dir.file("narrow" + std::to_string(bits) + "_0.png");
    writeNarrowPng(path, 5, 2, bits, values);
    const auto narrow = openVolumeSource(dir.file("narrow" + std::to_string(bits) + "_*.png"));
    EXPECT_EQ(narrow->info().valueMax, double((1u << bits) - 1)) << bits << " bits";
    EXPECT_EQ(readSlab<uint8_t>(*narrow, 0, 1), values) << bits << " bits";
  }

  writeImage(dir.file("bilevel/m4.png"), 13, 3, slicePattern<uint8_t>(13, 3, 4));  // 8 bits
  const std::string message = errorOf(dir.file("bilevel"));
  EXPECT_NE(message.find(dir.file("bilevel/m4.png") + " has 8-bit samples, but " +
                         dir.file("bilevel/m0.png") + " has 1-bit ones"),
            std::string::npos)
      << message;
}

// `gray` (a sample a pixel) as RGB, R = G = B, or with 4 channels as RGBA with an opaque alpha, or with 2 as
// gray with an opaque alpha.
template <typename T>
std::vector<T> asColor(const std::vector<T>& gray, int channels) {
  std::vector<T> color;
  for (T v : gray) {
    color.insert(color.end(), channels == 2 ? 1 : 3, v);
    if (channels != 3) color.push_back(std::numeric_limits<T>::max());
  }
  return color;
}

// A PNG palette of `entries` grays, entry i being 255 - i * 255 / (entries - 1): an index is not its gray.
std::vector<uint8_t> grayPalette(int entries) {
  std::vector<uint8_t> palette;
  for (int i = 0; i < entries; ++i) palette.insert(palette.end(), 3, uint8_t(255 - i * 255 / (entries - 1)));
  return palette;
}

// Gray content saved as RGB or RGBA (8 or 16 bits, PNG or TIFF, slices or pages), as a palette PNG of grays
// (OpenImageIO expands it to RGB, or RGBA with a tRNS chunk), or mixed with gray slices, converts to the
// same store as the gray slices, with a note.
TEST(SourceImages, GraySlicesSavedAsColorOrPaletteImagesConvertLikeGrayOnes) {
  TempDir dir;
  constexpr uint32_t w = 11, h = 9, depth = 4;
  const std::vector<std::string> colorStacks = {"gray_alpha", "rgb",           "rgba",
                                                "palette",    "palette_alpha", "mixed"};
  for (const std::string& name : colorStacks) std::filesystem::create_directories(dir.file(name));
  for (const std::string name : {"gray", "gray16", "rgb16"})
    std::filesystem::create_directories(dir.file(name));
  std::vector<std::vector<uint16_t>> rgb16Pages;
  for (uint32_t z = 0; z < depth; ++z) {
    const std::string slice = "/s" + std::to_string(z) + ".png";
    const std::vector<uint8_t> gray = slicePattern<uint8_t>(w, h, z);
    writeImage(dir.file("gray" + slice), w, h, gray);
    writeImage(dir.file("gray_alpha" + slice), w, h, asColor(gray, 2), 2);
    writeImage(dir.file("rgb" + slice), w, h, asColor(gray, 3), 3);
    writeImage(dir.file("rgba" + slice), w, h, asColor(gray, 4), 4);
    std::vector<uint8_t> indexes(gray.size());
    for (size_t i = 0; i < gray.size(); ++i) indexes[i] = uint8_t(255 - gray[i]);
    writePng(dir.file("palette" + slice), w, h, 8, 3, indexes, {{"PLTE", grayPalette(256)}});
    writePng(dir.file("palette_alpha" + slice), w, h, 8, 3, indexes,
             {{"PLTE", grayPalette(256)}, {"tRNS", std::vector<uint8_t>(256, 255)}});
    if (z % 2)
      writeImage(dir.file("mixed" + slice), w, h, asColor(gray, 3), 3);
    else
      writeImage(dir.file("mixed" + slice), w, h, gray);
    const std::vector<uint16_t> gray16 = slicePattern<uint16_t>(w, h, z);
    writeImage(dir.file("gray16/s" + std::to_string(z) + ".tif"), w, h, gray16);
    writeImage(dir.file("rgb16/s" + std::to_string(z) + ".tif"), w, h, asColor(gray16, 3), 3);
    rgb16Pages.push_back(asColor(gray16, 4));
  }
  writePages(dir.file("rgba16_pages.tif"), w, h, rgb16Pages, 4);

  const std::vector<double> gray = level0Data(*convertAndOpen(dir, dir.file("gray")));
  for (const std::string& name : colorStacks) {
    const auto source = openVolumeSource(dir.file(name));
    EXPECT_EQ(source->info().type, SampleType::UInt8) << name;
    ASSERT_EQ(source->info().notes.size(), 1u) << name;
    const std::string said = name == "mixed"
                                 ? "2 of the 4 slices (first: " + dir.file("mixed/s1.png") + ") are"
                                 : "the slices are";
    EXPECT_NE(source->info().notes[0].find(said + " RGB, RGBA or gray+alpha images, read as gray"),
              std::string::npos)
        << source->info().notes[0];
    EXPECT_EQ(level0Data(*convertAndOpen(dir, dir.file(name))), gray) << name;
  }
  const std::vector<double> gray16 = level0Data(*convertAndOpen(dir, dir.file("gray16")));
  for (const std::string name : {"rgb16", "rgba16_pages.tif"}) {
    EXPECT_EQ(openVolumeSource(dir.file(name))->info().type, SampleType::UInt16) << name;
    EXPECT_EQ(level0Data(*convertAndOpen(dir, dir.file(name))), gray16) << name;
  }

  // Palette TIFFs of 8- and 4-bit indexes whose color maps hold grays (16 bits an entry, g * 257 for the
  // 8-bit gray g): they read as the 8-bit grays, like a palette PNG's.
  const auto grayColorMap = [](int entries) {
    std::vector<uint16_t> map;
    for (int channel = 0; channel < 3; ++channel)
      for (int i = 0; i < entries; ++i) map.push_back(uint16_t(257 * (255 - i * 255 / (entries - 1))));
    return map;
  };
  std::filesystem::create_directories(dir.file("palette_tiff"));
  for (uint32_t z = 0; z < depth; ++z) {
    const std::vector<uint8_t> slice = slicePattern<uint8_t>(w, h, z);
    std::vector<uint8_t> indexes(slice.size());
    for (size_t i = 0; i < slice.size(); ++i) indexes[i] = uint8_t(255 - slice[i]);
    TiffPage page = tiffPage(w, h, indexes, /*photometric=*/3);
    page.colorMap = grayColorMap(256);
    writeTiff(dir.file("palette_tiff/s" + std::to_string(z) + ".tif"), {page});
  }
  EXPECT_EQ(level0Data(*convertAndOpen(dir, dir.file("palette_tiff"))), gray);
  std::vector<uint8_t> indexes4(5 * 2), grays4(indexes4.size());
  for (size_t i = 0; i < indexes4.size(); ++i) {
    indexes4[i] = uint8_t(i * 7 % 16);
    grays4[i] = uint8_t(255 - indexes4[i] * 17);
  }
  TiffPage page4{5, 2, 4, 3, packRows(indexes4, 5, 2, 4)};
  page4.colorMap = grayColorMap(16);
  writeTiff(dir.file("palette4_0.tif"), {page4});
  const auto palette4 = openVolumeSource(dir.file("palette4_*.tif"));
  EXPECT_EQ(palette4->info().type, SampleType::UInt8);
  EXPECT_EQ(readSlab<uint8_t>(*palette4, 0, 1), grays4);

  // A palette of 2-bit indexes: the grays are the palette's, of 8 bits.
  std::vector<uint8_t> indexes(5 * 2), grays(indexes.size());
  for (size_t i = 0; i < indexes.size(); ++i) {
    indexes[i] = uint8_t(i * 3 % 4);
    grays[i] = uint8_t(255 - indexes[i] * 85);
  }
  writePng(dir.file("palette2_0.png"), 5, 2, 2, 3, packRows(indexes, 5, 2, 2), {{"PLTE", grayPalette(4)}});
  const auto palette2 = openVolumeSource(dir.file("palette2_*.png"));
  EXPECT_EQ(palette2->info().valueMax, 255.0);
  EXPECT_EQ(readSlab<uint8_t>(*palette2, 0, 1), grays);
}

// The message of reading slice z of `source` alone; "" if it reads.
std::string readErrorOf(VolumeSource& source, uint32_t z) {
  try {
    readSlab<uint8_t>(source, z, 1);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// Whether a color slice is gray takes its pixels: the stack opens, and reading the slice that is not fails,
// naming it and its first pixel that is not gray.
TEST(SourceImages, AColorSliceThatIsNotGrayIsRefusedNamingThePixel) {
  TempDir dir;
  std::vector<std::vector<uint8_t>> grayAlpha, rgb, rgba;
  for (uint32_t z = 0; z < 3; ++z) {
    grayAlpha.push_back(asColor(slicePattern<uint8_t>(6, 5, z), 2));
    rgb.push_back(asColor(slicePattern<uint8_t>(6, 5, z), 3));
    rgba.push_back(asColor(slicePattern<uint8_t>(6, 5, z), 4));
  }
  const size_t at = 2 * 6 + 4;  // pixel (4, 2)
  const uint8_t r = rgb[1][3 * at];
  rgb[1][3 * at + 1] = uint8_t(r + 1);
  rgba[2][4 * at + 3] = 0;
  grayAlpha[1][2 * at + 1] = 7;
  for (uint32_t z = 0; z < 3; ++z) {
    writeImage(dir.file("ga" + std::to_string(z) + ".png"), 6, 5, grayAlpha[z], 2);
    writeImage(dir.file("rgb" + std::to_string(z) + ".png"), 6, 5, rgb[z], 3);
    writeImage(dir.file("rgba" + std::to_string(z) + ".png"), 6, 5, rgba[z], 4);
  }
  writePages(dir.file("pages.tif"), 6, 5, rgb, 3);

  const auto source = openVolumeSource(dir.file("rgb*.png"));
  EXPECT_EQ(readErrorOf(*source, 0), "");
  const std::string differ = " has color channels that differ at pixel (4, 2): R " + std::to_string(r) +
                             ", G " + std::to_string(r + 1) + ", B " + std::to_string(r) +
                             "; expected a grayscale image, or color channels equal at every pixel";
  std::string message = readErrorOf(*source, 1);
  EXPECT_NE(message.find(dir.file("rgb1.png") + differ), std::string::npos) << message;
  message = readErrorOf(*openVolumeSource(dir.file("pages.tif")), 1);
  EXPECT_NE(message.find(dir.file("pages.tif") + " (page 1)" + differ), std::string::npos) << message;
  EXPECT_THROW(convertAndOpen(dir, dir.file("pages.tif")), Error);

  struct AlphaCase {
    std::string stack;
    uint32_t slice;
    int alpha;
  };
  for (const AlphaCase& c : {AlphaCase{"ga", 1, 7}, AlphaCase{"rgba", 2, 0}}) {
    message = readErrorOf(*openVolumeSource(dir.file(c.stack + "*.png")), c.slice);
    EXPECT_NE(
        message.find(dir.file(c.stack + std::to_string(c.slice) + ".png") + " has alpha " +
                     std::to_string(c.alpha) +
                     " at pixel (4, 2); expected a grayscale image, or alpha opaque (255) at every pixel"),
        std::string::npos)
        << message;
  }
}

// A multi-page TIFF among the slices of a folder would give its first page only.
TEST(SourceImages, AMultiPageTiffAmongSlicesIsRefused) {
  TempDir dir;
  std::filesystem::create_directories(dir.file("stack"));
  writeMultiPage<uint8_t>(dir.file("stack/pages.tif"), 5, 4, 3);
  const std::string message = errorOf(dir.file("stack"));
  EXPECT_NE(message.find(dir.file("stack/pages.tif") + " has 3 pages"), std::string::npos) << message;
}

TEST(SourceImages, GapsAndRepeatsInTheNumberingAreNoted) {
  EXPECT_EQ(sliceNumberingNote({"d/s0.png", "d/s1.png", "d/s2.png"}), "");
  EXPECT_EQ(sliceNumberingNote({"d/a.png", "d/s1.png"}), "");  // not numbered
  EXPECT_EQ(
      sliceNumberingNote({"d/s0.png", "d/s1.png", "d/s3.png", "d/s4.png", "d/s9.png"}),
      "slices numbered 0 to 9 lack 5 number(s) (2, 5, 6, ...); the volume has 5 slices, one after another");
  EXPECT_EQ(sliceNumberingNote({"d/s1.png", "d/s01.png", "d/s2.png"}),
            "slices d/s1.png and d/s01.png have the same number, 1; both are in the volume");
  // The note reaches the source's info.
  TempDir dir;
  std::filesystem::create_directories(dir.file("gap"));
  for (int z : {0, 1, 3})
    writeImage(dir.file("gap/s" + std::to_string(z) + ".png"), 4, 3, slicePattern<uint8_t>(4, 3, z));
  const auto source = openVolumeSource(dir.file("gap"));
  ASSERT_EQ(source->info().notes.size(), 1u);
  EXPECT_NE(source->info().notes[0].find("lack 1 number(s) (2)"), std::string::npos)
      << source->info().notes[0];
}

TEST(SourceImages, SliceNameOrder) {
  EXPECT_TRUE(sliceNameLess("s2.png", "s10.png"));
  EXPECT_FALSE(sliceNameLess("s10.png", "s2.png"));
  EXPECT_TRUE(sliceNameLess("s002.png", "s010.png"));
  EXPECT_TRUE(sliceNameLess("a.png", "b.png"));
  EXPECT_TRUE(sliceNameLess("s9_b.png", "s10_a.png"));
  EXPECT_FALSE(sliceNameLess("s1.png", "s1.png"));
  EXPECT_TRUE(sliceNameLess("s1.png", "s01.png") != sliceNameLess("s01.png", "s1.png"));
}

// A multi-page TIFF's pages are checked against its first by their directories (tiffPageLayouts), and those
// stored otherwise through OpenImageIO: one of another size, sample format or photometric interpretation is
// refused when the TIFF opens, naming its page; pages stored alike open without a read of their own.
TEST(SourceImages, AMultiPageTiffsPagesStoredUnlikeItsFirstAreNamed) {
  TempDir dir;
  std::vector<TiffPage> pages;
  for (uint32_t z = 0; z < 5; ++z) pages.push_back(tiffPage<uint16_t>(6, 4, slicePattern<uint16_t>(6, 4, z)));
  const std::string alike = dir.file("alike.tif");
  writeTiff(alike, pages);
  const auto layouts = tiffPageLayouts(alike);
  ASSERT_TRUE(layouts);
  ASSERT_EQ(layouts->size(), 5u);
  EXPECT_EQ((*layouts)[0].width, 6u);
  EXPECT_EQ((*layouts)[0].height, 4u);
  EXPECT_EQ((*layouts)[0].bitsPerSample, 16u);
  for (const TiffPageLayout& layout : *layouts) EXPECT_EQ(layout, (*layouts)[0]);
  expectSlices<uint16_t>(*openVolumeSource(alike), 6, 4, 5);

  const auto refusedFor = [&](const std::string& name, TiffPage page, const std::string& expected) {
    std::vector<TiffPage> unlike = pages;
    unlike[3] = std::move(page);
    const std::string path = dir.file(name);
    writeTiff(path, unlike);
    EXPECT_NE((*tiffPageLayouts(path))[3], (*tiffPageLayouts(path))[0]) << name;
    const std::string message = errorOf(path);
    EXPECT_NE(message.find(path + " (page 3)"), std::string::npos) << name << ": " << message;
    EXPECT_NE(message.find(expected), std::string::npos) << name << ": " << message;
  };
  refusedFor("size.tif", tiffPage<uint16_t>(6, 5, slicePattern<uint16_t>(6, 5, 3)), "6x5");
  refusedFor("signed.tif", tiffPage<int16_t>(6, 4, slicePattern<int16_t>(6, 4, 3)), "int16");
  refusedFor("white.tif", tiffPage<uint16_t>(6, 4, slicePattern<uint16_t>(6, 4, 3), 0), "MinIsWhite");
  writeFile(dir.file("text.tif"), "not a TIFF at all");
  EXPECT_EQ(tiffPageLayouts(dir.file("text.tif")), std::nullopt);
}

TEST(SourceImages, DifferentSizeOrTypeNamesTheSlice) {
  TempDir dir;
  for (uint32_t z = 0; z < 4; ++z)
    writeImage(dir.file("s" + std::to_string(z) + ".png"), 6, 6, slicePattern<uint8_t>(6, 6, z));
  writeImage(dir.file("s4.png"), 6, 7, slicePattern<uint8_t>(6, 7, 4));
  std::string message = errorOf(dir.path().string());
  EXPECT_NE(message.find(dir.file("s4.png")), std::string::npos) << message;
  EXPECT_NE(message.find("6x7"), std::string::npos) << message;

  writeImage(dir.file("s4.png"), 6, 6, slicePattern<uint16_t>(6, 6, 4));
  message = errorOf(dir.path().string());
  EXPECT_NE(message.find(dir.file("s4.png")), std::string::npos) << message;
  EXPECT_NE(message.find("uint16"), std::string::npos) << message;
}

TEST(SourceImages, UnreadableOrMultiChannelNamesTheFile) {
  TempDir dir;
  writeImage(dir.file("s0.png"), 6, 6, slicePattern<uint8_t>(6, 6, 0));
  std::ofstream(dir.file("s1.png")) << "this is not a PNG file";
  std::string message = errorOf(dir.file("s*.png"));
  EXPECT_NE(message.find(dir.file("s1.png")), std::string::npos) << message;

  // Channels that are neither gray, gray and alpha, RGB nor RGBA: refused when the stack opens.
  writeImage(dir.file("t0.tif"), 6, 6, slicePattern<uint8_t>(6, 6, 0));
  writeImage(dir.file("t1.tif"), 6, 6, std::vector<uint8_t>(6 * 6 * 5, 9), 5);
  message = errorOf(dir.file("t*.tif"));
  EXPECT_NE(message.find(dir.file("t1.tif")), std::string::npos) << message;
  EXPECT_NE(message.find("5 channels"), std::string::npos) << message;

  // A slice broken after opening fails the read, naming it.
  writeImage(dir.file("s1.png"), 6, 6, slicePattern<uint8_t>(6, 6, 1));
  auto source = openVolumeSource(dir.file("s*.png"));
  std::ofstream(dir.file("s1.png"), std::ios::trunc) << "gone";
  std::vector<std::byte> slice(36);
  try {
    source->readSlab(1, 1, slice);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(dir.file("s1.png")), std::string::npos) << e.what();
  }
}

TEST(SourceImages, BadSpecsAreNamed) {
  TempDir dir;
  writeImage(dir.file("single.tif"), 4, 4, slicePattern<uint8_t>(4, 4, 0));
  std::string message = errorOf(dir.file("single.tif"));
  EXPECT_NE(message.find(dir.file("single.tif")), std::string::npos) << message;
  EXPECT_NE(message.find("single-page"), std::string::npos) << message;

  message = errorOf(dir.file("nothing_*.png"));
  EXPECT_NE(message.find(dir.file("nothing_*.png")), std::string::npos) << message;
  EXPECT_NE(message.find("matches no files"), std::string::npos) << message;

  fs::create_directories(dir.file("empty"));
  message = errorOf(dir.file("empty"));
  EXPECT_NE(message.find(dir.file("empty")), std::string::npos) << message;

  message = errorOf(dir.file("missing.tif"));
  EXPECT_NE(message.find(dir.file("missing.tif")), std::string::npos) << message;
  EXPECT_NE(message.find("no such file"), std::string::npos) << message;
}

}  // namespace
}  // namespace ropecast
