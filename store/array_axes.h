// Which three axes of an N-dimensional array (HDF5 datasets, Zarr arrays) are a volume's z, y and x: the
// axes longer than 1, in order, padded with the length-1 axes nearest before the first of them (else the
// first length-1 axes), so that a time point and a channel around z, y, x (tczyx, zyxc) fall away. Named axes
// (OME-Zarr's) are chosen by name instead, and a time or channel axis among them may be longer (one of its
// volumes is read). Pure functions; any thread.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace ropecast {

struct ArrayAxes {
  std::array<int, 3> zyx{};     // indices into the array's axes
  int time = -1, channel = -1;  // the axes named t and c, by name only; -1: none
  std::string problem;          // empty when the array is a volume; else why not ("it has 2 axes (3x4)...")
};

// "2x5x6x9"; "a scalar" for no axes.
std::string formatExtent(std::span<const uint64_t> extent);

// By length: three axes of any length, or more when all but three have length 1.
ArrayAxes volumeAxes(std::span<const uint64_t> extent);

// By name (lower case): the axes named z, y and x; one named t, one named c, and every other of length 1.
ArrayAxes volumeAxesNamed(std::span<const uint64_t> extent, const std::vector<std::string>& names);

// --axes's letters ("tzyx") as names, one per axis; a problem when they are not each of t, c, z, y and x at
// most once with z, y and x among them.
struct GivenAxisNames {
  std::vector<std::string> names;
  std::string problem;
};
GivenAxisNames axisNamesOf(const std::string& letters);

// The axes of an array that names none itself (`names` empty) or names them (an OME-Zarr image's, ilastik's
// axistags), with --axes (`given`) where given: by its names, else by length. `where` names the array in
// the refusal of --axes for an array that names its axes, or of letters of another count than its axes.
ArrayAxes arrayAxesOf(std::span<const uint64_t> extent, const std::vector<std::string>& names,
                      const std::string& given);

}  // namespace ropecast
