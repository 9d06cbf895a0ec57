// The HDF5 VolumeSource: one numeric dataset of an HDF5 file (simulation output, microscopy: ilastik, Fiji,
// BigDataViewer, Imaris .ims; netCDF-4), read slab by slab as hyperslabs through the HDF5 library, so every
// layout (contiguous, chunked, compact), byte order and built-in filter (deflate, shuffle, szip, checksums)
// reads as it is stored; a chunked dataset whose filters are none or shuffle and deflate is read a layer of
// chunks at a time as the file stores them, and decoded on one thread per core (store/chunk_layer.h). Read in
// ropecast's image module (tools/image_module.h). Owned by loader/.
//
// Threads: as VolumeSource (readSlab from one thread at a time); the library is called from that thread only.
//
// The input is FILE or FILE:/PATH/TO/DATASET (store/hdf5_spec.h), or a BigDataViewer XML (store/bdv_xml.h):
// its one view's full resolution, at its setup's voxel size, signed 16-bit cells read as unsigned (several
// views are an error that lists their datasets). Without a path: an Imaris file's full resolution, first time
// point and channel; else the file's one dataset that is a volume (several or none is an error that lists
// them). A volume is a dataset of 8-, 16- or 32-bit integers or of 32- or 64-bit floats
// whose axes, in HDF5's order (the last varies fastest), are z, y, x; more than three axes are taken when all
// but three have length 1 (a time point and a channel of ilastik's and BigDataViewer's layouts). Spacing:
// --spacing, else an `element_size_um` attribute (z, y, x: ilastik, Fiji), else Imaris's extents, else 1.
#pragma once

#include <memory>
#include <string>

#include "store/volume_source.h"

namespace ropecast {

// Throws ropecast::Error naming the file (and dataset) and the problem: not an HDF5 file, no such dataset,
// no dataset or several that are volumes, a dataset that is not one (its type or axes), a filter the HDF5
// library lacks; and, as slabs are read, damaged data.
std::unique_ptr<VolumeSource> openHdf5Source(const std::string& spec, const SourceOptions& options);

}  // namespace ropecast
