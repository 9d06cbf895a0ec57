#include "core/file_names.h"

#include <gtest/gtest.h>

#include "core/number_text.h"

namespace ropecast {
namespace {

TEST(FileNames, ExtensionsCompareInLowerCase) {
  EXPECT_EQ(lowerExtension("dir.d/Slice.TIFF"), ".tiff");
  EXPECT_EQ(lowerExtension("dir.d/README"), "");
  EXPECT_TRUE(hasExtension("a.Png", ".png"));
  EXPECT_TRUE(hasExtension("out/A.EXR", ".exr"));
  EXPECT_FALSE(hasExtension("a.png.tif", ".png"));
  EXPECT_FALSE(hasExtension("png", ".png"));
  EXPECT_FALSE(hasExtension("a.pngx", ".png"));
}

TEST(NumberText, TheWholeFieldMustBeTheNumber) {
  EXPECT_EQ(parseWholeNumber<int64_t>(" +42\t"), 42);
  EXPECT_EQ(parseWholeNumber<int64_t>("-7"), -7);
  EXPECT_EQ(parseWholeNumber<double>("0.5\r\n"), 0.5);
  EXPECT_EQ(parseWholeNumber<double>("1e3"), 1000.0);
  EXPECT_FALSE(parseWholeNumber<int64_t>(""));
  EXPECT_FALSE(parseWholeNumber<int64_t>("  "));
  EXPECT_FALSE(parseWholeNumber<int64_t>("+"));
  EXPECT_FALSE(parseWholeNumber<int64_t>("+-1"));
  EXPECT_FALSE(parseWholeNumber<int64_t>("4 2"));
  EXPECT_FALSE(parseWholeNumber<int64_t>("42mm"));
  EXPECT_FALSE(parseWholeNumber<int64_t>("1.5"));
  EXPECT_FALSE(parseWholeNumber<int64_t>("99999999999999999999"));
  EXPECT_FALSE(parseWholeNumber<uint32_t>("-1"));
}

}  // namespace
}  // namespace ropecast
