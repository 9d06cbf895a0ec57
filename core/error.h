// ropecast::Error: the one exception type library code throws for runtime failures (bad file, I/O, GL), and
// UsageError, the Error of a request that cannot work as written.
// The message names the function, file or option and what was expected; the CLI prints it and exits non-zero.
// Library code never exits the process. Any thread may throw it.
#pragma once

#include <cstdio>
#include <stdexcept>
#include <string>

namespace ropecast {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A request that cannot run as written, however sound its files: options that exclude each other, a value out
// of its range, a budget too small for one of the input's bricks, a malformed procedural spec. The CLI exits
// 2 for it, as for its parser's own usage errors, and 1 for a plain Error.
class UsageError : public Error {
 public:
  using Error::Error;
};

// A number in a message as a person writes it (%g: 50, 25.5, 1e+308, inf, nan); std::to_string prints
// 1e308 as 309 digits and 0.01 as 0.010000.
inline std::string formatNumber(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

}  // namespace ropecast
