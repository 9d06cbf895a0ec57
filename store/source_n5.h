// The N5 VolumeSource: an N5 dataset (a folder whose `attributes.json` gives its dimensions, a folder of
// blocks per axis below it), or a group of them whose first multiscale dataset is read (its `multiscales`,
// else its `s0`: N5 Viewer's, BigStitcher's, Paintera's and COSEM's pyramids), as Fiji's N5 plugins, the
// Saalfeld lab's and Janelia's tools and zarr-python's N5 store write them. Blocks are read and decompressed
// (raw, gzip, zlib, bzip2, xz, lz4, blosc, zstd) a layer at a time, as Zarr chunks are (store/chunk_layer.h),
// on worker threads; a block that is not stored holds zeros. Edge blocks may be stored whole or cut at the
// dataset's edge, as the N5 format allows. Owned by loader/.
//
// A BigDataViewer XML whose images are in N5 (BigStitcher's "bdv.n5") reads one view, as the HDF5 source
// reads those in HDF5.
//
// Axes: COSEM's transform names them; else as store/array_axes.h chooses (--axes for more than three long
// axes). Spacing: --spacing, else the calibration store/n5_metadata.h reads (the dataset's, else its
// group's times the dataset's downsampling factors, for a pyramid's level given alone), else 1.
//
// Threads: as VolumeSource (readSlab from one thread at a time: the decoded layer is per-source state).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "store/bdv_xml.h"
#include "store/volume_source.h"

namespace ropecast {

// Whether `path` is a folder of N5 attributes (`attributes.json`) and not a Zarr array's.
bool isN5Folder(const std::string& path);

// The decoded slices a source keeps, as kZarrMaxBufferedBytes.
inline constexpr uint64_t kN5MaxBufferedBytes = uint64_t(256) << 20;

// Throws ropecast::Error naming the folder (its attributes.json, the block file) and the problem: a group
// without a multiscale dataset (it lists the datasets below it), malformed attributes (store/n5_metadata.h),
// a dataset that is not a volume; and, as slabs are read, a block whose header or samples do not fit its
// place. `maxBufferedBytes` bounds the decoded slices (tests make it small).
std::unique_ptr<VolumeSource> openN5Source(const std::string& path, const SourceOptions& options,
                                           uint64_t maxBufferedBytes = kN5MaxBufferedBytes);

// One view of a BigDataViewer dataset whose images are in an N5 container (`dataset`, parsed from the XML
// `xml`: format bdv.n5): its time point and view setup as pickBdvView picks them, the full resolution
// (setupS/timepointT/s0), at the setup's voxel size unless --spacing is given. Throws as openN5Source.
std::unique_ptr<VolumeSource> openBdvN5Source(const std::string& xml, const BdvDataset& dataset,
                                              const SourceOptions& options);

}  // namespace ropecast
