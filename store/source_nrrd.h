// The NRRD VolumeSource: .nrrd (header and data in one file) and .nhdr (detached data), raw or gzip encoded.
// Raw data is read with pread; gzip data is inflated as a stream, forward, while slabs are read in order (a
// read of an earlier slab restarts the stream). Owned by loader/.
//
// Threads: as VolumeSource (readSlab from one thread at a time: the gzip stream is per-source state).
#pragma once

#include <memory>
#include <string>

#include "store/nrrd_header.h"
#include "store/volume_source.h"

namespace ropecast {

// The header of the NRRD file at `path` (a regular file: a FIFO would block), read as the source reads it: at
// most kMaxNrrdHeaderBytes. A header that does not end within them is refused (its data file, say, could be
// cut to another file's name). Throws ropecast::Error naming the file.
NrrdHeader readNrrdHeaderFile(const std::string& path);
// The file holding the data of the header read from `headerPath`: the header's own file, or its detached data
// file (relative to the header's folder).
std::string nrrdDataPath(const NrrdHeader& header, const std::string& headerPath);

// Spacing from options overrides the header's. Throws ropecast::Error naming the file (header or data) and
// the problem: malformed header (see parseNrrdHeader), missing data file, data shorter than the header says.
std::unique_ptr<VolumeSource> openNrrdSource(const std::string& path, const SourceOptions& options);

}  // namespace ropecast
