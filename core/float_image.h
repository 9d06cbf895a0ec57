// FloatImage: float pixels as renderers produce them and image files hold them. Plain data; any thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ropecast {

// Float pixels, row 0 at the top, channels interleaved.
struct FloatImage {
  uint32_t width = 0, height = 0, channels = 0;
  std::vector<float> pixels;  // width * height * channels

  float at(uint32_t x, uint32_t y, uint32_t c) const {
    return pixels[(size_t(y) * width + x) * channels + c];
  }
  float& at(uint32_t x, uint32_t y, uint32_t c) { return pixels[(size_t(y) * width + x) * channels + c]; }
};

}  // namespace ropecast
