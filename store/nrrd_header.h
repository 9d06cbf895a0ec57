// NRRD header parsing (https://teem.sourceforge.net/nrrd/format.html), the part of the NRRD source that sees
// untrusted text: a pure function over a string, fuzzed by fuzz/nrrd_header_fuzz.cpp. Used by the NRRD volume
// source (store/). Pure function; any thread.
//
// Supported: "NRRD000n" magic, dimension 3, or 4 with one axis not spatial (its kind not domain or space, or
// its space direction none) first (interleaved: a vector's components) or last (volumes one after another: a
// time series, a list of diffusion-weighted volumes), type (the NRRD spellings of int8, uint8, int16, uint16,
// int32, uint32, float and double; not the 64-bit integers or block; plain "char" is no NRRD type), sizes,
// encoding raw or gzip, endian, spacings or space directions (spacing = length of each direction), byte skip
// (-1 = data at the end of the file, raw only), line skip, data file (one detached file). Other fields,
// comments and key/value pairs are ignored.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <glm/vec3.hpp>

#include "core/orientation.h"
#include "core/sample_type.h"

namespace ropecast {

// The most of a file read as its header (readNrrdHeaderFile in store/source_nrrd.h, for the NRRD source and
// for whoever must know the data file a header names before the source opens, the output guard).
constexpr size_t kMaxNrrdHeaderBytes = size_t(1) << 20;

enum class NrrdEncoding : uint8_t { Raw, Gzip };

struct NrrdHeader {
  SampleType type = SampleType::UInt8;
  glm::u32vec3 sizes{0};    // samples per axis, axis 0 fastest
  glm::dvec3 spacing{1.0};  // from spacings or the lengths of space directions (1 where unknown)
  // Where the axes point (core/orientation.h): the space directions' directions, turned from the "space"
  // field's anatomical frame (RAS, LAS, ...) into LPS; other spaces as they are. Identity without them.
  AxisDirections axes{1.0};
  // Space directions that are not three orthogonal 3-vectors (a sheared grid, a "none"): only their lengths
  // are used (as spacing), and axes stays the identity.
  bool directionsNotApplied = false;
  // Those directions where they are three 3-vectors not at right angles (a sheared grid), turned into LPS as
  // the axes are: a source may place the slices they stack (store/placed_stack.h placeSkewedSlices).
  std::optional<std::array<glm::dvec3, 3>> shearedDirections;
  // The "space" field names a patient's frame (right-anterior-superior, LPS, ... and their -time forms), not
  // scanner-xyz or a 3D-handed space.
  bool anatomicalSpace = false;
  // The "space origin" (the center of the first sample), turned into LPS as the axes are; absent without one,
  // or when it is not three finite numbers (originNotRead: said to the user, the samples read the same).
  std::optional<glm::dvec3> origin;
  bool originNotRead = false;
  NrrdEncoding encoding = NrrdEncoding::Raw;
  bool bigEndian = false;  // the data's byte order (irrelevant for 1-byte types)
  int64_t byteSkip = 0;  // bytes to skip before the data (after decompression for gzip); -1: data at the end
  int64_t lineSkip = 0;  // lines to skip before the data (before decompression)
  std::string dataFile;  // detached data file as written (relative to the header's folder); empty: attached
  size_t headerBytes = 0;          // bytes of the header including the blank line that ends it
  bool endsWithBlankLine = false;  // false: the text ended without the blank line (fine for .nhdr only)

  // Dimension 4: the samples of `volumes` volumes, interleaved (the non-spatial axis first) or one after
  // another (last); a time series where that axis' kind is "time". One volume otherwise.
  uint32_t volumes = 1;
  bool volumesInterleaved = false;
  bool volumesAreTimePoints = false;

  // Of one volume.
  uint64_t dataBytes() const { return uint64_t(sizes.x) * sizes.y * sizes.z * bytesPerSample(type); }
};

// Parses the header at the start of `text` (which may continue with the data; parsing stops at the first
// empty line). `fileName` is only used in messages. Throws ropecast::Error naming the file and the field for
// a bad magic line, a missing required field (dimension, type, sizes, encoding, endian for multi-byte types),
// malformed or out-of-range numbers, sizes that are not positive integers or overflow (every volume's samples
// included), dimension other than 3 or 4, a 4th axis that is not one or lies between spatial ones,
// unsupported types and encodings.
NrrdHeader parseNrrdHeader(std::string_view text, const std::string& fileName);

}  // namespace ropecast
