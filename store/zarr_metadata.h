// Zarr v2 metadata as the Zarr source reads it (store/source_zarr.h): an array's `.zarray` (shape, chunks,
// sample type and byte order, compressor, fill value, order, chunk key separator) and, for an OME-Zarr image,
// the `multiscales` of its `.zattrs` (the full-resolution dataset's path, the axes' names and its scale).
// Pure functions; any thread.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/sample_type.h"

namespace ropecast {

enum class ZarrCompressor : uint8_t { None, Blosc, Zlib, Gzip, Zstd };

struct ZarrArray {
  std::vector<uint64_t> shape;   // samples per axis, the last varying fastest in C order
  std::vector<uint64_t> chunks;  // samples per chunk and axis (edge chunks are stored whole)
  SampleType type = SampleType::UInt8;
  bool bigEndian = false;
  ZarrCompressor compressor = ZarrCompressor::None;
  double fillValue = 0.0;     // samples of chunks not stored (null: 0)
  bool fortranOrder = false;  // "F": the first axis varies fastest within a chunk
  char separator = '.';       // between chunk indices in a chunk's key: "0.1.2" or "0/1/2"

  uint64_t chunkSamples() const;
};

// The `.zarray` of the array at `where` (named in messages), parsed. Throws ropecast::Error naming `where`
// and the field: not JSON, not zarr_format 2, shapes of different lengths or with zero chunks, a sample type
// other than 8-, 16- and 32-bit integers and 32- and 64-bit floats (bool, 64-bit integers, half floats,
// complex, records), a compressor other than blosc, zlib, gzip and zstd, filters.
ZarrArray parseZarrArray(std::string_view text, const std::string& where);

struct OmeMultiscale {
  std::string datasetPath;                   // the first (full-resolution) dataset's path
  std::vector<std::string> axisNames;        // lower case; empty when the image names no axes
  std::optional<std::vector<double>> scale;  // per axis, the dataset's scale times the image's
};

// The first multiscale image of a `.zattrs` (OME-NGFF 0.1 to 0.4), or nullopt when it holds none. Throws
// ropecast::Error naming `where` when `multiscales` is there but malformed (no datasets, a path that is not
// a string, a scale of another length than the axes).
std::optional<OmeMultiscale> parseOmeMultiscale(std::string_view text, const std::string& where);

}  // namespace ropecast
