// Image comparison for `ropecast regress`: a render against its golden image, and the amplified difference
// image of the report. Images are read as `ropecast compare` reads them (reference/image_io.h readImage: PNG
// through libpng, other formats through OpenImageIO). GL-free; any thread (no shared state).
#pragma once

#include <cstdint>
#include <string>

#include "core/float_image.h"

namespace ropecast::tools {

// How a render differs from its golden image over the RGB channels (values in [0, 1]).
struct GoldenDifference {
  uint32_t width = 0, height = 0;
  double psnrDb = 0.0;         // 20 log10(1 / RMS error), peak 1; +inf when identical
  double maxError = 0.0;       // largest |golden - render| of any channel
  uint64_t failingPixels = 0;  // pixels with a channel differing by more than the failing error
  double failingShare = 0.0;   // failingPixels / (width * height)
  double amplification = 1.0;  // of the difference image: a power of two that makes maxError visible
};

// Reads `render` back whole, as a golden made from it would be read: throws ropecast::Error naming it when it
// cannot be read or is not an RGB(A) image.
void checkRenderImage(const std::string& render);

// Compares `render` with `golden` (both RGB or RGBA) over RGB: a pixel fails where a channel differs by more
// than `failingPixelError`. With `difference` given, also
// makes |golden - render| * amplification there (RGB), for the caller to write. Throws ropecast::Error naming
// the file that cannot be read or is not RGB(A), and both sizes when they differ.
GoldenDifference compareWithGolden(const std::string& golden, const std::string& render,
                                   double failingPixelError, FloatImage* difference);

}  // namespace ropecast::tools
