// CLI11 checks for floating-point options. CLI::Range lets "nan" through (every comparison with NaN is
// false), so a NaN opacity, field of view or voxel size reached the renderer; these refuse it. Main thread.
#pragma once

#include <cmath>
#include <string>

#include <CLI/CLI.hpp>

#include "core/error.h"

namespace ropecast::tools {

// A finite number in [lo, hi]; the bounds may be infinite ("any finite number": finiteIn(-HUGE_VAL,
// HUGE_VAL)).
inline CLI::Validator finiteIn(double lo, double hi) {
  const std::string range =
      std::isinf(lo) && std::isinf(hi) ? "" : " in [" + formatNumber(lo) + ", " + formatNumber(hi) + "]";
  return CLI::Validator(
      [lo, hi, range](std::string& input) -> std::string {
        double v = 0.0;
        if (!CLI::detail::lexical_cast(input, v) || !std::isfinite(v) || v < lo || v > hi)
          return "expected a finite number" + range + ", got '" + input + "'";
        return "";
      },
      range.empty() ? "" : "FLOAT" + range, "finiteIn");
}

}  // namespace ropecast::tools
