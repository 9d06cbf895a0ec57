// Image files: PNG quantization, float EXR and depth EXR round trips, atomic writes, errors naming the file.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "core/error.h"
#include "reference/image_io.h"
#include "reference/png_codec.h"
#include "tests/render/testutil_gl.h"

namespace ropecast {
namespace {

// The names of the files directly in `dir`.
std::set<std::string> filesIn(const std::filesystem::path& dir) {
  std::set<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) names.insert(entry.path().filename());
  return names;
}

FloatImage gradientImage(uint32_t w, uint32_t h) {
  FloatImage img{w, h, 4, std::vector<float>(size_t(w) * h * 4)};
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      img.at(x, y, 0) = float(x) / float(w - 1);
      img.at(x, y, 1) = float(y) / float(h - 1);
      img.at(x, y, 2) = 1.5f - float(x + y) / float(w);  // goes beyond [0, 1] on purpose
      img.at(x, y, 3) = (x + y) % 2 ? 1.0f : 0.25f;
    }
  return img;
}

TEST(ImageIo, PngQuantizesAndClamps) {
  const auto dir = test::freshTempDir();
  const FloatImage img = gradientImage(17, 9);
  writePng((dir / "a.png").string(), img, true);
  writePng((dir / "b.png").string(), img, false);
  EXPECT_EQ(filesIn(dir), (std::set<std::string>{"a.png", "b.png"}));  // no temporary left behind
  const FloatImage a = readImage((dir / "a.png").string());
  const FloatImage b = readImage((dir / "b.png").string());
  ASSERT_EQ(a.channels, 4u);
  ASSERT_EQ(b.channels, 3u);
  ASSERT_EQ(a.width, 17u);
  ASSERT_EQ(a.height, 9u);
  for (uint32_t y = 0; y < 9; ++y)
    for (uint32_t x = 0; x < 17; ++x)
      for (uint32_t c = 0; c < 4; ++c) {
        const float want = std::round(std::clamp(img.at(x, y, c), 0.0f, 1.0f) * 255.0f) / 255.0f;
        EXPECT_NEAR(a.at(x, y, c), want, 1e-6) << x << "," << y << "," << c;
        if (c < 3) {
          EXPECT_NEAR(b.at(x, y, c), want, 1e-6);
        }
      }
}

// libpng encodes every 8-bit layout PNG has, and what it writes reads back through OpenImageIO; other formats
// are still OpenImageIO's.
TEST(ImageIo, PngEncoderWritesEveryLayoutAndOtherFormatsStillWork) {
  const auto dir = test::freshTempDir();
  constexpr uint32_t kWidth = 5, kHeight = 3;
  for (uint32_t channels = 1; channels <= 4; ++channels) {
    std::vector<uint8_t> pixels(size_t(kWidth) * kHeight * channels);
    for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = uint8_t(i * 37 + channels);
    ImageEncoding encoding;
    encoding.width = kWidth;
    encoding.height = kHeight;
    encoding.channels = channels;
    const std::string path = (dir / ("c" + std::to_string(channels) + ".PNG")).string();
    const std::vector<unsigned char> bytes = encodePng("test", path, encoding, pixels.data());
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    const FloatImage read = readImage(path);
    ASSERT_EQ(read.channels, channels);
    ASSERT_EQ(read.width, kWidth);
    ASSERT_EQ(read.height, kHeight);
    for (size_t i = 0; i < pixels.size(); ++i)
      EXPECT_NEAR(read.pixels[i], pixels[i] / 255.0f, 1e-6) << channels << " channels, value " << i;
  }
  ImageEncoding floats;
  floats.width = floats.height = 1;
  floats.channels = 4;
  floats.floatSamples = true;
  const float pixel[4] = {};
  EXPECT_THROW(encodePng("test", "f.png", floats, pixel), Error);

  const FloatImage img = gradientImage(6, 4);
  writePng((dir / "a.tif").string(), img, false);
  EXPECT_EQ(readImage((dir / "a.tif").string()).channels, 3u);
}

// The temporary name is unique: a file of the user's named like a temporary (here the input of a render,
// "out.png.tmp") is neither overwritten nor removed.
TEST(ImageIo, WritingLeavesAFileNamedLikeATemporaryAlone) {
  const auto dir = test::freshTempDir();
  for (const char* name : {"out.png", "out.exr"}) {
    const std::filesystem::path lookalike = dir / (std::string(name) + ".tmp");
    { std::ofstream(lookalike) << "precious"; }
    if (std::string(name).ends_with(".png"))
      writePng((dir / name).string(), gradientImage(4, 4), true);
    else
      writeExr((dir / name).string(), gradientImage(4, 4));
    std::ifstream in(lookalike);
    std::string text;
    in >> text;
    EXPECT_EQ(text, "precious") << lookalike;
    EXPECT_EQ(readImage((dir / name).string()).width, 4u);
  }
  EXPECT_EQ(filesIn(dir), (std::set<std::string>{"out.exr", "out.exr.tmp", "out.png", "out.png.tmp"}));
}

TEST(ImageIo, ExrKeepsFloatsAndDepthInfinity) {
  const auto dir = test::freshTempDir();
  const FloatImage img = gradientImage(8, 5);
  writeExr((dir / "c.exr").string(), img);
  const FloatImage c = readImage((dir / "c.exr").string());
  ASSERT_EQ(c.channels, 4u);
  EXPECT_EQ(c.pixels, img.pixels);

  FloatImage depth{3, 2, 1, {1.0f, 2.5f, std::numeric_limits<float>::infinity(), 0.0f, 1e6f, 3.25f}};
  writeDepthExr((dir / "d.exr").string(), depth);
  const FloatImage d = readImage((dir / "d.exr").string());
  ASSERT_EQ(d.channels, 1u);
  EXPECT_EQ(d.pixels, depth.pixels);
}

TEST(ImageIo, ErrorsNameTheFile) {
  const auto dir = test::freshTempDir();
  const std::string bad = (dir / "no_such_folder" / "x.png").string();
  try {
    writePng(bad, gradientImage(4, 4), true);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
  }
  EXPECT_TRUE(filesIn(dir).empty());
  try {
    readImage((dir / "missing.exr").string());
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("missing.exr"), std::string::npos) << e.what();
  }
  EXPECT_THROW(writePng((dir / "y.png").string(), FloatImage{2, 2, 4, {}}, true), Error);
}

TEST(ImageIo, OutputProblemsAreFoundBeforeWriting) {
  const auto dir = test::freshTempDir();
  const auto at = [&](const char* name) { return (dir / name).string(); };
  EXPECT_EQ(imageOutputProblem(at("a.png"), ImageOutputKind::Color8), "");
  EXPECT_EQ(imageOutputProblem(at("a.exr"), ImageOutputKind::FloatExr), "");
  EXPECT_EQ(imageOutputProblem(at("a.EXR"), ImageOutputKind::FloatExr), "");
  EXPECT_EQ(imageOutputProblem("relative.png", ImageOutputKind::Color8), "");
  EXPECT_EQ(imageOutputProblem(at("a.png"), ImageOutputKind::FloatExr),
            "expected a file name ending in .exr (float data)");
  EXPECT_EQ(imageOutputProblem(at("a.tif"), ImageOutputKind::FloatExr),
            "expected a file name ending in .exr (float data)");
  EXPECT_EQ(imageOutputProblem(at("noextension"), ImageOutputKind::Color8),
            "expected a name and an extension such as .png, got 'noextension'");
  EXPECT_EQ(imageOutputProblem(at(".png"), ImageOutputKind::Color8),
            "expected a name and an extension such as .png, got '.png'");
  EXPECT_EQ(imageOutputProblem(at("a.unknownext"), ImageOutputKind::Color8),
            "no image writer for this extension; use .png");
  EXPECT_EQ(imageOutputProblem(at("none/a.png"), ImageOutputKind::Color8),
            "its folder '" + at("none") + "' does not exist");
  EXPECT_EQ(std::filesystem::directory_iterator(dir),
            std::filesystem::directory_iterator());  // wrote nothing
}

}  // namespace
}  // namespace ropecast
