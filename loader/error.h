// ropecast::Error: the one exception type library code throws for runtime failures (bad file, I/O, GL).
// The message names the function, file or option and what was expected; the CLI prints it and exits non-zero.
// Library code never exits the process. Any thread may throw it.
#pragma once

#include <stdexcept>
#include <string>

namespace ropecast {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace ropecast
