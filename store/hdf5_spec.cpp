#include "store/hdf5_spec.h"

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>

#include "core/file_names.h"

namespace ropecast {
namespace {

constexpr std::array<char, 8> kHdf5Signature = {'\x89', 'H', 'D', 'F', '\r', '\n', '\x1a', '\n'};

bool isHdf5File(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec) &&
         (hasHdf5Extension(path) || startsWithHdf5Signature(path));
}

}  // namespace

bool hasHdf5Extension(const std::string& path) {
  const std::string ext = lowerExtension(path);
  return ext == ".h5" || ext == ".hdf5" || ext == ".he5" || ext == ".hdf" || ext == ".ims" || ext == ".nc";
}

bool startsWithHdf5Signature(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;  // a FIFO would block the read
  std::array<char, kHdf5Signature.size()> start{};
  std::ifstream file(path, std::ios::binary);
  return file.read(start.data(), start.size()) && start == kHdf5Signature;
}

std::optional<Hdf5Spec> hdf5SpecOf(const std::string& spec) {
  if (isHdf5File(spec)) return Hdf5Spec{spec, ""};
  for (size_t colon = spec.find(':'); colon != std::string::npos; colon = spec.find(':', colon + 1)) {
    const std::string file = spec.substr(0, colon);
    if (!file.empty() && isHdf5File(file)) return Hdf5Spec{file, spec.substr(colon + 1)};
  }
  return std::nullopt;
}

}  // namespace ropecast
