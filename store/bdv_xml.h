// BigDataViewer's dataset XML (Fiji's BigDataViewer, BigStitcher, Multiview Reconstruction: a `.xml` beside
// its HDF5 file): which HDF5 file holds the images, its view setups (their size and voxel size) and time
// points. The HDF5 source reads a dataset's one view from it (store/source_hdf5.h). Parsed with expat; pure
// functions; any thread.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

namespace ropecast {

struct BdvSetup {
  int id = 0;
  std::string name;                     // empty where the XML names none
  std::optional<glm::dvec3> voxelSize;  // x, y, z
  std::string unit;                     // the voxel size's ("µm", "micron", ...)
};

struct BdvDataset {
  std::string hdf5File;  // the path of the HDF5 file, from the XML's folder and its BasePath
  std::vector<BdvSetup> setups;
  std::vector<int> timepoints;
};

// Whether `path` names an XML file whose root element is SpimData (read: its first 4 KiB).
bool isBdvXml(const std::string& path);

// Parses the XML `text` of the file `path` (its folder resolves relative paths). Throws ropecast::Error
// naming the file: not well-formed, no SpimData root, an image loader other than "bdv.hdf5", no setups, a
// setup's id or voxel size that is not numbers, time points of a kind not read.
BdvDataset parseBdvXml(std::string_view text, const std::string& path);

// The HDF5 dataset of a view's full resolution: "/t00000/s00/0/cells".
std::string bdvCellsPath(int timepoint, int setup);
// Whether a dataset path is one of BigDataViewer's images ("/t00000/s00/0/cells", any level), whose signed
// 16-bit samples hold unsigned ones.
bool isBdvCellsPath(std::string_view datasetPath);

}  // namespace ropecast
