// The arrays below a group of a hierarchical array format (a Zarr group's arrays, an N5 group's datasets),
// for the message that refuses the group and lists them. Any thread.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace ropecast {

// How far below a group arrays are looked for.
inline constexpr int kArraySearchDepth = 4;

// The folders below `group` (relative to it, sorted) for which `holdsArray` is true, at most
// kArraySearchDepth deep, not looking inside them; folders that cannot be read are passed over.
std::vector<std::string> arraysBelow(const std::string& group,
                                     const std::function<bool(const std::string& folder)>& holdsArray);

}  // namespace ropecast
