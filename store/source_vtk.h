// The legacy VTK VolumeSource (.vtk files of VTK and ParaView): STRUCTURED_POINTS, the volume being the point
// data's first SCALARS (or FIELD array) of one component; BINARY files big-endian as VTK writes them, read
// through FileSamples (store/file_samples.h), ASCII ones through TextSamples (store/text_samples.h).
//
// Threads: as VolumeSource.
#pragma once

#include <memory>
#include <string>

#include "store/volume_source.h"
#include "store/vtk_header.h"

namespace ropecast {

// The header of the legacy VTK file at `path` (a regular file), read as the source reads it: at most
// kMaxVtkHeaderBytes. Throws ropecast::Error naming the file.
VtkHeader readVtkHeaderFile(const std::string& path);

// Spacing from options overrides the header's. Throws ropecast::Error naming the file and the problem:
// malformed or unsupported header (see parseVtkHeader), a file shorter than its samples.
std::unique_ptr<VolumeSource> openVtkSource(const std::string& path, const SourceOptions& options);

}  // namespace ropecast
