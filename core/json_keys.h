// duplicateJsonKey: the JSON files people write (transfer functions, camera paths, regression suites, viewer
// scripts) are read with nlohmann::json, which keeps the last of two equal keys of an object: the first would
// silently do nothing (a suite's first "cases" never run). Readers parse as before and then ask this, to
// refuse such a file with the others it refuses. Pure function; any thread.
#pragma once

#include <string>
#include <string_view>

namespace ropecast {

// The first key that an object of `text` gives twice, or "" when none does (or `text` is not JSON: the
// caller's own parse says why).
std::string duplicateJsonKey(std::string_view text);

}  // namespace ropecast
