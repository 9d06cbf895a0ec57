// finiteIn: the check of floating-point options, which CLI::Range is not (it passes "nan").
#include <gtest/gtest.h>

#include "tools/cli_checks.h"

namespace ropecast::tools {
namespace {

// The check's verdict on `text`: "" when accepted.
std::string verdict(const CLI::Validator& check, std::string text) {
  return check(text);
}

TEST(FiniteIn, AcceptsFiniteNumbersInRange) {
  const CLI::Validator unit = finiteIn(0.0, 1.0);
  EXPECT_EQ(verdict(unit, "0"), "");
  EXPECT_EQ(verdict(unit, "0.99"), "");
  EXPECT_EQ(verdict(unit, "1"), "");
  EXPECT_EQ(verdict(finiteIn(-HUGE_VAL, HUGE_VAL), "-1e300"), "");
}

TEST(FiniteIn, RefusesNanInfinityAndOutOfRange) {
  const CLI::Validator unit = finiteIn(0.0, 1.0);
  for (const char* bad : {"nan", "NaN", "inf", "-inf", "1.5", "-0.1", "opaque"})
    EXPECT_EQ(verdict(unit, bad), std::string("expected a finite number in [0, 1], got '") + bad + "'");
  EXPECT_EQ(verdict(finiteIn(-HUGE_VAL, HUGE_VAL), "nan"), "expected a finite number, got 'nan'");
  EXPECT_EQ(verdict(finiteIn(-HUGE_VAL, HUGE_VAL), "inf"), "expected a finite number, got 'inf'");
}

}  // namespace
}  // namespace ropecast::tools
