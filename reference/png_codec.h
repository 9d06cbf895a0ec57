// 8-bit PNG files through libpng, for the images ropecast writes and reads most (render's -o, the viewer's
// screenshots, `compare`): neither needs OpenImageIO nor the image module that carries it
// (tools/image_module.h), whose loading took the larger part of a small render or comparison. GL-free; any
// thread.
#pragma once

#include <string>
#include <vector>

#include "core/float_image.h"
#include "reference/image_codec.h"

namespace ropecast {

// The bytes of a PNG file holding `pixels`: 8-bit gray, gray+alpha, RGB or RGBA (1 to 4 channels, alpha last
// and not premultiplied), rows from the top. Throws ropecast::Error naming `where` and `path`.
std::vector<unsigned char> encodePng(const std::string& where, const std::string& path,
                                     const ImageEncoding& encoding, const void* pixels);

// Whether the file at `path` starts with PNG's signature (false when it cannot be read).
bool hasPngSignature(const std::string& path);

// The PNG file at `path` as floats, the values OpenImageIO's reader gives (decodeImage): samples v / 255, or
// v / 65535 for 16-bit files; palettes and gray of 1, 2 or 4 bits expanded, a transparency chunk made alpha;
// the stored color (not premultiplied) and no gamma applied. Throws ropecast::Error "readImage: ..." naming
// `path` when it cannot be read, is not a valid PNG or claims more than 16384x16384 RGBA values.
FloatImage decodePng(const std::string& path);

}  // namespace ropecast
