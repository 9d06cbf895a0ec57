// For the fuzz targets whose code under test reads a path: each input written whole to one file, replacing
// the last, in a private folder of the fuzzing process (readers that look at the file's folder see it
// alone). Aborts (a finding the fuzzer reports) where it cannot. One thread.
#pragma once

#include <stdlib.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace ropecast::fuzz {

// `data` written to `fileName` in the process's folder (made at the first call); returns its path.
inline const std::string& writeInputFile(const char* fileName, const uint8_t* data, size_t size) {
  static const std::string path = [&] {
    char folder[] = "/tmp/ropecast_fuzz_XXXXXX";
    if (!mkdtemp(folder)) std::abort();
    return std::string(folder) + "/" + fileName;
  }();
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f || std::fwrite(data, 1, size, f) != size || std::fclose(f) != 0) std::abort();
  return path;
}

}  // namespace ropecast::fuzz
