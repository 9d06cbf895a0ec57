// Checks and reads for the files a command takes as input. A path that is not a regular file (a FIFO, a
// device such as /dev/zero, a socket) is refused before it is opened: opening a FIFO blocks until a writer
// comes, and a device may never end. Small text inputs (transfer functions, camera paths, suites, scripts)
// are read whole, up to a size past which they cannot be what they claim. Pure functions of the file system;
// any thread.
#pragma once

#include <cstddef>
#include <string>

namespace ropecast {

// Larger than any transfer function, camera path, regression suite or viewer script a person writes.
inline constexpr size_t kMaxTextInputBytes = size_t(64) << 20;

// Throws ropecast::Error "WHAT: reason" unless `path` names a regular file (symbolic links followed).
void requireRegularFile(const std::string& path, const std::string& what);

// The whole of the regular file `path`, at most `maxBytes`. Throws ropecast::Error "WHAT: reason" when it is
// missing, not a regular file, larger, or cannot be read.
std::string readTextInput(const std::string& path, const std::string& what,
                          size_t maxBytes = kMaxTextInputBytes);

}  // namespace ropecast
