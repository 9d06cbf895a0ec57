// Writes Zarr v2 arrays for the Zarr source's tests (tests/store/source_zarr_test.cpp): any shape, chunking,
// C or F order, chunk key separator, byte order and compressor (blosc, zlib, gzip, zstd, none), with chosen
// chunks left unwritten. Test code only; one thread.
#pragma once

#include <blosc.h>
#include <zlib.h>
#include <zstd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/store/store_test_util.h"

namespace ropecast::testing {

struct ZarrArraySpec {
  std::vector<uint64_t> shape, chunks;
  std::string dtype = "<u2";        // numpy's: byte order, kind, bytes
  std::string compressor = "none";  // none, blosc, zlib, gzip, zstd
  bool fortranOrder = false;
  char separator = '.';
  nlohmann::json fill = 0;
  std::set<std::vector<uint64_t>> unwritten;  // chunk indices left out (they hold the fill value)
};

inline std::string compressedChunk(const std::string& compressor, const std::string& raw, size_t typeSize) {
  if (compressor == "none") return raw;
  if (compressor == "blosc") {
    std::string out(raw.size() + BLOSC_MAX_OVERHEAD, '\0');
    const int n = blosc_compress_ctx(5, BLOSC_SHUFFLE, typeSize, raw.size(), raw.data(), out.data(),
                                     out.size(), "lz4", 0, 1);
    out.resize(size_t(n));
    return out;
  }
  if (compressor == "zlib") {
    uLongf size = compressBound(uLong(raw.size()));
    std::string out(size, '\0');
    compress2(reinterpret_cast<Bytef*>(out.data()), &size, reinterpret_cast<const Bytef*>(raw.data()),
              uLong(raw.size()), 6);
    out.resize(size);
    return out;
  }
  if (compressor == "gzip") return gzipOf(raw);
  std::string out(ZSTD_compressBound(raw.size()), '\0');
  out.resize(ZSTD_compress(out.data(), out.size(), raw.data(), raw.size(), 3));
  return out;
}

// Writes the array `values` (C order over spec.shape, native byte order, `width` bytes each) to `folder`.
inline void writeZarrArray(const std::filesystem::path& folder, const ZarrArraySpec& spec, const void* values,
                           size_t width) {
  std::filesystem::create_directories(folder);
  nlohmann::json compressor = nullptr;
  if (spec.compressor == "blosc")
    compressor = {{"id", "blosc"}, {"cname", "lz4"}, {"clevel", 5}, {"shuffle", 1}, {"blocksize", 0}};
  else if (spec.compressor != "none")
    compressor = {{"id", spec.compressor}, {"level", 1}};
  const nlohmann::json meta = {{"zarr_format", 2},
                               {"shape", spec.shape},
                               {"chunks", spec.chunks},
                               {"dtype", spec.dtype},
                               {"compressor", compressor},
                               {"fill_value", spec.fill},
                               {"order", spec.fortranOrder ? "F" : "C"},
                               {"filters", nullptr},
                               {"dimension_separator", std::string(1, spec.separator)}};
  writeFile(folder / ".zarray", meta.dump());
  const size_t rank = spec.shape.size();
  std::vector<uint64_t> grid(rank), index(rank, 0);
  for (size_t a = 0; a < rank; ++a) grid[a] = (spec.shape[a] + spec.chunks[a] - 1) / spec.chunks[a];
  const bool swap = spec.dtype[0] == '>';
  for (;;) {
    if (!spec.unwritten.count(index)) {
      // The chunk's samples in its own order; past the array's end zeros (never read).
      uint64_t samples = 1;
      for (uint64_t c : spec.chunks) samples *= c;
      std::string raw(samples * width, '\0');
      std::vector<uint64_t> at(rank, 0);
      for (uint64_t i = 0; i < samples; ++i) {
        // Position in the chunk of its i-th stored sample.
        uint64_t rest = i;
        if (spec.fortranOrder) {
          for (size_t a = 0; a < rank; ++a) at[a] = rest % spec.chunks[a], rest /= spec.chunks[a];
        } else {
          for (size_t a = rank; a-- > 0;) at[a] = rest % spec.chunks[a], rest /= spec.chunks[a];
        }
        bool inside = true;
        uint64_t offset = 0;
        for (size_t a = 0; a < rank; ++a) {
          const uint64_t p = index[a] * spec.chunks[a] + at[a];
          inside = inside && p < spec.shape[a];
          offset = offset * spec.shape[a] + p;
        }
        if (inside)
          std::memcpy(raw.data() + i * width, static_cast<const char*>(values) + offset * width, width);
        if (swap) std::reverse(raw.begin() + long(i * width), raw.begin() + long((i + 1) * width));
      }
      std::string key;
      for (size_t a = 0; a < rank; ++a)
        key += (a ? std::string(1, spec.separator) : "") + std::to_string(index[a]);
      const std::filesystem::path file = folder / key;
      std::filesystem::create_directories(file.parent_path());
      writeFile(file, compressedChunk(spec.compressor, raw, width));
    }
    size_t a = rank;
    while (a-- > 0 && ++index[a] == grid[a]) index[a] = 0;
    if (a == size_t(-1)) break;
  }
}

}  // namespace ropecast::testing
