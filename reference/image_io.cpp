#include "reference/image_io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <span>
#include <system_error>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include "core/error.h"
#include "core/input_file.h"
#include "core/temporary_file.h"

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

// Encodes `data` (pixels of `spec`) with the plugin chosen by `path`'s extension in memory, then writes the
// bytes under a temporary name next to `path` ("OUT.tmp-XXXXXX": a fixed name could be a file of the user's,
// an input even). Encoding in memory lets TemporaryFile report a failed write (a full disk): OpenImageIO's
// PNG writer does not.
StagedImage stage(const std::string& where, const std::string& path, const OIIO::ImageSpec& spec,
                  OIIO::TypeDesc dataType, const void* data) {
  auto out = OIIO::ImageOutput::create(path);
  if (!out)
    throw Error(where + ": '" + path + "': no image writer for this extension (" + OIIO::geterror() + ")");
  if (!out->supports("ioproxy"))
    throw Error(where + ": '" + path + "': the " + out->format_name() +
                " writer cannot write to memory; use .png or .exr");
  std::vector<unsigned char> encoded;
  OIIO::Filesystem::IOVecOutput memory(encoded);
  if (!out->set_ioproxy(&memory)) throw Error(where + ": '" + path + "': " + out->geterror());
  bool ok = out->open(path, spec) && out->write_image(dataType, data);
  const std::string err = ok ? "" : out->geterror();
  ok = out->close() && ok;
  if (!ok) throw Error(where + ": encoding '" + path + "' failed: " + (err.empty() ? out->geterror() : err));
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
    return hasExrExtension(path) ? "" : "expected a file name ending in .exr (float data)";
  // ".png" alone is a hidden file's name without an extension to the file system, and to OpenImageIO.
  if (std::filesystem::path(path).extension().empty())
    return "expected a name and an extension such as .png, got '" +
           std::filesystem::path(path).filename().string() + "'";
  auto out = OIIO::ImageOutput::create(path);
  if (!out) return "no image writer for this extension; use .png";
  if (!out->supports("ioproxy"))
    return std::string("the ") + out->format_name() + " writer cannot write to memory; use .png or .exr";
  return "";
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
  OIIO::ImageSpec spec(int(image.width), int(image.height), int(channels), OIIO::TypeDesc::UINT8);
  spec.attribute("oiio:UnassociatedAlpha", 1);  // color is final (background composited): write it unchanged
  return stage("writePng", path, spec, OIIO::TypeDesc::UINT8, bytes.data());
}

StagedImage stageExr(const std::string& path, const FloatImage& image) {
  checkImage("writeExr", path, image, 1);
  OIIO::ImageSpec spec(int(image.width), int(image.height), int(image.channels), OIIO::TypeDesc::FLOAT);
  if (image.channels == 4) spec.channelnames = {"R", "G", "B", "A"};
  if (image.channels == 4) spec.alpha_channel = 3;
  return stage("writeExr", path, spec, OIIO::TypeDesc::FLOAT, image.pixels.data());
}

StagedImage stageDepthExr(const std::string& path, const FloatImage& depth) {
  checkImage("writeDepthExr", path, depth, 1);
  if (depth.channels != 1) throw Error("writeDepthExr: '" + path + "': depth images have one channel");
  OIIO::ImageSpec spec(int(depth.width), int(depth.height), 1, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"Z"};
  spec.z_channel = 0;
  return stage("writeDepthExr", path, spec, OIIO::TypeDesc::FLOAT, depth.pixels.data());
}

FloatImage readImage(const std::string& path) {
  requireRegularFile(path, "readImage: '" + path + "'");  // a FIFO would block, a device never end
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);  // PNG: return the stored color, not color * alpha
  auto in = OIIO::ImageInput::open(path, &config);
  if (!in) throw Error("readImage: cannot open '" + path + "': " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  // A header may claim any size: what it claims is checked before anything is allocated. The limit holds the
  // largest image ropecast writes (16384 x 16384 RGBA).
  constexpr uint64_t kMaxValues = uint64_t(16384) * 16384 * 4;
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 ||
      uint64_t(spec.width) * uint64_t(spec.height) * uint64_t(spec.nchannels) > kMaxValues)
    throw Error("readImage: '" + path + "' claims " + std::to_string(spec.width) + "x" +
                std::to_string(spec.height) + " pixels of " + std::to_string(spec.nchannels) +
                " channels; expected at most " + std::to_string(kMaxValues) + " values (16384x16384 RGBA)");
  FloatImage image;
  image.width = uint32_t(spec.width);
  image.height = uint32_t(spec.height);
  image.channels = uint32_t(spec.nchannels);
  image.pixels.resize(size_t(image.width) * image.height * image.channels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data()))
    throw Error("readImage: reading '" + path + "' failed: " + in->geterror());
  in->close();
  return image;
}

}  // namespace ropecast
