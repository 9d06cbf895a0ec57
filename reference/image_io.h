// Image files: PNG (8-bit RGB or RGBA, clamped to [0,1], no gamma; through libpng, png_codec.h), other
// 8-bit formats OpenImageIO writes, and OpenEXR (float RGBA; a depth EXR with one float channel "Z") through
// OpenImageIO, and reading them back as floats (tests, regression goldens).
// Writes go to a unique temporary name next to the path ("<path>.tmp-XXXXXX") and are renamed when complete,
// so a failure leaves nothing half-written and no file of the user's is touched but the output. GL-free; any
// thread (no shared state).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/float_image.h"
#include "core/temporary_file.h"

namespace ropecast {

// An image written in full under its temporary name (core/temporary_file.h): commit() puts it in place,
// destruction without commit removes it. Outputs that must appear together or not at all are staged first and
// committed last (render's -o, --exr and --depth).
using StagedImage = std::unique_ptr<TemporaryFile>;

// Writes the first 3 (withAlpha false) or 4 channels of an image with >= 3 (>= 4) channels as 8-bit PNG:
// round(clamp(v, 0, 1) * 255). Throws ropecast::Error naming the file.
StagedImage stagePng(const std::string& path, const FloatImage& image, bool withAlpha);
// Writes all channels as 32-bit float EXR (channel names R, G, B, A for 4 channels). Throws naming the file.
StagedImage stageExr(const std::string& path, const FloatImage& image);
// Writes a 1-channel image as a float EXR with the channel "Z" (world units; +inf = miss).
StagedImage stageDepthExr(const std::string& path, const FloatImage& depth);

// Staged and committed at once.
inline void writePng(const std::string& path, const FloatImage& image, bool withAlpha) {
  stagePng(path, image, withAlpha)->commit();
}
inline void writeExr(const std::string& path, const FloatImage& image) {
  stageExr(path, image)->commit();
}
inline void writeDepthExr(const std::string& path, const FloatImage& depth) {
  stageDepthExr(path, depth)->commit();
}
// What an image output is for: writePng's 8-bit color, or writeExr's and writeDepthExr's float data.
enum class ImageOutputKind { Color8, FloatExr };
// Why an image of `kind` cannot be written at `path`, in words ("" when it can): its folder does not exist,
// no writer knows its extension, or a float output's name does not end in .exr (any other format would round
// the floats). Callers check their outputs before long work, so a typo does not surface after the render.
std::string imageOutputProblem(const std::string& path, ImageOutputKind kind);
// Reads any image OpenImageIO knows as floats (8-bit PNG values become v / 255; PNG files through libpng,
// png_codec.h). Throws naming the file.
FloatImage readImage(const std::string& path);

}  // namespace ropecast
