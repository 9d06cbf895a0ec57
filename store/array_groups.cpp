#include "store/array_groups.h"

#include <algorithm>
#include <filesystem>

namespace ropecast {

std::vector<std::string> arraysBelow(const std::string& group,
                                     const std::function<bool(const std::string& folder)>& holdsArray) {
  namespace fs = std::filesystem;
  std::vector<std::string> arrays;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(group, fs::directory_options::skip_permission_denied, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (!it->is_directory(ec)) continue;
    if (holdsArray(it->path().string())) {
      arrays.push_back(fs::relative(it->path(), group, ec).string());
      it.disable_recursion_pending();
    } else if (it.depth() + 1 >= kArraySearchDepth) {
      it.disable_recursion_pending();
    }
  }
  std::sort(arrays.begin(), arrays.end());
  return arrays;
}

}  // namespace ropecast
