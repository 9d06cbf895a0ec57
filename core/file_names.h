// File-name checks by extension, case-insensitive: which reader or writer a path asks for. Pure functions;
// any thread.
#pragma once

#include <string>
#include <string_view>

namespace ropecast {

// The extension of `path`'s file name with its dot, in lower case (".png"); "" when it has none.
std::string lowerExtension(const std::string& path);

// Whether `path`'s extension is `lowerDotted` (".exr") in any case.
bool hasExtension(const std::string& path, std::string_view lowerDotted);

}  // namespace ropecast
