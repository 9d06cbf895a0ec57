// MetaImage header parsing (ITK's MetaIO format, https://itk.org/Wiki/ITK/MetaIO/Documentation): the part of
// the MetaImage source that sees untrusted text, a pure function over a string, fuzzed by
// fuzz/metaimage_header_fuzz.cpp. Used by the MetaImage volume source (store/). Pure function; any thread.
//
// Supported: "Key = Value" lines (keys in any case) up to ElementDataFile, which ends the header as MetaIO
// says it must (but for LIST's file names, which follow it): ObjectType Image, NDims 3, DimSize, ElementType
// (MET_CHAR, MET_UCHAR, MET_SHORT, MET_USHORT, MET_INT, MET_UINT, MET_LONG, MET_ULONG (32-bit in MetaIO),
// MET_FLOAT, MET_DOUBLE), ElementSpacing (else ElementSize), BinaryData, BinaryDataByteOrderMSB or
// ElementByteOrderMSB, CompressedData (a zlib stream; with a file per slice, one each), HeaderSize (-1: the
// data ends the file; with a file per slice, each file's), ElementNumberOfChannels (interleaved),
// TransformMatrix (or Rotation or Orientation: only whether it turns the axes), Offset (or Origin, Position),
// ElementDataFile LOCAL, one file, or a file per slice (LIST, or a file name pattern). Other keys are
// ignored.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "core/orientation.h"
#include "core/sample_type.h"

namespace ropecast {

// The most of a file read as its header (readMetaImageHeaderFile in store/source_metaimage.h).
constexpr size_t kMaxMetaImageHeaderBytes = size_t(1) << 20;

struct MetaImageHeader {
  SampleType type = SampleType::UInt8;
  glm::u32vec3 sizes{0};    // samples per axis, axis 0 fastest
  uint32_t channels = 1;    // ElementNumberOfChannels: samples per point, one after another
  glm::dvec3 spacing{1.0};  // ElementSpacing, else ElementSize (1 where neither is given)
  // Where the axes point (core/orientation.h), LPS as ITK writes it: TransformMatrix's three rows, the
  // directions of x, y and z. Identity without one.
  AxisDirections axes{1.0};
  bool matrixNotApplied = false;  // a TransformMatrix whose rows are not at right angles (a sheared grid)
  // Such a matrix's rows (directions of x, y and z, not yet scaled by the spacing), where all are finite: a
  // source may place the slices they stack (store/placed_stack.h placeSkewedSlices).
  std::optional<std::array<glm::dvec3, 3>> shearedMatrix;
  std::optional<glm::dvec3> origin;  // Offset (or Origin, Position): the first sample's center, in LPS
  // AnatomicalOrientation names a patient's frame: three letters, one of R or L, A or P, S or I ("RAI"); ITK
  // writes "???" where it does not know.
  bool anatomicalOrientation = false;
  bool compressed = false;  // CompressedData: the data is one zlib stream (a file per slice: one each)
  bool bigEndian = false;   // the data's byte order (irrelevant for 1-byte types)
  int64_t headerSize = 0;   // bytes of the data file skipped before the data; -1: data at the end
  std::string dataFile;     // ElementDataFile as written (relative to the header's folder); empty: LOCAL
  // One data file per slice, in slice order (relative to the header's folder): the names after
  // `ElementDataFile = LIST` (or `LIST 2D`), or those a pattern gives (`slice%03d.raw 1 100 1`: printf's %d
  // with a width, from the first number to the second by the third). Empty: one data file (dataFile, or
  // LOCAL).
  std::vector<std::string> sliceFiles;
  size_t headerBytes = 0;  // bytes of the header, the ElementDataFile line and its line end included

  // Of every channel.
  uint64_t dataBytes() const {
    return uint64_t(sizes.x) * sizes.y * sizes.z * channels * bytesPerSample(type);
  }
};

// Parses the header at the start of `text` (which may continue with the data: parsing stops after the
// ElementDataFile line). `fileName` is only used in messages. Throws ropecast::Error naming the file and the
// key for a missing ElementDataFile, NDims, DimSize or ElementType, malformed or out-of-range numbers, a key
// given twice, sizes that are not 3 positive integers or overflow (their channels' samples included), NDims
// other than 3,
// ASCII data, unsupported element types, a list or pattern of data files that does not give one per slice,
// and an ObjectType other than Image.
MetaImageHeader parseMetaImageHeader(std::string_view text, const std::string& fileName);

}  // namespace ropecast
