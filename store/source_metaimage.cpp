#include "store/source_metaimage.h"

#include <algorithm>
#include <optional>

#include "core/error.h"
#include "core/header_text.h"
#include "store/file_samples.h"
#include "store/source_raw.h"

namespace ropecast {

MetaImageHeader readMetaImageHeaderFile(const std::string& path) {
  const PosixFile file(path);
  const std::string text = file.readStart(kMaxMetaImageHeaderBytes);
  const auto tooLong = [&] {
    return Error("MetaImage header " + path + ": longer than the " +
                 std::to_string(kMaxMetaImageHeaderBytes) +
                 " bytes read as a header (no whole ElementDataFile line within them)");
  };
  MetaImageHeader header;
  try {
    header = parseMetaImageHeader(text, path);
  } catch (const Error&) {
    if (file.sizeBytes() > text.size() && lowerAscii(text).find("elementdatafile") == std::string::npos)
      throw tooLong();
    throw;
  }
  // An ElementDataFile line cut where the reading stopped could name another file.
  if (file.sizeBytes() > text.size() && text[header.headerBytes - 1] != '\n') throw tooLong();
  return header;
}

std::string metaImageDataPath(const MetaImageHeader& header, const std::string& headerPath) {
  return header.dataFile.empty() ? headerPath : pathBesideHeader(headerPath, header.dataFile);
}

std::unique_ptr<VolumeSource> openMetaImageSource(const std::string& path, const SourceOptions& options) {
  const MetaImageHeader header = readMetaImageHeaderFile(path);
  auto data = openDataFile(metaImageDataPath(header, path), "MetaImage header", path, header.dataFile);
  SampleBlock block;
  block.fileKind = "MetaImage data file";
  block.volume = formatDims(header.sizes) + " " + std::string(sampleTypeName(header.type));
  block.bytes = header.dataBytes();
  if (header.compressed) block.encoding = SampleEncoding::Deflated;
  if (header.headerSize == -1)
    block.start = std::nullopt;
  else
    block.start = (header.dataFile.empty() ? header.headerBytes : 0) + uint64_t(header.headerSize);

  VolumeInfo info;
  info.dims = header.sizes;
  info.type = header.type;
  info.spacing = options.spacing.value_or(header.spacing);
  info.description = "metaimage:" + path;
  info.axes = header.axes;
  info.origin = header.origin;
  info.patientFrame = header.anatomicalOrientation && !header.matrixNotApplied;
  if (header.matrixNotApplied) info.notes.push_back(unappliedTransformNote(path, "its TransformMatrix"));
  return openBlockSource(std::move(info), std::make_unique<FileSamples>(std::move(data), std::move(block)),
                         header.bigEndian);
}

}  // namespace ropecast
