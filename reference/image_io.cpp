#include "reference/image_io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <span>
#include <system_error>
#include <vector>

#include "core/error.h"
#include "core/file_names.h"
#include "core/input_file.h"
#include "core/temporary_file.h"
#include "reference/image_codec.h"
#include "reference/png_codec.h"

namespace ropecast {

namespace {

void checkImage(const std::string& where, const std::string& path, const FloatImage& image,
                uint32_t minChannels) {
  if (image.width == 0 || image.height == 0) throw Error(where + ": '" + path + "': empty image");
  if (image.channels < minChannels)
    throw Error(where + ": '" + path + "': image has " + std::to_string(image.channels) + " channels, need " +
                std::to_string(minChannels));
  if (image.pixels.size() != size_t(image.width) * image.height * image.channels)
    throw Error(where + ": '" + path + "': pixel buffer size does not match width x height x channels");
}

ImageEncoding encodingOf(const FloatImage& image, uint32_t channels, bool floatSamples) {
  ImageEncoding encoding;
  encoding.width = image.width;
  encoding.height = image.height;
  encoding.channels = channels;
  encoding.floatSamples = floatSamples;
  return encoding;
}

// Writes the encoded bytes under a temporary name next to `path` ("OUT.tmp-XXXXXX": a fixed name could be a
// file of the user's, an input even). PNG's 8-bit pixels are encoded here; other formats through OpenImageIO.
StagedImage stage(const std::string& where, const std::string& path, const ImageEncoding& encoding,
                  const void* pixels) {
  const std::vector<unsigned char> encoded = !encoding.floatSamples && hasExtension(path, ".png")
                                                 ? encodePng(where, path, encoding, pixels)
                                                 : encodeImage(where, path, encoding, pixels);
  auto file = std::make_unique<TemporaryFile>(path, where);  // removed unless committed, also on a signal
  file->writeAt(0, std::as_bytes(std::span(encoded)));
  return file;
}

bool parentFolderExists(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ec;
  return parent.empty() || std::filesystem::is_directory(parent, ec);
}

}  // namespace

std::string imageOutputProblem(const std::string& path, ImageOutputKind kind) {
  if (!parentFolderExists(path))
    return "its folder '" + std::filesystem::path(path).parent_path().string() + "' does not exist";
  if (kind == ImageOutputKind::FloatExr)
    return hasExtension(path, ".exr") ? imageWriterProblem(path)
                                      : "expected a file name ending in .exr (float data)";
  // ".png" alone is a hidden file's name without an extension to the file system, and to OpenImageIO.
  if (std::filesystem::path(path).extension().empty())
    return "expected a name and an extension such as .png, got '" +
           std::filesystem::path(path).filename().string() + "'";
  return hasExtension(path, ".png") ? "" : imageWriterProblem(path);
}

StagedImage stagePng(const std::string& path, const FloatImage& image, bool withAlpha) {
  const uint32_t channels = withAlpha ? 4 : 3;
  checkImage("writePng", path, image, channels);
  std::vector<uint8_t> bytes(size_t(image.width) * image.height * channels);
  for (size_t p = 0; p < size_t(image.width) * image.height; ++p)
    for (uint32_t c = 0; c < channels; ++c) {
      const float v = image.pixels[p * image.channels + c];
      const float clamped = std::isnan(v) ? 0.0f : std::clamp(v, 0.0f, 1.0f);
      bytes[p * channels + c] = uint8_t(std::lround(clamped * 255.0f));
    }
  ImageEncoding encoding = encodingOf(image, channels, /*floatSamples=*/false);
  encoding.unassociatedAlpha = true;  // color is final (background composited): write it unchanged
  return stage("writePng", path, encoding, bytes.data());
}

StagedImage stageExr(const std::string& path, const FloatImage& image) {
  checkImage("writeExr", path, image, 1);
  ImageEncoding encoding = encodingOf(image, image.channels, /*floatSamples=*/true);
  if (image.channels == 4) {
    encoding.channelNames = {"R", "G", "B", "A"};
    encoding.alphaChannel = 3;
  }
  return stage("writeExr", path, encoding, image.pixels.data());
}

StagedImage stageDepthExr(const std::string& path, const FloatImage& depth) {
  checkImage("writeDepthExr", path, depth, 1);
  if (depth.channels != 1) throw Error("writeDepthExr: '" + path + "': depth images have one channel");
  ImageEncoding encoding = encodingOf(depth, 1, /*floatSamples=*/true);
  encoding.channelNames = {"Z"};
  encoding.zChannel = 0;
  return stage("writeDepthExr", path, encoding, depth.pixels.data());
}

FloatImage readImage(const std::string& path) {
  requireRegularFile(path, "readImage: '" + path + "'");  // a FIFO would block, a device never end
  // PNG, what ropecast writes and compares most, through libpng: OpenImageIO (in the ropecast executable, its
  // image module) only for the other formats.
  return hasPngSignature(path) ? decodePng(path) : decodeImage(path);
}

}  // namespace ropecast
