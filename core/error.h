// ropecast::Error: the one exception type library code throws for runtime failures (bad file, I/O, GL).
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

// A number in a message as a person writes it (%g: 50, 25.5, 1e+308, inf, nan); std::to_string prints
// 1e308 as 309 digits and 0.01 as 0.010000.
inline std::string formatNumber(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

}  // namespace ropecast
