// The VTK XML image data VolumeSource (.vti files of VTK and ParaView): the point data's active scalars,
// stored appended (raw or base64) or inline (base64), plain or in zlib blocks, read slab by slab without
// reading the rest of the file (a slab decodes the base64 quads and decompresses the blocks it touches).
// Owned by loader/.
//
// Threads: as VolumeSource (readSlab from one thread at a time: the last block decompressed is kept).
#pragma once

#include <memory>
#include <string>

#include "store/volume_source.h"
#include "store/vti_header.h"

namespace ropecast {

// The header of the .vti file at `path` (a regular file), read as the source reads it: at most
// kMaxVtiHeaderBytes. Throws ropecast::Error naming the file.
VtiHeader readVtiHeaderFile(const std::string& path);

// Spacing from options overrides the header's. Throws ropecast::Error naming the file and the problem:
// malformed or unsupported header (see parseVtiHeader), a data header that disagrees with the extent (a
// byte count or compression header for another size), data past the end of the file (at once), damaged base64
// or zlib blocks (as they are read).
std::unique_ptr<VolumeSource> openVtiSource(const std::string& path, const SourceOptions& options);

}  // namespace ropecast
