#include "reference/image_compare.h"

#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"

namespace ropecast::tools {

ImageDifference compareImages(std::span<const float> a, uint32_t aChannels, std::span<const float> b,
                              uint32_t bChannels, uint32_t channels) {
  if (channels == 0 || channels > aChannels || channels > bChannels)
    throw Error("compareImages: cannot compare " + std::to_string(channels) + " channels of images with " +
                std::to_string(aChannels) + " and " + std::to_string(bChannels));
  if (a.size() % aChannels != 0 || b.size() % bChannels != 0 || a.size() / aChannels != b.size() / bChannels)
    throw Error("compareImages: the images differ in size (" + std::to_string(a.size() / aChannels) +
                " and " + std::to_string(b.size() / bChannels) + " pixels)");
  ImageDifference d;
  const size_t pixels = a.size() / aChannels;
  double sumSq = 0.0, sumAbs = 0.0;
  for (size_t p = 0; p < pixels; ++p)
    for (uint32_t c = 0; c < channels; ++c) {
      const double x = a[p * aChannels + c], y = b[p * bChannels + c];
      // Equal values differ by nothing, infinities (a depth image's misses) and NaN included; a value that
      // is not finite against one that differs, by an infinite amount (a miss against a hit).
      const bool same = x == y || (std::isnan(x) && std::isnan(y));
      const double diff = same ? 0.0 : std::isfinite(x - y) ? std::abs(x - y) : HUGE_VAL;
      sumSq += diff * diff;
      sumAbs += diff;
      d.maxAbs = std::max(d.maxAbs, diff);
    }
  d.values = uint64_t(pixels) * channels;
  if (d.values == 0) throw Error("compareImages: empty images");
  const double mse = sumSq / double(d.values);
  d.meanAbs = sumAbs / double(d.values);
  d.psnrDb = mse > 0.0 ? 10.0 * std::log10(1.0 / mse) : std::numeric_limits<double>::infinity();
  return d;
}

}  // namespace ropecast::tools
