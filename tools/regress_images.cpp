#include "tools/regress_images.h"

#include <cmath>
#include <limits>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include "core/error.h"
#include "core/float_image.h"
#include "core/input_file.h"

namespace ropecast::tools {
namespace {

// Goldens and renders are color images: a one-channel golden compared on its one channel would pass a render
// whatever its green and blue. The stored color, as `ropecast compare` reads it (not color * alpha).
OIIO::ImageBuf readBuf(const std::string& path, const char* what) {
  requireRegularFile(path, "regress: the " + std::string(what) + " " + path);  // a FIFO would block
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  OIIO::ImageBuf image(path, 0, 0, nullptr, &config);
  if (!image.read(0, 0, /*force=*/true, OIIO::TypeDesc::FLOAT))
    throw Error("regress: cannot read the " + std::string(what) + " " + path + ": " + image.geterror());
  if (image.spec().nchannels < 3)
    throw Error("regress: the " + std::string(what) + " " + path + " has " +
                std::to_string(image.spec().nchannels) +
                " channel(s), expected an RGB or RGBA image (regress --update writes one from the render)");
  return image;
}

// The smallest power of two in [1, 256] that brings the largest difference to at least half of white.
double amplificationFor(double maxError) {
  double amplification = 1.0;
  while (amplification < 256.0 && maxError * amplification * 2.0 <= 1.0) amplification *= 2.0;
  return amplification;
}

}  // namespace

void checkRenderImage(const std::string& render) {
  readBuf(render, "render");
}

GoldenDifference compareWithGolden(const std::string& golden, const std::string& render,
                                   double failingPixelError, FloatImage* difference) {
  const OIIO::ImageBuf a = readBuf(golden, "golden image");
  const OIIO::ImageBuf b = readBuf(render, "render");
  const OIIO::ImageSpec &sa = a.spec(), &sb = b.spec();
  if (sa.width != sb.width || sa.height != sb.height)
    throw Error("regress: the golden image " + golden + " is " + std::to_string(sa.width) + "x" +
                std::to_string(sa.height) + ", the render " + std::to_string(sb.width) + "x" +
                std::to_string(sb.height));
  const int channels = 3;
  OIIO::ROI roi = a.roi();
  roi.chbegin = 0;
  roi.chend = channels;
  const OIIO::ImageBufAlgo::CompareResults r =
      OIIO::ImageBufAlgo::compare(a, b, float(failingPixelError), float(failingPixelError), roi);
  // compare() also sets `error` when pixels fail; only without failures does it mean the comparison broke.
  if (r.error && r.nfail == 0)
    throw Error("regress: comparing " + golden + " with " + render + " failed: " + OIIO::geterror());

  GoldenDifference d;
  d.width = uint32_t(sa.width);
  d.height = uint32_t(sa.height);
  d.psnrDb =
      r.rms_error > 0.0 ? 20.0 * std::log10(1.0 / r.rms_error) : std::numeric_limits<double>::infinity();
  d.maxError = r.maxerror;
  d.failingPixels = r.nfail;
  d.failingShare = double(r.nfail) / (double(d.width) * double(d.height));
  d.amplification = amplificationFor(d.maxError);
  if (!difference) return d;

  OIIO::ImageBuf amplified = OIIO::ImageBufAlgo::absdiff(a, b, roi);
  amplified = OIIO::ImageBufAlgo::mul(amplified, float(d.amplification));
  difference->width = d.width;
  difference->height = d.height;
  difference->channels = channels;
  difference->pixels.assign(size_t(d.width) * d.height * channels, 0.0f);
  OIIO::ROI all = amplified.roi();
  all.chend = channels;
  amplified.get_pixels(all, OIIO::TypeDesc::FLOAT, difference->pixels.data());
  return d;
}

}  // namespace ropecast::tools
