#include "core/file_names.h"

#include <cctype>
#include <filesystem>

namespace ropecast {

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

bool hasExtension(const std::string& path, std::string_view lowerDotted) {
  return lowerExtension(path) == lowerDotted;
}

}  // namespace ropecast
