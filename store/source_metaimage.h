// The MetaImage VolumeSource (ITK, 3D Slicer, ParaView): .mha (header and data in one file) and .mhd (the
// data in the file its ElementDataFile names, raw or zlib-compressed (CompressedData), or in a raw file per
// slice: LIST, or a file name pattern). Read through
// FileSamples (store/file_samples.h). Owned by loader/.
//
// Threads: as VolumeSource (readSlab from one thread at a time: a compressed stream is per-source state).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "store/metaimage_header.h"
#include "store/volume_source.h"

namespace ropecast {

// The header of the MetaImage file at `path` (a regular file), read as the source reads it: at most
// kMaxMetaImageHeaderBytes, which must hold its ElementDataFile line. Throws ropecast::Error naming the file.
MetaImageHeader readMetaImageHeaderFile(const std::string& path);
// The file holding the data of the header read from `headerPath`: the header's own file (LOCAL), or the file
// its ElementDataFile names (relative to the header's folder).
std::string metaImageDataPath(const MetaImageHeader& header, const std::string& headerPath);
// Every file holding its data: metaImageDataPath's, or each slice's file (LIST, a pattern).
std::vector<std::string> metaImageDataPaths(const MetaImageHeader& header, const std::string& headerPath);

// Spacing from options overrides the header's. Throws ropecast::Error naming the file (header or data) and
// the problem: malformed header (see parseMetaImageHeader), missing data file, data shorter than the header
// says (raw data at once; compressed data as it is read).
std::unique_ptr<VolumeSource> openMetaImageSource(const std::string& path, const SourceOptions& options);

}  // namespace ropecast
