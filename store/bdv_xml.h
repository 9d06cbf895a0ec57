// BigDataViewer's dataset XML (Fiji's BigDataViewer, BigStitcher, Multiview Reconstruction: a `.xml` beside
// its HDF5 file or N5 container): which file or container holds the images, its view setups (their size and
// voxel size) and time points. The HDF5 source (store/source_hdf5.h) and the N5 source (store/source_n5.h)
// read a dataset's one view from it. Parsed with expat; pure functions; any thread.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "store/picked_volume.h"

namespace ropecast {

struct BdvSetup {
  int id = 0;
  std::string name;                     // empty where the XML names none
  std::optional<glm::dvec3> voxelSize;  // x, y, z
  std::string unit;                     // the voxel size's ("µm", "micron", ...)
};

// How the images are stored: the XML's ImageLoader format, "bdv.hdf5" or "bdv.n5".
enum class BdvImageFormat : uint8_t { Hdf5, N5 };

struct BdvDataset {
  BdvImageFormat format = BdvImageFormat::Hdf5;
  std::string images;  // the HDF5 file or the N5 container's folder, from the XML's folder and its BasePath
  std::vector<BdvSetup> setups;
  std::vector<int> timepoints;
};

// Whether `path` names an XML file whose root element is SpimData (read: its first 4 KiB).
bool isBdvXml(const std::string& path);

// Parses the XML `text` of the file `path` (its folder resolves relative paths). Throws ropecast::Error
// naming the file: not well-formed, no SpimData root, an image loader other than "bdv.hdf5" and "bdv.n5", no
// setups, a
// setup's id or voxel size that is not numbers, time points of a kind not read.
BdvDataset parseBdvXml(std::string_view text, const std::string& path);

// The view of `dataset` (the XML `xml`) that --time (its time points, in the XML's order) and --channel (its
// view setups, their names said beside their numbers) pick, by default the first of each. Throws UsageError
// as pickVolume does.
PickedVolume pickBdvView(const BdvDataset& dataset, const SourceOptions& options, const std::string& xml);

// The HDF5 dataset of a view's full resolution: "/t00000/s00/0/cells".
std::string bdvCellsPath(int timepoint, int setup);
// The N5 dataset of a view's full resolution, within the container: "setup0/timepoint0/s0".
std::string bdvN5DatasetPath(int timepoint, int setup);
// Whether a dataset path is one of BigDataViewer's images ("/t00000/s00/0/cells", any level), whose signed
// 16-bit samples hold unsigned ones.
bool isBdvCellsPath(std::string_view datasetPath);

}  // namespace ropecast
