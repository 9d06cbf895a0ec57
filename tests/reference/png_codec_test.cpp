// PNG decoding through libpng (reference/png_codec.h): every layout PNG has reads to the floats OpenImageIO's
// reader gives, and damaged files are refused with their name.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <png.h>

#include "core/error.h"
#include "reference/image_codec.h"
#include "reference/image_io.h"
#include "reference/png_codec.h"
#include "tests/render/testutil_gl.h"

namespace ropecast {
namespace {

struct PngLayoutCase {
  const char* name;
  int colorType;
  int bitDepth;
  bool interlaced = false;
  bool transparency = false;  // a tRNS chunk: palette alphas, or the gray or RGB value that is transparent
  double gamma = 0.0;         // a gAMA chunk when > 0 (the readers apply none)
};

// Writes a PNG of the case's layout through libpng's full API (the simplified one writes only some), its
// bytes a pattern that reaches every sample value of small depths.
void writeCase(const std::string& path, const PngLayoutCase& layout, uint32_t width, uint32_t height) {
  FILE* file = std::fopen(path.c_str(), "wb");
  ASSERT_NE(file, nullptr) << path;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, file);
  png_set_IHDR(png, info, width, height, layout.bitDepth, layout.colorType,
               layout.interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_color palette[16];
  png_byte paletteAlpha[16];
  for (int i = 0; i < 16; ++i) {
    palette[i] = {png_byte(i * 16), png_byte(255 - i * 13), png_byte(i * i)};
    paletteAlpha[i] = png_byte(i * 17);
  }
  png_color_16 transparent{};
  transparent.gray = 3;
  transparent.red = 5, transparent.green = 42, transparent.blue = 79;
  if (layout.colorType == PNG_COLOR_TYPE_PALETTE) {
    png_set_PLTE(png, info, palette, 16);
    if (layout.transparency) png_set_tRNS(png, info, paletteAlpha, 16, nullptr);
  } else if (layout.transparency) {
    png_set_tRNS(png, info, nullptr, 0, &transparent);
  }
  if (layout.gamma > 0.0) png_set_gAMA(png, info, layout.gamma);
  png_write_info(png, info);
  const int channels = layout.colorType == PNG_COLOR_TYPE_RGB_ALPHA    ? 4
                       : layout.colorType == PNG_COLOR_TYPE_RGB        ? 3
                       : layout.colorType == PNG_COLOR_TYPE_GRAY_ALPHA ? 2
                                                                       : 1;
  const size_t rowBytes = (size_t(width) * channels * layout.bitDepth + 7) / 8;
  std::vector<png_byte> bytes(rowBytes * height);
  for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = png_byte(i * 37 + 5);
  std::vector<png_bytep> rows(height);
  for (uint32_t y = 0; y < height; ++y) rows[y] = bytes.data() + y * rowBytes;
  png_set_rows(png, info, rows.data());
  png_write_image(png, rows.data());
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(file);
}

TEST(PngCodec, EveryLayoutReadsAsOpenImageIoReadsIt) {
  const auto dir = test::freshTempDir();
  const PngLayoutCase cases[] = {
      {"gray1", PNG_COLOR_TYPE_GRAY, 1},
      {"gray2_interlaced", PNG_COLOR_TYPE_GRAY, 2, true},
      {"gray4", PNG_COLOR_TYPE_GRAY, 4},
      {"gray8_transparent", PNG_COLOR_TYPE_GRAY, 8, false, true},
      {"gray16", PNG_COLOR_TYPE_GRAY, 16},
      {"gray_alpha8", PNG_COLOR_TYPE_GRAY_ALPHA, 8},
      {"gray_alpha16", PNG_COLOR_TYPE_GRAY_ALPHA, 16},
      {"rgb8_linear_gamma_interlaced", PNG_COLOR_TYPE_RGB, 8, true, false, 1.0},
      {"rgb8_transparent", PNG_COLOR_TYPE_RGB, 8, false, true},
      {"rgb16", PNG_COLOR_TYPE_RGB, 16},
      {"rgba8", PNG_COLOR_TYPE_RGB_ALPHA, 8},
      {"rgba16_interlaced", PNG_COLOR_TYPE_RGB_ALPHA, 16, true},
      {"palette4", PNG_COLOR_TYPE_PALETTE, 4},
      {"palette4_alpha", PNG_COLOR_TYPE_PALETTE, 4, false, true},
  };
  for (const PngLayoutCase& layout : cases) {
    const std::string path = (dir / (std::string(layout.name) + ".png")).string();
    writeCase(path, layout, 13, 7);
    ASSERT_TRUE(hasPngSignature(path)) << layout.name;
    const FloatImage ours = decodePng(path);
    const FloatImage theirs = decodeImage(path);  // OpenImageIO's reader
    EXPECT_EQ(ours.width, 13u) << layout.name;
    EXPECT_EQ(ours.height, 7u) << layout.name;
    EXPECT_EQ(ours.channels, theirs.channels) << layout.name;
    EXPECT_EQ(ours.pixels, theirs.pixels) << layout.name;
    EXPECT_EQ(readImage(path).pixels, ours.pixels) << layout.name;
  }
}

// A cut-off file, a damaged one and a file that only claims to be PNG are refused with the file's name.
TEST(PngCodec, DamagedFilesAreRefusedWithTheirName) {
  const auto dir = test::freshTempDir();
  const std::string whole = (dir / "whole.png").string();
  writeCase(whole, {"rgb8", PNG_COLOR_TYPE_RGB, 8}, 64, 64);
  std::ifstream in(whole, std::ios::binary);
  const std::vector<char> bytes{std::istreambuf_iterator<char>(in), {}};
  const auto written = [&](const char* name, std::vector<char> content) {
    const std::string path = (dir / name).string();
    std::ofstream(path, std::ios::binary).write(content.data(), std::streamsize(content.size()));
    return path;
  };
  std::vector<char> damaged = bytes;
  damaged[bytes.size() / 2] ^= 0x5a;  // inside the image data: a bad CRC
  const std::vector<char> signatureOnly(bytes.begin(), bytes.begin() + 8);
  for (const std::string& path :
       {written("cut.png", std::vector<char>(bytes.begin(), bytes.begin() + bytes.size() / 2)),
        written("damaged.png", damaged), written("signature_only.png", signatureOnly)}) {
    ASSERT_TRUE(hasPngSignature(path)) << path;
    try {
      decodePng(path);
      ADD_FAILURE() << path << " was read";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
  EXPECT_FALSE(hasPngSignature(written("text.png", {'n', 'o', 't', ' ', 'a', ' ', 'p', 'n', 'g'})));
  EXPECT_FALSE(hasPngSignature(written("empty.png", {})));
  EXPECT_FALSE(hasPngSignature((dir / "missing.png").string()));
  EXPECT_THROW(readImage((dir / "text.png").string()), Error);  // OpenImageIO's turn: it refuses too
}

}  // namespace
}  // namespace ropecast
