// The N5 VolumeSource: an N5 dataset (a folder whose `attributes.json` gives its dimensions, a folder of
// blocks per axis below it), or a group of them whose first multiscale dataset is read (its `multiscales`,
// else its `s0`: N5 Viewer's, BigStitcher's, Paintera's and COSEM's pyramids), as Fiji's N5 plugins, the
// Saalfeld lab's and Janelia's tools and zarr-python's N5 store write them. Blocks are read and decompressed
// (raw, gzip, zlib, bzip2, xz, lz4, blosc, zstd) a layer at a time, as Zarr chunks are (store/chunk_layer.h),
// on worker threads; a block that is not stored holds zeros. Edge blocks may be stored whole or cut at the
// dataset's edge, as the N5 format allows. Owned by loader/.
//
// Axes: COSEM's transform names them; else as store/array_axes.h chooses (--axes for more than three long
// axes). Spacing: --spacing, else the calibration store/n5_metadata.h reads (the dataset's, else its
// group's), else 1.
//
// Threads: as VolumeSource (readSlab from one thread at a time: the decoded layer is per-source state).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

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

}  // namespace ropecast
