#include "store/source_vtk.h"

#include <algorithm>

#include "core/error.h"
#include "store/file_samples.h"
#include "store/source_raw.h"
#include "store/text_samples.h"

namespace ropecast {

VtkHeader readVtkHeaderFile(const std::string& path) {
  const PosixFile file(path);
  return parseVtkHeader(file.readStart(kMaxVtkHeaderBytes), path);
}

std::unique_ptr<VolumeSource> openVtkSource(const std::string& path, const SourceOptions& options) {
  const VtkHeader header = readVtkHeaderFile(path);
  VolumeInfo info;
  info.dims = header.sizes;
  info.type = header.type;
  info.spacing = options.spacing.value_or(header.spacing);
  info.origin = header.origin;
  info.description = "vtk:" + path + " (" + header.arrayName + ")";
  if (header.ascii) {
    TextSamples text;
    text.start = header.headerBytes;
    text.fileKind = "legacy VTK file";
    text.scale = header.colorScalars ? 255.0 : 1.0;  // VTK writes color scalars in ASCII as fractions
    return openTextSampleSource(std::move(info), std::make_unique<PosixFile>(path), std::move(text));
  }
  SampleBlock block;
  block.fileKind = "legacy VTK file";
  block.volume = formatDims(header.sizes) + " " + std::string(sampleTypeName(header.type));
  block.bytes = header.dataBytes();
  block.start = header.headerBytes;
  return openBlockSource(std::move(info),
                         std::make_unique<FileSamples>(std::make_unique<PosixFile>(path), std::move(block)),
                         /*storedBigEndian=*/true);
}

}  // namespace ropecast
