// Image files in memory, through OpenImageIO: pixels encoded into the bytes of the file format a name's
// extension chooses, and a file decoded into floats. image_io.h puts the bytes in place; the ropecast
// executable reaches these functions through its image module (tools/image_module.h), so they hold no state
// and write no file. GL-free; any thread.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/float_image.h"

namespace ropecast {

// How the pixels given to encodeImage are laid out and what the file should say about them.
struct ImageEncoding {
  uint32_t width = 0, height = 0, channels = 0;
  bool floatSamples = false;              // 32-bit floats; else 8-bit unsigned
  std::vector<std::string> channelNames;  // empty: the format's own names
  int alphaChannel = -1, zChannel = -1;   // -1: none
  bool unassociatedAlpha = false;         // the color is final (composited): written unchanged
};

// The bytes of a file of `path`'s format holding `pixels`. Encoding in memory lets the caller report a failed
// write (a full disk): OpenImageIO's PNG writer does not. Throws ropecast::Error naming `where` and `path`.
std::vector<unsigned char> encodeImage(const std::string& where, const std::string& path,
                                       const ImageEncoding& encoding, const void* pixels);

// Why no writer can encode `path`'s extension in memory, in words ("" when one can).
std::string imageWriterProblem(const std::string& path);

// The most values a decoded image may hold: the largest image ropecast writes (16384 x 16384 RGBA). A header
// that claims more is refused before anything is allocated.
inline constexpr uint64_t kMaxDecodedImageValues = uint64_t(16384) * 16384 * 4;

// `path` read as floats (8-bit PNG values become v / 255; the stored color, not color * alpha), at most
// kMaxDecodedImageValues. Throws ropecast::Error naming the file.
FloatImage decodeImage(const std::string& path);

}  // namespace ropecast
