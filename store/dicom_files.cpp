// Recognizing DICOM files by their signature (store/source_dicom.h), without GDCM: the ropecast executable
// chooses a volume's reader with it before it loads the image module.
#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "store/source_dicom.h"

namespace ropecast {

bool startsWithDicomMagic(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;  // a FIFO would block the read
  std::array<char, 132> head{};
  std::ifstream file(path, std::ios::binary);
  return file.read(head.data(), head.size()) && std::equal(head.end() - 4, head.end(), "DICM");
}

std::vector<std::string> listDicomFiles(const std::string& directory) {
  namespace fs = std::filesystem;
  std::vector<std::string> files;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(directory, ec))
    if (entry.is_regular_file(ec) && startsWithDicomMagic(entry.path().string()))
      files.push_back(entry.path().string());
  if (ec) throw Error("cannot list DICOM folder " + directory + ": " + ec.message());
  std::sort(files.begin(), files.end());
  return files;
}

std::vector<std::string> listDicomFilesBelow(const std::string& directory) {
  namespace fs = std::filesystem;
  std::vector<std::string> files;
  std::error_code ec;
  size_t entries = 0;
  fs::recursive_directory_iterator it(directory, fs::directory_options::skip_permission_denied, ec);
  for (; !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (++entries > kDicomSearchEntries)
      throw Error("the search of " + directory + " for DICOM images stopped after " +
                  std::to_string(kDicomSearchEntries) + " files and folders (" +
                  std::to_string(kDicomSearchDepth) +
                  " levels down); give the folder of one series, or one of its images");
    if (it.depth() >= kDicomSearchDepth) it.disable_recursion_pending();  // its entries would lie deeper
    std::error_code fileError;                                            // a dangling link is passed over
    if (it.depth() > 0 && it->is_regular_file(fileError) && startsWithDicomMagic(it->path().string()))
      files.push_back(it->path().string());
  }
  if (ec) throw Error("cannot list DICOM folder " + directory + ": " + ec.message());
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace ropecast
