// Zarr metadata as the Zarr source reads it (store/source_zarr.h): a v2 array's `.zarray` or a v3 array's
// `zarr.json` (shape, chunks and shards, sample type and byte order, codecs, fill value, order, chunk keys)
// and, for an OME-Zarr image, the `multiscales` of its `.zattrs` or `zarr.json` (the full-resolution
// dataset's path, the axes' names, its scale and translation).
// Pure functions; any thread.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/sample_type.h"

namespace ropecast {

// A bytes-to-bytes codec: a v2 array's compressor, or one of a v3 array's codecs.
// Lz4: numcodecs' (the decompressed size as 4 bytes, little-endian, then an LZ4 block); Lzma: an .xz or
// .lzma stream; Bz2: a bzip2 stream.
enum class ZarrCodec : uint8_t { Blosc, Zlib, Gzip, Zstd, Lz4, Lzma, Bz2, Crc32c };

// A v3 array's `sharding_indexed` codec: each stored chunk (a shard) holds inner chunks, each encoded on its
// own, and an index of where they lie.
struct ZarrSharding {
  std::vector<uint64_t> chunks;   // samples per inner chunk and axis (the shard's a whole multiple)
  std::vector<ZarrCodec> codecs;  // the inner chunks' bytes-to-bytes codecs, in encoding order
  bool bigEndian = false;         // the inner chunks' samples
  bool indexAtEnd = true;         // "end" (the default) or "start"
  bool indexChecksum = false;     // the index is followed by a CRC-32C (not checked)
};

struct ZarrArray {
  std::vector<uint64_t> shape;   // samples per axis, the last varying fastest in C order
  std::vector<uint64_t> chunks;  // samples per stored chunk and axis (edge chunks are stored whole)
  SampleType type = SampleType::UInt8;
  bool bigEndian = false;
  std::vector<ZarrCodec> codecs;  // bytes-to-bytes, in encoding order (decoded in reverse)
  std::optional<ZarrSharding> sharding;
  double fillValue = 0.0;     // samples of chunks not stored (null: 0)
  bool fortranOrder = false;  // v2's "F": the first axis varies fastest within a chunk
  std::string keyPrefix;      // before a chunk's indices in its key: v3's default encoding "c/", else ""
  char separator = '.';       // between chunk indices in a chunk's key: "0.1.2" or "0/1/2"
  std::vector<std::string> dimensionNames;  // v3's `dimension_names`, lower case; empty when not all named

  uint64_t chunkSamples() const;
};

// The `.zarray` of a v2 array at `where` (named in messages), parsed. Throws ropecast::Error naming `where`
// and the field: not JSON, not zarr_format 2, shapes of different lengths or with zero chunks, a sample type
// other than 8-, 16- and 32-bit integers and 32- and 64-bit floats (bool, 64-bit integers, half floats,
// complex, records), a compressor other than blosc, zlib, gzip, zstd, lz4, lzma (not its raw format) and bz2,
// filters.
ZarrArray parseZarrArray(std::string_view text, const std::string& where);

// What a v3 `zarr.json` describes: "array", "group", or another node_type as written ("" when none).
// Throws ropecast::Error naming `where` when it is not JSON.
std::string zarrV3NodeType(std::string_view text, const std::string& where);

// The `zarr.json` of a v3 array, parsed, with the same refusals and: a node that is not an array, a chunk
// grid other than "regular", a chunk key encoding other than "default" and "v2", codecs other than bytes,
// blosc, gzip, zstd, crc32c, sharding_indexed and numcodecs' compressors (numcodecs.zlib, .gzip, .zstd,
// .blosc, .lz4, .lzma, .bz2) (transpose, nested sharding, numcodecs' filters), more than one compressor in a
// chain.
ZarrArray parseZarrV3Array(std::string_view text, const std::string& where);

struct OmeMultiscale {
  std::string datasetPath;  // the dataset's path: the first (full resolution), or the one asked for
  std::vector<std::string> axisNames;        // lower case; empty when the image names no axes
  std::optional<std::vector<double>> scale;  // per axis, the dataset's scale times the image's
  // Per axis, where the first sample lies: the dataset's translation, then the image's scale and translation
  std::optional<std::vector<double>> translation;
  // The `omero` block's channel labels, in order, where it labels every channel; else empty.
  std::vector<std::string> channelLabels;
};

// The first multiscale image of a `.zattrs` (OME-NGFF 0.1 to 0.4) or of a group's `zarr.json` (0.5: under
// attributes.ome), or nullopt when it holds none. Throws
// ropecast::Error naming `where` when `multiscales` is there but malformed (no datasets, a path that is not
// a string, a scale of another length than the axes).
// With `datasetPath`, the image's dataset of that path instead (a level given alone), or nullopt when the
// image lists none such.
std::optional<OmeMultiscale> parseOmeMultiscale(std::string_view text, const std::string& where,
                                                std::string_view datasetPath = "");

}  // namespace ropecast
