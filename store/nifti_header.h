// NIfTI header parsing (NIfTI-1 and NIfTI-2, https://nifti.nimh.nih.gov/nifti-1/): the part of the NIfTI
// source that sees untrusted bytes, a pure function over the header's bytes, fuzzed by
// fuzz/nifti_header_fuzz.cpp. Used by the NIfTI volume source (store/). Pure function; any thread.
//
// Supported: both versions in either byte order, single files ("n+1", "n+2": .nii, .nii.gz) and header/image
// pairs ("ni1", "ni2": .hdr with .img), and the ANALYZE 7.5 headers NIfTI-1 grew from (a .hdr without NIfTI's
// magic: the same sizes, datatype, pixdim, vox_offset and SPM's scale factor; no orientation); 3 to 7
// dimensions (the 4th time, the 5th to 7th a sample's components, as NIfTI names them: a time series or a
// vector field is a series of volumes); the scalar datatypes int8, uint8, int16, uint16, int32, uint32,
// float32 and float64; pixdim 1-3 as spacing; scl_slope and scl_inter; whether the qform or sform turns the
// axes, and where it places the first sample.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include <glm/vec3.hpp>

#include "core/orientation.h"
#include "core/sample_type.h"

namespace ropecast {

// The bytes a header needs: NIfTI-1's 348, NIfTI-2's 540.
constexpr size_t kNifti1HeaderBytes = 348, kNifti2HeaderBytes = 540;

struct NiftiHeader {
  int version = 1;          // 1 or 2
  bool pairedFile = false;  // "ni1"/"ni2", or ANALYZE: the samples are in the .img beside the .hdr
  // An ANALYZE 7.5 header: where NIfTI keeps its qform and sform, ANALYZE keeps an orientation code whose
  // left and right readers disagree on, so the axes stay as stored and no origin is given.
  bool analyze = false;
  SampleType type = SampleType::UInt8;
  glm::u32vec3 sizes{0};  // samples per axis, axis 0 fastest
  // Volumes after one another: dim[4] time points, each of dim[5] * dim[6] * dim[7] components (1 where the
  // file has fewer dimensions); the volume of time point t and component c is the (c * timePoints + t)-th.
  uint64_t timePoints = 1, components = 1;
  glm::dvec3 spacing{1.0};      // |pixdim[1..3]| (1 where zero or not finite)
  bool spacingUnknown = false;  // some pixdim[1..3] was zero or not finite
  bool bigEndian = false;       // the header's and the samples' byte order
  uint64_t voxOffset = 0;       // where the samples start in their file (decompressed, for .nii.gz)
  // Values are slope * stored + intercept where scaled (scl_slope non-zero and finite, and not 1 with
  // intercept 0).
  bool scaled = false;
  double slope = 1.0, intercept = 0.0;
  // Where the axes point (core/orientation.h): the sform's or qform's (whichever the file says to use)
  // directions, turned from NIfTI's RAS into LPS. Identity where the file sets neither.
  AxisDirections axes{1.0};
  bool transformNotApplied = false;  // an sform whose columns are not at right angles (a sheared grid)
  // Such an sform's three axis vectors (spacing included) and its offset, in LPS, where all are finite: a
  // source may place the slices they stack (store/placed_stack.h placeSkewedSlices).
  std::optional<std::array<glm::dvec3, 4>> shearedSform;
  // The center of the first sample in LPS: the sform's offsets, or the qform's (qoffset), with the axes they
  // turn; absent where neither is applied or they are not finite.
  std::optional<glm::dvec3> origin;

  uint64_t dataBytes() const { return uint64_t(sizes.x) * sizes.y * sizes.z * bytesPerSample(type); }
};

// Parses a header from `bytes` (at least its first 348 bytes; 540 for NIfTI-2). `fileName` is only used in
// messages. Throws ropecast::Error naming the file and the field for: no NIfTI header (neither size in either
// byte order, or a magic other than the four, unless an ANALYZE header is allowed), fewer dimensions than 3
// or more than 7, all the volumes' samples more than 2^62 bytes, sizes that are not positive or overflow,
// unsupported datatypes (complex, RGB, 64-bit integers, ...), a bitpix that does not match the datatype, and
// a vox_offset before the header's end (single files). `analyzeAllowed`: a 348-byte header without NIfTI's
// magic is read as ANALYZE 7.5 (the header of a .hdr and .img pair); else it is refused.
NiftiHeader parseNiftiHeader(std::span<const std::byte> bytes, const std::string& fileName,
                             bool analyzeAllowed = false);

// NIfTI's datatype code of a sample type (extract's NIfTI files write it).
int16_t niftiDatatypeOf(SampleType type);

}  // namespace ropecast
