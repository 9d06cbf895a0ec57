// reference/image_compare: PSNR and absolute differences against values worked out by hand.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "reference/image_compare.h"

namespace ropecast::tools {
namespace {

TEST(ImageCompare, IdenticalImagesHaveInfinitePsnr) {
  const std::vector<float> a = {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f};
  const ImageDifference d = compareImages(a, 3, a, 3, 3);
  EXPECT_TRUE(std::isinf(d.psnrDb));
  EXPECT_EQ(d.maxAbs, 0.0);
  EXPECT_EQ(d.values, 6u);
}

TEST(ImageCompare, PsnrOfAKnownError) {
  // Two RGB pixels; one value off by 0.1: MSE = 0.01 / 6, PSNR = 10 log10(600) = 27.78 dB.
  const std::vector<float> a = {0.f, 0.f, 0.f, 1.f, 1.f, 1.f};
  std::vector<float> b = a;
  b[4] = 0.9f;
  const ImageDifference d = compareImages(a, 3, b, 3, 3);
  EXPECT_NEAR(d.psnrDb, 10.0 * std::log10(600.0), 1e-4);
  EXPECT_NEAR(d.maxAbs, 0.1, 1e-6);
  EXPECT_NEAR(d.meanAbs, 0.1 / 6.0, 1e-7);
}

TEST(ImageCompare, DepthMissesMatchEachOtherAndDifferFromHits) {
  // Depth images: +inf where the ray missed. Equal misses (and NaN against NaN) differ by nothing; a miss
  // against a hit differs by an infinite amount, so the PSNR is -inf, not the +inf of identical images.
  const float inf = INFINITY;
  const std::vector<float> misses = {inf, inf, 0.5f, NAN};
  const ImageDifference same = compareImages(misses, 1, misses, 1, 1);
  EXPECT_EQ(same.psnrDb, HUGE_VAL);
  EXPECT_EQ(same.maxAbs, 0.0);
  const std::vector<float> hit = {0.25f, inf, 0.5f, NAN};
  const ImageDifference d = compareImages(misses, 1, hit, 1, 1);
  EXPECT_EQ(d.maxAbs, HUGE_VAL);
  EXPECT_EQ(d.meanAbs, HUGE_VAL);
  EXPECT_EQ(d.psnrDb, -HUGE_VAL);
  const std::vector<float> nanAgainstNumber = {inf, inf, 0.5f, 0.0f};
  EXPECT_EQ(compareImages(misses, 1, nanAgainstNumber, 1, 1).psnrDb, -HUGE_VAL);
}

TEST(ImageCompare, ComparesOnlyTheChosenChannelsOfDifferentLayouts) {
  // RGBA against RGB: alpha differs wildly but only RGB is compared.
  const std::vector<float> rgba = {0.5f, 0.25f, 1.f, 0.f, 0.f, 0.f, 0.f, 1.f};
  const std::vector<float> rgb = {0.5f, 0.25f, 1.f, 0.f, 0.f, 0.2f};
  const ImageDifference d = compareImages(rgba, 4, rgb, 3, 3);
  EXPECT_NEAR(d.maxAbs, 0.2, 1e-6);
  EXPECT_NEAR(d.psnrDb, 10.0 * std::log10(6.0 / 0.04), 1e-3);
  EXPECT_THROW(compareImages(rgba, 4, rgb, 3, 4), Error);
}

TEST(ImageCompare, RejectsImagesOfDifferentSizes) {
  const std::vector<float> a(12, 0.f), b(9, 0.f);
  EXPECT_THROW(compareImages(a, 3, b, 3, 3), Error);
  EXPECT_THROW(compareImages(a, 3, a, 3, 0), Error);
}

}  // namespace
}  // namespace ropecast::tools
