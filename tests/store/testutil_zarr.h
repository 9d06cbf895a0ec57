// Writes Zarr arrays for the Zarr source's tests (tests/store/source_zarr_test.cpp): v2 of any shape,
// chunking, C or F order, chunk key separator, byte order and compressor (blosc, zlib, gzip, zstd, lz4, lzma,
// bz2, none), and
// v3, sharded or not, with chosen chunks left unwritten. Test code only; one thread.
#pragma once

#include <blosc.h>
#include <bzlib.h>
#include <lz4.h>
#include <lzma.h>
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
  std::string compressor = "none";  // none, blosc, zlib, gzip, zstd, lz4, lzma, bz2
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
  if (compressor == "lz4") {  // numcodecs': the size, 4 bytes little-endian, then the block
    std::string out(4 + size_t(LZ4_compressBound(int(raw.size()))), '\0');
    for (size_t i = 0; i < 4; ++i) out[i] = char(raw.size() >> (8 * i));
    out.resize(
        4 + size_t(LZ4_compress_default(raw.data(), out.data() + 4, int(raw.size()), int(out.size() - 4))));
    return out;
  }
  if (compressor == "lzma") {  // an .xz stream, numcodecs' default format
    std::string out(lzma_stream_buffer_bound(raw.size()), '\0');
    size_t size = 0;
    lzma_easy_buffer_encode(0, LZMA_CHECK_CRC64, nullptr, reinterpret_cast<const uint8_t*>(raw.data()),
                            raw.size(), reinterpret_cast<uint8_t*>(out.data()), &size, out.size());
    out.resize(size);
    return out;
  }
  if (compressor == "bz2") {
    std::string out(raw.size() + raw.size() / 100 + 600, '\0');
    unsigned size = unsigned(out.size());
    BZ2_bzBuffToBuffCompress(out.data(), &size, const_cast<char*>(raw.data()), unsigned(raw.size()), 9, 0, 0);
    out.resize(size);
    return out;
  }
  std::string out(ZSTD_compressBound(raw.size()), '\0');
  out.resize(ZSTD_compress(out.data(), out.size(), raw.data(), raw.size(), 3));
  return out;
}

// The samples of chunk `index` (chunks of `chunkShape`) of the array `values` (C order over `shape`, native
// byte order, `width` bytes each), in the chunk's own order and the given byte order; past the array's end
// zeros (never read).
inline std::string rawChunk(const std::vector<uint64_t>& shape, const std::vector<uint64_t>& chunkShape,
                            const std::vector<uint64_t>& index, const void* values, size_t width,
                            bool fortranOrder, bool bigEndian) {
  const size_t rank = shape.size();
  uint64_t samples = 1;
  for (uint64_t c : chunkShape) samples *= c;
  std::string raw(samples * width, '\0');
  std::vector<uint64_t> at(rank, 0);
  for (uint64_t i = 0; i < samples; ++i) {
    uint64_t rest = i;  // the position in the chunk of its i-th stored sample
    if (fortranOrder) {
      for (size_t a = 0; a < rank; ++a) at[a] = rest % chunkShape[a], rest /= chunkShape[a];
    } else {
      for (size_t a = rank; a-- > 0;) at[a] = rest % chunkShape[a], rest /= chunkShape[a];
    }
    bool inside = true;
    uint64_t offset = 0;
    for (size_t a = 0; a < rank; ++a) {
      const uint64_t p = index[a] * chunkShape[a] + at[a];
      inside = inside && p < shape[a];
      offset = offset * shape[a] + p;
    }
    if (inside) std::memcpy(raw.data() + i * width, static_cast<const char*>(values) + offset * width, width);
    if (bigEndian) std::reverse(raw.begin() + long(i * width), raw.begin() + long((i + 1) * width));
  }
  return raw;
}

// Calls f(index) for every index of a grid of `extent`, the last axis fastest.
template <typename F>
void forEachIndex(const std::vector<uint64_t>& extent, F&& f) {
  std::vector<uint64_t> index(extent.size(), 0);
  for (;;) {
    f(index);
    size_t a = extent.size();
    while (a-- > 0 && ++index[a] == extent[a]) index[a] = 0;
    if (a == size_t(-1)) return;
  }
}

inline std::vector<uint64_t> chunkGrid(const std::vector<uint64_t>& shape,
                                       const std::vector<uint64_t>& chunks) {
  std::vector<uint64_t> grid(shape.size());
  for (size_t a = 0; a < shape.size(); ++a) grid[a] = (shape[a] + chunks[a] - 1) / chunks[a];
  return grid;
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
  forEachIndex(chunkGrid(spec.shape, spec.chunks), [&](const std::vector<uint64_t>& index) {
    if (spec.unwritten.count(index)) return;
    const std::string raw =
        rawChunk(spec.shape, spec.chunks, index, values, width, spec.fortranOrder, spec.dtype[0] == '>');
    std::string key;
    for (size_t a = 0; a < index.size(); ++a)
      key += (a ? std::string(1, spec.separator) : "") + std::to_string(index[a]);
    const std::filesystem::path file = folder / key;
    std::filesystem::create_directories(file.parent_path());
    writeFile(file, compressedChunk(spec.compressor, raw, width));
  });
}

// A v3 array: spec.dtype is a v3 data type ("uint16"); spec.compressor one of none, blosc, gzip, zstd, or
// numcodecs' as numcodecs.zarr3 names them ("numcodecs.lz4": the compressors of compressedChunk), with a
// crc32c codec after it; keys "c/0/1/2". With `innerChunks`, spec.chunks are shards of such inner chunks
// (index at the end, with a checksum), and spec.unwritten names inner chunks (global indices) left out (a
// shard all of whose inner chunks are left out is not written).
struct ZarrV3Options {
  bool bigEndian = false;
  std::vector<uint64_t> innerChunks;  // empty: not sharded
  std::vector<std::string> dimensionNames;
};

inline void writeZarrV3Array(const std::filesystem::path& folder, const ZarrArraySpec& spec,
                             const ZarrV3Options& v3, const void* values, size_t width) {
  std::filesystem::create_directories(folder);
  nlohmann::json chain = nlohmann::json::array(
      {{{"name", "bytes"}, {"configuration", {{"endian", v3.bigEndian ? "big" : "little"}}}}});
  if (spec.compressor == "blosc")
    chain.push_back(
        {{"name", "blosc"},
         {"configuration", {{"cname", "lz4"}, {"clevel", 5}, {"shuffle", "shuffle"}, {"typesize", width}}}});
  else if (spec.compressor != "none")
    chain.push_back({{"name", spec.compressor}, {"configuration", {{"level", 1}}}});
  chain.push_back({{"name", "crc32c"}});
  nlohmann::json codecs = chain;
  if (!v3.innerChunks.empty())
    codecs = nlohmann::json::array(
        {{{"name", "sharding_indexed"},
          {"configuration",
           {{"chunk_shape", v3.innerChunks},
            {"codecs", chain},
            {"index_codecs",
             nlohmann::json::array(
                 {{{"name", "bytes"}, {"configuration", {{"endian", "little"}}}}, {{"name", "crc32c"}}})},
            {"index_location", "end"}}}}});
  nlohmann::json meta = {
      {"zarr_format", 3},
      {"node_type", "array"},
      {"shape", spec.shape},
      {"data_type", spec.dtype},
      {"chunk_grid", {{"name", "regular"}, {"configuration", {{"chunk_shape", spec.chunks}}}}},
      {"chunk_key_encoding", {{"name", "default"}, {"configuration", {{"separator", "/"}}}}},
      {"fill_value", spec.fill},
      {"codecs", codecs}};
  if (!v3.dimensionNames.empty()) meta["dimension_names"] = v3.dimensionNames;
  writeFile(folder / "zarr.json", meta.dump());
  const auto encoded = [&](const std::vector<uint64_t>& chunks, const std::vector<uint64_t>& index) {
    const std::string compressor =
        spec.compressor.starts_with("numcodecs.") ? spec.compressor.substr(10) : spec.compressor;
    std::string bytes = compressedChunk(
        compressor, rawChunk(spec.shape, chunks, index, values, width, false, v3.bigEndian), width);
    return bytes + "CRC!";  // a checksum's 4 bytes (not checked by the reader)
  };
  forEachIndex(chunkGrid(spec.shape, spec.chunks), [&](const std::vector<uint64_t>& index) {
    std::string stored;
    if (v3.innerChunks.empty()) {
      if (spec.unwritten.count(index)) return;
      stored = encoded(spec.chunks, index);
    } else {
      std::vector<uint64_t> ratio(index.size());
      for (size_t a = 0; a < index.size(); ++a) ratio[a] = spec.chunks[a] / v3.innerChunks[a];
      std::string indexBytes;
      const auto appendLittleEndian = [&](uint64_t v) {
        for (int i = 0; i < 8; ++i) indexBytes += char((v >> (8 * i)) & 0xFF);
      };
      forEachIndex(ratio, [&](const std::vector<uint64_t>& local) {
        std::vector<uint64_t> global(index.size());
        for (size_t a = 0; a < index.size(); ++a) global[a] = index[a] * ratio[a] + local[a];
        if (spec.unwritten.count(global)) {
          appendLittleEndian(~uint64_t(0));
          appendLittleEndian(~uint64_t(0));
          return;
        }
        const std::string inner = encoded(v3.innerChunks, global);
        appendLittleEndian(stored.size());
        appendLittleEndian(inner.size());
        stored += inner;
      });
      if (stored.empty()) return;  // every inner chunk left out: no shard
      stored += indexBytes + "CRC!";
    }
    std::string key = "c";
    for (uint64_t i : index) key += "/" + std::to_string(i);
    const std::filesystem::path file = folder / key;
    std::filesystem::create_directories(file.parent_path());
    writeFile(file, stored);
  });
}

}  // namespace ropecast::testing
