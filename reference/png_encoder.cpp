#include "reference/png_encoder.h"

#include <png.h>

#include "core/error.h"

namespace ropecast {

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

}  // namespace ropecast
