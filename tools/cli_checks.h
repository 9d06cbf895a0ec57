// CLI11 checks for option values. CLI::Range lets "nan" through (every comparison with NaN is false), so a
// NaN opacity, field of view or voxel size reached the renderer; finiteIn refuses it. Main thread.
#pragma once

#include <cmath>
#include <string>

#include <CLI/CLI.hpp>

#include "core/error.h"

namespace ropecast::tools {

// A finite number in [lo, hi], or in (lo, hi] with lowOpen; the bounds may be infinite ("any finite number":
// finiteIn(-HUGE_VAL, HUGE_VAL)).
inline CLI::Validator finiteIn(double lo, double hi, bool lowOpen = false) {
  std::string range;  // of the finite bounds: "in [0, inf]" would promise infinity
  if (!std::isinf(lo) && !std::isinf(hi))
    range = std::string(lowOpen ? " in (" : " in [") + formatNumber(lo) + ", " + formatNumber(hi) + "]";
  else if (!std::isinf(lo))
    range = (lowOpen ? " > " : " >= ") + formatNumber(lo);
  else if (!std::isinf(hi))
    range = " <= " + formatNumber(hi);
  return CLI::Validator(
      [lo, hi, lowOpen, range](std::string& input) -> std::string {
        double v = 0.0;
        if (!CLI::detail::lexical_cast(input, v) || !std::isfinite(v) || v < lo || (lowOpen && v == lo) ||
            v > hi)
          return "expected a finite number" + range + ", got '" + input + "'";
        return "";
      },
      range.empty() ? "" : "FLOAT" + range, "finiteIn");
}

// A finite number in (lo, hi].
inline CLI::Validator finiteAbove(double lo, double hi) {
  return finiteIn(lo, hi, true);
}

// An input that is not empty (`--tf "$UNSET"` is a slip: taken as not given, it would silently do nothing);
// `what` says what it names ("a preset or a JSON file").
inline CLI::Validator notEmpty(const std::string& what) {
  return CLI::Validator(
      [what](const std::string& value) -> std::string {
        return value.empty() ? "expected " + what + ", got ''" : "";
      },
      "", "notEmpty");
}

// A path that is not empty (`-o ""` is a slip, not a name), nor "-", which other tools read as standard
// output, where ropecast writes nothing (its outputs are written whole and renamed into place); `what` says
// what it names ("a file", "a folder").
inline CLI::Validator nonEmptyPath(const std::string& what) {
  return CLI::Validator(
      [what](const std::string& path) -> std::string {
        if (path.empty()) return "expected " + what + " name, got ''";
        if (path == "-") return "expected " + what + " name, got '-' (standard output is not written to)";
        return "";
      },
      "", "nonEmptyPath");
}

}  // namespace ropecast::tools
