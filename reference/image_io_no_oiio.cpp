// Stands in for image_io.cpp in builds without OpenImageIO (ROPECAST_WITH_OIIO=OFF), which exist to carry
// ropecast to a GPU machine without Debian's libraries: "PNG" output is written as binary PPM (P6) when the
// path ends in .ppm; everything else is refused with a message that says why.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "core/error.h"
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

void writePng(const std::string& path, const FloatImage& image, bool withAlpha) {
  if (!path.ends_with(".ppm")) refuse("writePng", path);
  if (image.channels < 3) throw Error("writePng: '" + path + "': needs at least 3 channels");
  const std::string tmp = path + ".tmp";
  std::FILE* file = std::fopen(tmp.c_str(), "wb");
  if (!file) throw Error("writePng: cannot write '" + tmp + "'");
  std::fprintf(file, "P6\n%u %u\n255\n", image.width, image.height);
  std::vector<unsigned char> row(size_t(image.width) * 3);
  bool ok = true;
  for (uint32_t y = 0; y < image.height && ok; ++y) {
    for (uint32_t x = 0; x < image.width; ++x)
      for (uint32_t c = 0; c < 3; ++c)
        row[x * 3 + c] =
            static_cast<unsigned char>(std::lround(std::clamp(image.at(x, y, c), 0.0f, 1.0f) * 255.0f));
    ok = std::fwrite(row.data(), 1, row.size(), file) == row.size();
  }
  ok = (std::fclose(file) == 0) && ok;
  std::error_code ec;
  if (ok) std::filesystem::rename(tmp, path, ec);
  if (!ok || ec) {
    std::filesystem::remove(tmp, ec);
    throw Error("writePng: writing '" + path + "' failed");
  }
}

void writeExr(const std::string& path, const FloatImage&) {
  refuse("writeExr", path);
}

void writeDepthExr(const std::string& path, const FloatImage&) {
  refuse("writeDepthExr", path);
}

FloatImage readImage(const std::string& path) {
  refuse("readImage", path);
}

}  // namespace ropecast
