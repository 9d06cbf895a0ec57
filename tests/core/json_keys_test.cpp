// duplicateJsonKey: the first key an object repeats, at any depth; none in valid files and in text that is
// not JSON.
#include "core/json_keys.h"

#include <gtest/gtest.h>

namespace ropecast {
namespace {

TEST(DuplicateJsonKey, FindsTheFirstKeyAnObjectRepeats) {
  EXPECT_EQ(duplicateJsonKey(R"({"a": 1, "b": 2, "a": 3})"), "a");
  EXPECT_EQ(duplicateJsonKey(R"([{"x": {"y": 1, "z": [{"q": 1, "q": 2}]}}])"), "q");
  EXPECT_EQ(duplicateJsonKey(R"({"a": {"k": 1}, "b": {"k": 2}})"), "") << "equal keys of two objects";
  EXPECT_EQ(duplicateJsonKey(R"({"a": [{"k": 1}, {"k": 2}]})"), "");
  EXPECT_EQ(duplicateJsonKey(R"({"a": 1, "A": 2})"), "") << "keys are case-sensitive";
  EXPECT_EQ(duplicateJsonKey("{\"a\": "), "") << "not JSON: the caller's parse says why";
  EXPECT_EQ(duplicateJsonKey("[]"), "");
}

}  // namespace
}  // namespace ropecast
