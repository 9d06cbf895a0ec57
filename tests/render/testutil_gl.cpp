#include "tests/render/testutil_gl.h"

#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

#include <gtest/gtest.h>

namespace ropecast::test {

GlContext& sharedGlContext() {
  static std::unique_ptr<GlContext> context = std::make_unique<GlContext>();
  return *context;
}

double psnrDb(const FloatImage& a, const FloatImage& b, uint32_t channels) {
  if (a.width != b.width || a.height != b.height || a.channels < channels || b.channels < channels)
    throw std::invalid_argument("psnrDb: images differ in size or channels");
  double sum = 0.0;
  const size_t n = size_t(a.width) * a.height;
  for (size_t p = 0; p < n; ++p)
    for (uint32_t c = 0; c < channels; ++c) {
      const double d = double(a.pixels[p * a.channels + c]) - double(b.pixels[p * b.channels + c]);
      sum += d * d;
    }
  const double mse = sum / double(n * channels);
  return mse == 0.0 ? std::numeric_limits<double>::infinity() : 10.0 * std::log10(1.0 / mse);
}

double maxAbsDifference(const FloatImage& a, const FloatImage& b, uint32_t channels) {
  if (a.width != b.width || a.height != b.height || a.channels < channels || b.channels < channels)
    throw std::invalid_argument("maxAbsDifference: images differ in size or channels");
  double worst = 0.0;
  const size_t n = size_t(a.width) * a.height;
  for (size_t p = 0; p < n; ++p)
    for (uint32_t c = 0; c < channels; ++c) {
      const float x = a.pixels[p * a.channels + c], y = b.pixels[p * b.channels + c];
      if (x == y) continue;  // also inf == inf
      const double d = std::abs(double(x) - double(y));
      worst = std::isnan(d) ? std::numeric_limits<double>::infinity() : std::max(worst, d);
    }
  return worst;
}

std::filesystem::path freshTempDir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = "ropecast_gltest";
  if (info) name += std::string("_") + info->test_suite_name() + "_" + info->name();
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace ropecast::test
