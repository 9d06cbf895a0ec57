// The Zarr VolumeSource: a Zarr array, v2 (a folder holding `.zarray` and its chunk files) or v3
// (`zarr.json`, sharded or not), or an OME-Zarr image (a folder whose `.zattrs`, or v3 `zarr.json`, holds
// `multiscales`: its first, full-resolution dataset; an array that is one of an image's levels takes the
// image's axes and that level's scale), as microscopy (OME-NGFF 0.1 to 0.5, napari, webKnossos
// exports) and simulation pipelines write them. Chunks (or shards) are read and decompressed
// (store/chunk_codecs.h) a layer at a time (up to kZarrMaxBufferedBytes), on worker threads; a chunk that is
// not stored holds the array's fill value. Owned by loader/.
//
// Axes: an OME-Zarr image's named z, y, x (its other axes, time and channel, of length 1), else a v3 array's
// dimension names when they name z, y and x, else as store/array_axes.h chooses. Spacing: --spacing, else the
// OME-Zarr scale of z, y, x, else 1.
//
// Threads: as VolumeSource (readSlab from one thread at a time: the decoded layer is per-source state).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "store/volume_source.h"

namespace ropecast {

// Whether `path` is a folder of Zarr metadata: `.zarray`, `.zgroup` or `.zattrs` (v2), or `zarr.json` (v3).
bool isZarrFolder(const std::string& path);

// The decoded slices a source keeps: a whole layer of chunks when it fits (each chunk decoded once), else as
// many slices of the layer as fit (its chunks decoded again for each such band), so that a conversion's
// memory stays bounded whatever the chunks' depth.
inline constexpr uint64_t kZarrMaxBufferedBytes = uint64_t(256) << 20;

// Throws ropecast::Error naming the folder (the `.zarray`, the chunk file) and the problem: no array (a group
// without multiscales lists the arrays below it), malformed metadata (store/zarr_metadata.h), an array that
// is not a volume, Zarr v3; and, as slabs are read, a chunk that does not decompress to its size.
// `maxBufferedBytes` bounds the decoded slices (tests make it small).
std::unique_ptr<VolumeSource> openZarrSource(const std::string& path, const SourceOptions& options,
                                             uint64_t maxBufferedBytes = kZarrMaxBufferedBytes);

}  // namespace ropecast
