// Stands in for image_io.cpp in builds without OpenImageIO (ROPECAST_WITH_OIIO=OFF), which exist to carry
// ropecast to a GPU machine without Debian's libraries: "PNG" output is written as binary PPM (P6) when the
// path ends in .ppm; everything else is refused with a message that says why.
#include <algorithm>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/temporary_file.h"
#include "reference/image_io.h"

namespace ropecast {

namespace {
[[noreturn]] void refuse(const std::string& where, const std::string& path) {
  throw Error(where + ": '" + path +
              "': this ropecast was built without OpenImageIO (ROPECAST_WITH_OIIO=OFF); "
              "it writes .ppm images only");
}
}  // namespace

std::string imageOutputProblem(const std::string& path, ImageOutputKind kind) {
  if (kind == ImageOutputKind::Color8 && path.ends_with(".ppm")) return "";
  return "this ropecast was built without OpenImageIO (ROPECAST_WITH_OIIO=OFF); it writes .ppm images only";
}

StagedImage stagePng(const std::string& path, const FloatImage& image, bool withAlpha) {
  if (!path.ends_with(".ppm")) refuse("writePng", path);
  if (image.channels < 3) throw Error("writePng: '" + path + "': needs at least 3 channels");
  auto file = std::make_unique<TemporaryFile>(path, "writePng");  // removed unless committed
  const std::string header =
      "P6\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n255\n";
  file->writeAt(0, std::as_bytes(std::span(header)));
  std::vector<unsigned char> row(size_t(image.width) * 3);
  for (uint32_t y = 0; y < image.height; ++y) {
    for (uint32_t x = 0; x < image.width; ++x)
      for (uint32_t c = 0; c < 3; ++c)
        row[x * 3 + c] =
            static_cast<unsigned char>(std::lround(std::clamp(image.at(x, y, c), 0.0f, 1.0f) * 255.0f));
    file->writeAt(header.size() + uint64_t(y) * row.size(), std::as_bytes(std::span(row)));
  }
  return file;
}

StagedImage stageExr(const std::string& path, const FloatImage&) {
  refuse("writeExr", path);
}

StagedImage stageDepthExr(const std::string& path, const FloatImage&) {
  refuse("writeDepthExr", path);
}

FloatImage readImage(const std::string& path) {
  refuse("readImage", path);
}

}  // namespace ropecast
