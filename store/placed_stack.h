// A stack of parallel slices drawn where their file places them: a DICOM series acquired with a tilted gantry
// (each slice moved within its plane against the one below it) or with a slice missing (one gap twice the
// others) is resampled onto a regular grid that holds every slice where it lies, instead of being stacked
// straight and evenly. 3D Slicer's acquisition geometry regularization and dcm2niix's gantry tilt correction
// do the same. Values are interpolated linearly (bilinearly within a slice, then across slices); samples of
// the grid that no slice reaches take the smallest value of the bottom slice (the scanner's padding, or air).
//
// Threads: planSlices any thread; the source resampleSlices returns is a VolumeSource (readSlab from one
// thread at a time).
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "store/volume_source.h"

namespace ropecast {

// A slice moved less than this within its plane (in samples, against a straight stack) stays where the stack
// puts it: resampling would blur more than the move misplaces.
inline constexpr double kShearSamplesResampled = 0.5;
// Gaps between slices whose largest is more than this times the smallest (a missing slice, a change of
// thickness) are resampled; smaller variations (rounded positions) are stacked at their average.
inline constexpr double kGapRatioResampled = 1.5;
// A grid that would hold more than this many times the stack's samples is not made (slices that far apart are
// no gantry tilt): they are stacked straight.
inline constexpr double kMostGrowthResampled = 4.0;

// The regular grid that holds every slice where it lies.
struct SliceGrid {
  glm::u32vec3 dims{0};
  glm::dvec3 spacing{1.0};  // in-plane the slices', across the smallest gap (or the average: gaps even)
  glm::dvec3 origin{0.0};   // where the grid's sample (0, 0, 0) lies, in the positions' frame
  // Where each slice lies in the grid, in samples: x and y of its sample (0, 0), z its grid slice (a fraction
  // between two where it falls between them).
  std::vector<glm::dvec3> slices;
};

// How slices are stacked.
struct SlicePlan {
  std::optional<double> averageGap;  // the stack's extent along its normal over its gaps (two slices or more)
  std::optional<SliceGrid> grid;     // absent: stacked straight, averageGap apart
  std::vector<std::string> notes;    // what a person should hear about it
};

// Where the slices of `stacked` (info of a source of them in stacking order, a z slice each, its spacing in
// x and y theirs) lie: `positions[k]` is slice k's sample (0, 0) in the frame the info's axes point in (LPS
// for DICOM), whose x and y run along the slices' rows and columns and z along their normal. The positions
// increase along z (stacking order; two at one position are the caller's to refuse). Notes call the slices
// `what` ("the DICOM slices"). Throws ropecast::Error when positions and slices differ in number.
SlicePlan planSlices(const VolumeInfo& stacked, std::span<const glm::dvec3> positions,
                     const std::string& what);

// A volume whose file gives its axes as vectors not at right angles (`vectors`: x, y and z in the frame of
// `info`'s origin, LPS for medical files, their lengths the spacings) where x and y are at right angles:
// slices whose stacking direction is skewed, as a gantry tilt written into a file's directions leaves them.
// Turns `info` (dims and type set) into the slices' frame: axes x, y and their normal on z's side (a
// mirroring frame where that is how they turn), spacing x's and y's lengths and the gap along the normal;
// plans where the slices lie (planSlices, its notes added to info's, calling the slices `what`), the grid in
// `grid` when they are to be resampled. False, `info` untouched, where x and y are not at right angles
// either, or z lies in their plane.
bool placeSkewedSlices(VolumeInfo& info, const std::array<glm::dvec3, 3>& vectors, const std::string& what,
                       std::optional<SliceGrid>& grid);

// The slices of `stacked` on `grid`; its info is that of `stacked` with the grid's dims, spacing and origin
// (where it has one; the value range kept: interpolation stays within it). Reads the bottom slice for the
// value outside the slices; throws as `stacked` does.
std::unique_ptr<VolumeSource> resampleSlices(std::unique_ptr<VolumeSource> stacked, SliceGrid grid);

}  // namespace ropecast
