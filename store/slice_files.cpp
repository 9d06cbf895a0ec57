#include "store/slice_files.h"

#include <glob.h>

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "core/error.h"
#include "core/file_names.h"

namespace ropecast {

namespace fs = std::filesystem;

bool isSliceImageName(const std::string& path) {
  const std::string ext = lowerExtension(path);
  return ext == ".tif" || ext == ".tiff" || ext == ".png";
}

bool sliceNameLess(std::string_view a, std::string_view b) {
  const auto isDigit = [](char c) { return c >= '0' && c <= '9'; };
  size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (isDigit(a[i]) && isDigit(b[j])) {
      size_t iEnd = i, jEnd = j;
      while (iEnd < a.size() && isDigit(a[iEnd])) ++iEnd;
      while (jEnd < b.size() && isDigit(b[jEnd])) ++jEnd;
      // Compare the numbers without leading zeros: first by length, then digit by digit.
      size_t iStart = i, jStart = j;
      while (iStart + 1 < iEnd && a[iStart] == '0') ++iStart;
      while (jStart + 1 < jEnd && b[jStart] == '0') ++jStart;
      const std::string_view na = a.substr(iStart, iEnd - iStart), nb = b.substr(jStart, jEnd - jStart);
      if (na.size() != nb.size()) return na.size() < nb.size();
      if (na != nb) return na < nb;
      if (iEnd - i != jEnd - j) return iEnd - i < jEnd - j;  // same number: fewer leading zeros first
      i = iEnd;
      j = jEnd;
    } else {
      if (a[i] != b[j]) return (unsigned char)a[i] < (unsigned char)b[j];
      ++i;
      ++j;
    }
  }
  return a.size() - i < b.size() - j;
}

std::vector<std::string> listSliceFiles(const std::string& directoryOrPattern) {
  std::vector<std::string> files;
  std::error_code ec;
  if (fs::is_directory(directoryOrPattern, ec)) {
    for (const auto& entry : fs::directory_iterator(directoryOrPattern, ec))
      if (entry.is_regular_file() && isSliceImageName(entry.path().string()))
        files.push_back(entry.path().string());
    if (ec) throw Error("cannot list slice directory " + directoryOrPattern + ": " + ec.message());
    if (files.empty())
      throw Error("slice directory " + directoryOrPattern + " has no .tif, .tiff or .png files");
  } else {
    glob_t matches{};
    const int status = ::glob(directoryOrPattern.c_str(), 0, nullptr, &matches);
    if (status == 0)
      for (size_t i = 0; i < matches.gl_pathc; ++i)
        if (fs::is_regular_file(matches.gl_pathv[i], ec)) files.emplace_back(matches.gl_pathv[i]);
    globfree(&matches);
    if (status != 0 && status != GLOB_NOMATCH)
      throw Error("cannot expand slice pattern " + directoryOrPattern + " (glob error " +
                  std::to_string(status) + ")");
    if (files.empty()) throw Error("slice pattern " + directoryOrPattern + " matches no files");
  }
  std::sort(files.begin(), files.end(), [](const std::string& a, const std::string& b) {
    return sliceNameLess(fs::path(a).filename().string(), fs::path(b).filename().string());
  });
  return files;
}

std::string sliceNumberingNote(const std::vector<std::string>& files) {
  // The last run of digits in each file name; a name without one means the stack is not numbered.
  std::vector<std::pair<uint64_t, std::string>> numbered;
  for (const std::string& file : files) {
    const std::string name = fs::path(file).stem().string();
    const size_t end = name.find_last_of("0123456789");
    if (end == std::string::npos) return "";
    size_t begin = end;
    while (begin > 0 && std::isdigit(static_cast<unsigned char>(name[begin - 1]))) --begin;
    if (end + 1 - begin > 18) return "";
    numbered.emplace_back(std::stoull(name.substr(begin, end + 1 - begin)), file);
  }
  std::stable_sort(numbered.begin(), numbered.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (size_t i = 1; i < numbered.size(); ++i)
    if (numbered[i].first == numbered[i - 1].first)
      return "slices " + numbered[i - 1].second + " and " + numbered[i].second + " have the same number, " +
             std::to_string(numbered[i].first) + "; both are in the volume";
  const uint64_t first = numbered.front().first, last = numbered.back().first;
  const uint64_t missing = last - first + 1 - numbered.size();
  if (missing == 0) return "";
  std::string lacking;
  for (size_t i = 1, listed = 0; i < numbered.size() && listed < 3; ++i)
    for (uint64_t n = numbered[i - 1].first + 1; n < numbered[i].first && listed < 3; ++n, ++listed)
      lacking += (lacking.empty() ? "" : ", ") + std::to_string(n);
  return "slices numbered " + std::to_string(first) + " to " + std::to_string(last) + " lack " +
         std::to_string(missing) + " number(s) (" + lacking + (missing > 3 ? ", ..." : "") +
         "); the volume has " + std::to_string(numbered.size()) + " slices, one after another";
}

}  // namespace ropecast
