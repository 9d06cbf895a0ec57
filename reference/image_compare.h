// Image difference measures for `ropecast compare` and the quality benchmarks: PSNR (peak 1.0), largest and
// mean absolute difference over the first `channels` channels of two images of the same size. Pure
// functions over float pixels (row-major, channels interleaved, as reference/image_io.h FloatImage holds
// them); any thread.
#pragma once

#include <cstdint>
#include <span>

namespace ropecast::tools {

struct ImageDifference {
  double psnrDb = 0.0;   // 10 log10(1 / MSE); +inf for identical images, -inf when maxAbs is
  double maxAbs = 0.0;   // largest |a - b|; +inf where one value is not finite and the other differs
  double meanAbs = 0.0;  // mean |a - b|
  uint64_t values = 0;   // values compared: pixels * channels
};

// `aChannels`/`bChannels`: channels per pixel of each image; the first `channels` of both are compared.
// Throws ropecast::Error when the pixel counts differ or `channels` exceeds either image's channels.
ImageDifference compareImages(std::span<const float> a, uint32_t aChannels, std::span<const float> b,
                              uint32_t bChannels, uint32_t channels);

}  // namespace ropecast::tools
