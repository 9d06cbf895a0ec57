#include "reference/png_codec.h"

#include <bit>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <memory>

#include <png.h>

#include "core/error.h"

namespace ropecast {

namespace {

// libpng's reading state. Its error handler jumps back into the function that called setjmp, skipping
// destructors on the way: the calls that may fail run in functions that hold nothing with one (readLayout,
// readRows), and this struct, which frees libpng's state, lives in their caller.
struct PngReader {
  png_structp png = nullptr;
  png_infop info = nullptr;
  char message[256] = "";
  ~PngReader() { png_destroy_read_struct(&png, info ? &info : nullptr, nullptr); }
};

[[noreturn]] void onPngError(png_structp png, png_const_charp message) {
  auto* reader = static_cast<PngReader*>(png_get_error_ptr(png));
  std::snprintf(reader->message, sizeof reader->message, "%s", message);
  png_longjmp(png, 1);
}

void onPngWarning(png_structp, png_const_charp) {}  // a damaged ancillary chunk: OpenImageIO reads on too

// The decoded rows' layout: 8- or 16-bit samples, 1 to 4 channels.
struct PngLayout {
  png_uint_32 width = 0, height = 0;
  int channels = 0, bitDepth = 0;
  size_t rowBytes = 0;
};

// Reads the header and asks for the expansions that make every PNG 8- or 16-bit gray, gray+alpha, RGB or RGBA
// in native byte order, without gamma (as OpenImageIO's reader does).
bool readLayout(PngReader& reader, FILE* file, PngLayout& layout) {
  if (setjmp(png_jmpbuf(reader.png))) return false;
  png_init_io(reader.png, file);
  png_read_info(reader.png, reader.info);
  const int colorType = png_get_color_type(reader.png, reader.info);
  const int bitDepth = png_get_bit_depth(reader.png, reader.info);
  if (colorType == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(reader.png);
  if (colorType == PNG_COLOR_TYPE_GRAY && bitDepth < 8) png_set_expand_gray_1_2_4_to_8(reader.png);
  if (png_get_valid(reader.png, reader.info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(reader.png);
  if (bitDepth == 16 && std::endian::native == std::endian::little) png_set_swap(reader.png);
  png_set_interlace_handling(reader.png);
  png_read_update_info(reader.png, reader.info);
  layout.width = png_get_image_width(reader.png, reader.info);
  layout.height = png_get_image_height(reader.png, reader.info);
  layout.channels = png_get_channels(reader.png, reader.info);
  layout.bitDepth = png_get_bit_depth(reader.png, reader.info);
  layout.rowBytes = png_get_rowbytes(reader.png, reader.info);
  return true;
}

bool readRows(PngReader& reader, png_bytepp rows) {
  if (setjmp(png_jmpbuf(reader.png))) return false;
  png_read_image(reader.png, rows);
  png_read_end(reader.png, nullptr);
  return true;
}

using FileHandle = std::unique_ptr<FILE, int (*)(FILE*)>;

FileHandle openForReading(const std::string& path) {
  return FileHandle(std::fopen(path.c_str(), "rb"), &std::fclose);
}

}  // namespace

std::vector<unsigned char> encodePng(const std::string& where, const std::string& path,
                                     const ImageEncoding& encoding, const void* pixels) {
  static constexpr png_uint_32 kFormats[] = {PNG_FORMAT_GRAY, PNG_FORMAT_GA, PNG_FORMAT_RGB, PNG_FORMAT_RGBA};
  if (encoding.floatSamples || encoding.channels < 1 || encoding.channels > 4)
    throw Error(where + ": '" + path + "': PNG holds 1 to 4 channels of 8-bit samples, not " +
                std::to_string(encoding.channels) + (encoding.floatSamples ? " of floats" : ""));
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = encoding.width;
  image.height = encoding.height;
  image.format = kFormats[encoding.channels - 1];
  png_alloc_size_t size = 0;
  std::vector<unsigned char> encoded;
  // The first call measures, the second writes; libpng frees its state when a call ends, also on failure.
  if (png_image_write_get_memory_size(image, size, 0, pixels, 0, nullptr)) {
    encoded.resize(size);
    if (png_image_write_to_memory(&image, encoded.data(), &size, 0, pixels, 0, nullptr)) {
      encoded.resize(size);
      return encoded;
    }
  }
  throw Error(where + ": encoding '" + path + "' failed: " + image.message);
}

bool hasPngSignature(const std::string& path) {
  const FileHandle file = openForReading(path);
  png_byte signature[8] = {};
  return file && std::fread(signature, 1, sizeof signature, file.get()) == sizeof signature &&
         png_sig_cmp(signature, 0, sizeof signature) == 0;
}

FloatImage decodePng(const std::string& path) {
  const FileHandle file = openForReading(path);
  if (!file) throw Error("readImage: cannot open '" + path + "'");
  PngReader reader;
  reader.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &reader, onPngError, onPngWarning);
  if (reader.png) reader.info = png_create_info_struct(reader.png);
  if (!reader.info) throw Error("readImage: '" + path + "': out of memory");
  PngLayout layout;
  if (!readLayout(reader, file.get(), layout))
    throw Error("readImage: '" + path + "' is not a valid PNG file: " + reader.message);
  const uint64_t values = uint64_t(layout.width) * layout.height * uint64_t(layout.channels);
  if (values == 0 || values > kMaxDecodedImageValues || (layout.bitDepth != 8 && layout.bitDepth != 16))
    throw Error("readImage: '" + path + "' claims " + std::to_string(layout.width) + "x" +
                std::to_string(layout.height) + " pixels of " + std::to_string(layout.channels) +
                " channels of " + std::to_string(layout.bitDepth) + " bits; expected at most " +
                std::to_string(kMaxDecodedImageValues) + " values (16384x16384 RGBA) of 8 or 16 bits");

  std::vector<png_byte> bytes(layout.rowBytes * layout.height);
  std::vector<png_bytep> rows(layout.height);
  for (png_uint_32 y = 0; y < layout.height; ++y) rows[y] = bytes.data() + y * layout.rowBytes;
  if (!readRows(reader, rows.data()))
    throw Error("readImage: reading '" + path + "' failed: " + reader.message);

  FloatImage image;
  image.width = layout.width;
  image.height = layout.height;
  image.channels = uint32_t(layout.channels);
  image.pixels.resize(values);
  for (png_uint_32 y = 0; y < layout.height; ++y) {
    float* out = image.pixels.data() + size_t(y) * layout.width * layout.channels;
    const size_t samples = size_t(layout.width) * layout.channels;
    // The scales OpenImageIO converts with, so that either reader gives the same floats.
    if (layout.bitDepth == 8) {
      for (size_t i = 0; i < samples; ++i) out[i] = float(rows[y][i]) * (1.0f / 255.0f);
    } else {
      for (size_t i = 0; i < samples; ++i) {
        uint16_t sample;
        std::memcpy(&sample, rows[y] + 2 * i, sizeof sample);
        out[i] = float(sample) * (1.0f / 65535.0f);
      }
    }
  }
  return image;
}

}  // namespace ropecast
