// Writes small DICOM images with GDCM, for the DICOM source's tests and the command-line test's series
// (tests/cli/write_dicom_series.cpp). Test code only; any thread.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace ropecast::testing {

// One image (several frames where `frames` says so), in Explicit VR Little Endian. Header values left empty
// or unset are not written.
struct DicomSliceSpec {
  uint32_t columns = 5, rows = 4;
  uint16_t bitsAllocated = 16, bitsStored = 12;
  bool isSigned = false;
  uint16_t samplesPerPixel = 1;
  std::vector<int64_t> stored;  // rows * columns * samplesPerPixel stored values, row by row
  std::optional<glm::dvec3> position = glm::dvec3(0.0);
  std::optional<std::array<double, 6>> orientation = std::array<double, 6>{1, 0, 0, 0, 1, 0};
  std::optional<int> instance;
  std::optional<int> temporalPosition;  // Temporal Position Identifier (0020,0100)
  std::optional<double> slope, intercept;
  std::optional<glm::dvec2> pixelSpacing =
      glm::dvec2(0.75, 0.5);       // as the header orders it: row spacing first
  std::optional<uint32_t> frames;  // Number of Frames: `stored` holds them one after another
  std::optional<double> spacingBetweenSlices;
  // Written as an Enhanced CT image when set (one position per frame): the positions in the per-frame
  // functional groups, the orientation, pixel spacing (with a Slice Thickness of 1) and rescale in the shared
  // ones, none of them at the top level.
  std::vector<glm::dvec3> framePositions;
  // The pixel data's length in bytes where it is not what the size says (a file that lies about it); 0: the
  // size's.
  size_t pixelDataBytes = 0;
  std::string seriesUid = "1.2.826.0.1.3680043.9.7607.1";
  std::string modality = "CT", seriesDescription, photometric = "MONOCHROME2";
};

void writeDicomSlice(const std::string& path, const DicomSliceSpec& spec);

// A DICOM file without an image (a Basic Text SR header): what a DICOMDIR or a report in a series folder is.
void writeDicomWithoutImage(const std::string& path);

}  // namespace ropecast::testing
