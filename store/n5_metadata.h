// N5 metadata as the N5 source reads it (store/source_n5.h): a dataset's `attributes.json` (dimensions,
// block size, data type, compression), the calibration N5 writers leave among the attributes (N5 Viewer's
// pixelResolution, Paintera's resolution and offset, COSEM's transform), a group's first multiscale dataset,
// and the header before a block's samples. N5 lists axes fastest first; everything here is slowest first, as
// Zarr's C order and store/array_axes.h have them.
// Pure functions; any thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/sample_type.h"
#include "store/chunk_codecs.h"

namespace ropecast {

struct N5Dataset {
  std::vector<uint64_t> shape;      // samples per axis, slowest first
  std::vector<uint64_t> blockSize;  // samples per block and axis, slowest first (edge blocks may be cut)
  SampleType type = SampleType::UInt8;
  std::optional<Compressor> compressor;  // none: raw
};

// Whether `attributes` (an attributes.json) describe a dataset: they hold 'dimensions'. Throws
// ropecast::Error naming `where` when they are not a JSON object.
bool isN5Dataset(std::string_view attributes, const std::string& where);

// A dataset's attributes, parsed. Throws ropecast::Error naming `where` and the field: not JSON, no or
// malformed dimensions or blockSize (of another length, a zero block, blocks past 2 GiB), a data type other
// than 8-, 16- and 32-bit integers and 32- and 64-bit floats (64-bit integers, object), a compression other
// than raw, gzip (and zlib), bzip2, xz, lz4, blosc and zstd.
N5Dataset parseN5Dataset(std::string_view attributes, const std::string& where);

// Per axis, slowest first: where samples lie apart and where the first lies, from a dataset's or a group's
// attributes: COSEM's `transform` (its axes named, its lists in its `ordering`), else N5 Viewer's
// `pixelResolution` (a list, or an object with `dimensions`), else Paintera's `resolution`, with `offset`.
struct N5Calibration {
  std::vector<std::string> axisNames;  // lower case; only COSEM's transform names them
  std::optional<std::vector<double>> scale, translation;
  std::string attribute;  // the one read, for the source's description ("pixelResolution")
};
// Empty (nothing known) when the attributes hold none of them. Throws ropecast::Error naming `where` when
// one of them is there but malformed (not a list of numbers, axes and scale of different lengths).
N5Calibration parseN5Calibration(std::string_view attributes, const std::string& where);

// A pyramid level's `downsamplingFactors` (N5 Viewer's, Paintera's, BigDataViewer's: per axis, how many of
// the full resolution's samples one of the level's spans), slowest first; nullopt when the attributes hold
// none. Their pixelResolution or resolution, on the group, is the full resolution's. Throws ropecast::Error
// naming `where` when they are not a list of numbers.
std::optional<std::vector<double>> parseN5DownsamplingFactors(std::string_view attributes,
                                                              const std::string& where);

// The path of a group's first multiscale dataset from its attributes' `multiscales` (as OME-NGFF's, which
// COSEM writes into N5 groups), or nullopt when there is none. Throws ropecast::Error naming `where` when
// `multiscales` is malformed.
std::optional<std::string> n5MultiscaleDataset(std::string_view attributes, const std::string& where);

// A block's header (big-endian): its mode (0 default, 1 a count of samples follows), its number of axes, its
// samples per axis (cut at the dataset's far edges), for mode 1 the count.
struct N5BlockHeader {
  std::vector<uint64_t> size;  // samples per axis, slowest first
  size_t bytes = 0;            // the header's, before the (compressed) samples
};
// Parses the header of a block of a dataset of `rank` axes. Returns the problem ("" when none): too short, an
// object block (mode 2), another number of axes, a count of samples other than the axes' product.
std::string parseN5BlockHeader(std::span<const std::byte> block, size_t rank, N5BlockHeader& header);

}  // namespace ropecast
