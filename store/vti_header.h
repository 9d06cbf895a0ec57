// VTK XML image data header parsing (.vti, "VTK File Formats", XML section), with expat: the part of the
// .vti source that sees untrusted text, a pure function over the file's first bytes, fuzzed by
// fuzz/volume_headers_fuzz.cpp. Used by the .vti volume source (store/). Pure function; any thread.
//
// Supported: VTKFile of type ImageData, either byte order, UInt32 or UInt64 headers, no compressor or
// vtkZLibDataCompressor, vtkLZ4DataCompressor or vtkLZMADataCompressor; one Piece covering the WholeExtent;
// the point data's active scalars (its Scalars attribute, else its first DataArray) of one component and a
// scalar type of ropecast's, stored appended (raw or base64) or inline (format "binary", base64). Spacing,
// Direction (only whether it turns the axes) and Origin are read.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <glm/vec3.hpp>

#include "core/orientation.h"
#include "core/sample_type.h"

namespace ropecast {

// The most of a file read as its header (readVtiHeaderFile in store/source_vti.h).
constexpr size_t kMaxVtiHeaderBytes = size_t(1) << 20;

// The VTKFile's compressor: how each block of a compressed array is stored (zlib, an LZ4 block, an xz
// stream).
enum class VtiCompressor : uint8_t { None, ZLib, LZ4, LZMA };

struct VtiHeader {
  SampleType type = SampleType::UInt8;
  glm::u32vec3 sizes{0};    // from WholeExtent: samples per axis, axis 0 fastest
  glm::dvec3 spacing{1.0};  // Spacing (1 where not given)
  // Where the axes point (core/orientation.h): Direction's columns (VTK's row-major matrix). Identity
  // without one.
  AxisDirections axes{1.0};
  bool directionNotApplied = false;  // a Direction whose columns are not at right angles
  std::optional<glm::dvec3>
      origin;                  // where the first sample lies: Origin, moved to the WholeExtent's low corner
  bool bigEndian = false;      // byte_order: of the samples and of the data's header words
  size_t headerWordBytes = 4;  // header_type UInt32 (4) or UInt64 (8)
  VtiCompressor compressor = VtiCompressor::None;  // the data in blocks each compressed alone, or not
  bool base64 = false;  // the data is base64 text (inline, or appended with encoding base64)
  // File offset of the array's data: its header words first (the byte count, or the compression header).
  uint64_t dataStart = 0;
  std::string arrayName;
  uint32_t components = 1;  // NumberOfComponents: samples per point, one after another

  // Of every component.
  uint64_t dataBytes() const {
    return uint64_t(sizes.x) * sizes.y * sizes.z * components * bytesPerSample(type);
  }
};

// Parses the XML at the start of `text` (the file's first bytes; the appended data may follow). `fileName`
// is only used in messages. Throws ropecast::Error naming the file for: text that is not well-formed XML
// (with expat's message and line), a VTKFile of another type, an unknown byte order, header type or
// compressor, a WholeExtent that is not 6 integers or holds no samples, several
// pieces or one that does not cover the whole extent, point data without a DataArray, components past 65536
// or whose samples pass 2^62 bytes, unsupported types (64-bit integers, strings), ASCII data, and data that
// starts past `text`.
VtiHeader parseVtiHeader(std::string_view text, const std::string& fileName);

}  // namespace ropecast
