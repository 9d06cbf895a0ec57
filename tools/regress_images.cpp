#include "tools/regress_images.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/float_image.h"
#include "reference/image_io.h"

namespace ropecast::tools {
namespace {

// Goldens and renders are color images: a one-channel golden compared on its one channel would pass a render
// whatever its green and blue. The stored color, as `ropecast compare` reads it (not color * alpha).
FloatImage readColorImage(const std::string& path, const char* what) {
  FloatImage image;
  try {
    image = readImage(path);  // PNG through libpng, other formats through OpenImageIO
  } catch (const Error& e) {
    throw Error("regress: cannot read the " + std::string(what) + " " + path + ": " + e.what());
  }
  if (image.channels < 3)
    throw Error("regress: the " + std::string(what) + " " + path + " has " + std::to_string(image.channels) +
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
  readColorImage(render, "render");
}

GoldenDifference compareWithGolden(const std::string& golden, const std::string& render,
                                   double failingPixelError, FloatImage* difference) {
  const FloatImage a = readColorImage(golden, "golden image");
  const FloatImage b = readColorImage(render, "render");
  if (a.width != b.width || a.height != b.height)
    throw Error("regress: the golden image " + golden + " is " + std::to_string(a.width) + "x" +
                std::to_string(a.height) + ", the render " + std::to_string(b.width) + "x" +
                std::to_string(b.height));
  constexpr uint32_t kChannels = 3;
  GoldenDifference d;
  d.width = a.width;
  d.height = a.height;
  if (difference) {
    difference->width = d.width;
    difference->height = d.height;
    difference->channels = kChannels;
    difference->pixels.assign(size_t(d.width) * d.height * kChannels, 0.0f);
  }
  double squares = 0.0;
  for (uint32_t y = 0; y < d.height; ++y)
    for (uint32_t x = 0; x < d.width; ++x) {
      bool fails = false;
      for (uint32_t c = 0; c < kChannels; ++c) {
        const double error = std::abs(double(a.at(x, y, c)) - double(b.at(x, y, c)));
        squares += error * error;
        d.maxError = std::max(d.maxError, error);
        fails = fails || error > failingPixelError;
        if (difference) difference->at(x, y, c) = float(error);
      }
      d.failingPixels += fails ? 1 : 0;
    }
  const double rms = std::sqrt(squares / (double(d.width) * d.height * kChannels));
  d.psnrDb = rms > 0.0 ? 20.0 * std::log10(1.0 / rms) : std::numeric_limits<double>::infinity();
  d.failingShare = double(d.failingPixels) / (double(d.width) * double(d.height));
  d.amplification = amplificationFor(d.maxError);
  if (difference)
    for (float& v : difference->pixels) v = float(v * d.amplification);
  return d;
}

}  // namespace ropecast::tools
