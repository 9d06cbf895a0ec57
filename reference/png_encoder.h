// 8-bit PNG files in memory through libpng's simplified API, for the images ropecast writes most (render's
// -o, the viewer's screenshots): encoding them needs neither OpenImageIO nor the image module that carries it
// (tools/image_module.h), whose loading took the larger part of a small render. GL-free; any thread.
#pragma once

#include <string>
#include <vector>

#include "reference/image_codec.h"

namespace ropecast {

// The bytes of a PNG file holding `pixels`: 8-bit gray, gray+alpha, RGB or RGBA (1 to 4 channels, alpha last
// and not premultiplied), rows from the top. Throws ropecast::Error naming `where` and `path`.
std::vector<unsigned char> encodePng(const std::string& where, const std::string& path,
                                     const ImageEncoding& encoding, const void* pixels);

}  // namespace ropecast
