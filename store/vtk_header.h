// Legacy VTK header parsing (the ".vtk" files of VTK and ParaView, "VTK File Formats", legacy section): the
// part of the legacy VTK source that sees untrusted text, a pure function over a string, fuzzed by
// fuzz/volume_headers_fuzz.cpp. Used by the legacy VTK volume source (store/). Pure function; any thread.
//
// Supported: BINARY files (big-endian samples, as VTK writes them) and ASCII files (the samples as numbers
// separated by blanks and line ends) of DATASET STRUCTURED_POINTS with
// DIMENSIONS, SPACING (or ASPECT_RATIO) and ORIGIN in any order, then POINT_DATA whose first attribute is
// SCALARS of one component (an optional LOOKUP_TABLE line after it), COLOR_SCALARS of one (how VTK writes
// unsigned char scalars) or a FIELD whose first array has one component; keywords in any case. Types: char,
// unsigned_char, short, unsigned_short, int, unsigned_int, float, double (and VTK 9's vtktypeint8 ...
// vtktypeuint32 spellings of the integers).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <glm/vec3.hpp>

#include "core/sample_type.h"

namespace ropecast {

// The most of a file read as its header (readVtkHeaderFile in store/source_vtk.h).
constexpr size_t kMaxVtkHeaderBytes = size_t(1) << 20;

struct VtkHeader {
  SampleType type = SampleType::UInt8;
  glm::u32vec3 sizes{0};             // DIMENSIONS: samples per axis, axis 0 fastest
  glm::dvec3 spacing{1.0};           // SPACING (or ASPECT_RATIO): 1 where not given
  std::optional<glm::dvec3> origin;  // ORIGIN: the first sample's place
  std::string arrayName;             // the SCALARS' or FIELD array's name, for the description
  size_t headerBytes = 0;            // where the samples start: after the line that ends the header
  bool ascii = false;                // ASCII: the samples are numbers in text
  // COLOR_SCALARS: unsigned char samples, which an ASCII file writes as fractions of 255 ("0.501961")
  bool colorScalars = false;

  uint64_t dataBytes() const { return uint64_t(sizes.x) * sizes.y * sizes.z * bytesPerSample(type); }
};

// Parses the header at the start of `text` (which goes on with the samples). `fileName` is only used in
// messages. Throws ropecast::Error naming the file and the line for: no "# vtk DataFile Version" line, a
// format other than ASCII or BINARY, datasets other than STRUCTURED_POINTS, missing or malformed DIMENSIONS,
// spacings that are zero or not numbers, a POINT_DATA count other than the samples of DIMENSIONS, cell data
// or attributes other than scalars first, several components, unsupported types (bit, long, 64-bit), and a
// text that ends before the samples.
VtkHeader parseVtkHeader(std::string_view text, const std::string& fileName);

}  // namespace ropecast
