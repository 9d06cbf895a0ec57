#include "reference/image_codec.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include "core/error.h"

namespace ropecast {

std::vector<unsigned char> encodeImage(const std::string& where, const std::string& path,
                                       const ImageEncoding& encoding, const void* pixels) {
  auto out = OIIO::ImageOutput::create(path);
  if (!out)
    throw Error(where + ": '" + path + "': no image writer for this extension (" + OIIO::geterror() + ")");
  if (!out->supports("ioproxy"))
    throw Error(where + ": '" + path + "': the " + out->format_name() +
                " writer cannot write to memory; use .png or .exr");
  const OIIO::TypeDesc type = encoding.floatSamples ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8;
  OIIO::ImageSpec spec(int(encoding.width), int(encoding.height), int(encoding.channels), type);
  if (!encoding.channelNames.empty()) spec.channelnames = encoding.channelNames;
  if (encoding.alphaChannel >= 0) spec.alpha_channel = encoding.alphaChannel;
  if (encoding.zChannel >= 0) spec.z_channel = encoding.zChannel;
  if (encoding.unassociatedAlpha) spec.attribute("oiio:UnassociatedAlpha", 1);

  std::vector<unsigned char> encoded;
  OIIO::Filesystem::IOVecOutput memory(encoded);
  if (!out->set_ioproxy(&memory)) throw Error(where + ": '" + path + "': " + out->geterror());
  bool ok = out->open(path, spec) && out->write_image(type, pixels);
  const std::string err = ok ? "" : out->geterror();
  ok = out->close() && ok;
  if (!ok) throw Error(where + ": encoding '" + path + "' failed: " + (err.empty() ? out->geterror() : err));
  return encoded;
}

std::string imageWriterProblem(const std::string& path) {
  auto out = OIIO::ImageOutput::create(path);
  if (!out) return "no image writer for this extension; use .png";
  if (!out->supports("ioproxy"))
    return std::string("the ") + out->format_name() + " writer cannot write to memory; use .png or .exr";
  return "";
}

FloatImage decodeImage(const std::string& path) {
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);  // PNG: return the stored color, not color * alpha
  auto in = OIIO::ImageInput::open(path, &config);
  if (!in) throw Error("readImage: cannot open '" + path + "': " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 ||
      uint64_t(spec.width) * uint64_t(spec.height) * uint64_t(spec.nchannels) > kMaxDecodedImageValues)
    throw Error("readImage: '" + path + "' claims " + std::to_string(spec.width) + "x" +
                std::to_string(spec.height) + " pixels of " + std::to_string(spec.nchannels) +
                " channels; expected at most " + std::to_string(kMaxDecodedImageValues) +
                " values (16384x16384 RGBA)");
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
