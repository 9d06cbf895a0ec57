// The command line's compound values: accepted forms, and errors that name the option.
#include "tools/cli_values.h"

#include <gtest/gtest.h>

#include "core/error.h"

namespace ropecast::tools {
namespace {

std::string errorOf(auto&& call) {
  try {
    call();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(CliValues, ParsesTriples) {
  EXPECT_EQ(parseTriple("1.5,2,-3", "--eye"), glm::dvec3(1.5, 2, -3));
  EXPECT_EQ(parseTriple(" 0, 0 ,1e2", "--up"), glm::dvec3(0, 0, 100));
  for (const char* bad : {"", "1,2", "1,2,3,4", "a,b,c", "1,,3", "1,2,nan"}) {
    const std::string message = errorOf([&] { parseTriple(bad, "--eye"); });
    EXPECT_NE(message.find("--eye"), std::string::npos) << "'" << bad << "' gave: " << message;
  }
}

TEST(CliValues, ParsesDims) {
  EXPECT_EQ(parseDims("301,370,316", "--dims"), glm::u32vec3(301, 370, 316));
  for (const char* bad : {"0,1,1", "-1,2,3", "1.5,2,3", "1,2", "x"})
    EXPECT_NE(errorOf([&] { parseDims(bad, "--dims"); }).find("--dims"), std::string::npos) << bad;
}

TEST(CliValues, ParsesImageSizes) {
  EXPECT_EQ(parseImageSize("512x256", "--size"), glm::u32vec2(512, 256));
  EXPECT_EQ(parseImageSize("1x1", "--size"), glm::u32vec2(1, 1));
  for (const char* bad : {"512", "0x10", "512x", "x512", "100000x10", "-5x5", "5*5"})
    EXPECT_NE(errorOf([&] { parseImageSize(bad, "--size"); }).find("--size"), std::string::npos) << bad;
}

TEST(CliValues, ParsesByteSizesInBinaryUnits) {
  EXPECT_EQ(parseBytes("1073741824", "--cpu-cache"), uint64_t(1) << 30);
  EXPECT_EQ(parseBytes("512M", "--cpu-cache"), uint64_t(512) << 20);
  EXPECT_EQ(parseBytes("2G", "--cpu-cache"), uint64_t(2) << 30);
  EXPECT_EQ(parseBytes("64K", "--cpu-cache"), uint64_t(64) << 10);
  EXPECT_EQ(parseBytes("1.5G", "--cpu-cache"), uint64_t(3) << 29);
  EXPECT_EQ(parseBytes("2GiB", "--cpu-cache"), uint64_t(2) << 30);
  for (const char* bad : {"", "M", "-1G", "12Q", "1..5G"})
    EXPECT_NE(errorOf([&] { parseBytes(bad, "--gpu-budget"); }).find("--gpu-budget"), std::string::npos)
        << bad;
}

}  // namespace
}  // namespace ropecast::tools
