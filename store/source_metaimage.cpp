#include "store/source_metaimage.h"

#include <algorithm>
#include <optional>

#include "core/error.h"
#include "core/header_text.h"
#include "store/file_samples.h"
#include "store/picked_volume.h"
#include "store/placed_stack.h"
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
  block.volume = formatDims(header.sizes) + " " + std::string(sampleTypeName(header.type)) +
                 (header.channels > 1 ? " of " + std::to_string(header.channels) + " channels" : "");
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
  const PickedVolume picked = pickVolume(options, {1, header.channels}, "MetaImage " + path);
  info.description = "metaimage:" + path;
  describePicked(info, picked);
  info.axes = header.axes;
  info.origin = header.origin;
  // A matrix whose third row alone is off the slices' normal (a gantry's tilt kept in the file): the slices
  // are placed where they lie.
  std::optional<SliceGrid> grid;
  bool placed = false;
  if (header.shearedMatrix && !options.spacing) {
    const auto& m = *header.shearedMatrix;
    const glm::dvec3 s = header.spacing;
    placed = placeSkewedSlices(info, {m[0] * s.x, m[1] * s.y, m[2] * s.z}, "the slices of " + path, grid);
  }
  info.patientFrame = header.anatomicalOrientation && (placed || !header.matrixNotApplied);
  if (header.matrixNotApplied && !placed)
    info.notes.push_back(unappliedTransformNote(path, "its TransformMatrix"));
  auto samples = std::make_unique<FileSamples>(std::move(data), std::move(block));
  std::unique_ptr<VolumeSource> source;
  if (header.channels == 1) {
    source = openBlockSource(std::move(info), std::move(samples), header.bigEndian);
  } else {
    // Channels are interleaved: read as rows of channels times as many samples, one channel kept.
    if (uint64_t(header.sizes.x) * header.channels > UINT32_MAX)
      throw Error("MetaImage " + path + ": rows of " + std::to_string(header.sizes.x) + " samples of " +
                  std::to_string(header.channels) + " channels each are too long to read");
    VolumeInfo stored;
    stored.dims = {header.sizes.x * header.channels, header.sizes.y, header.sizes.z};
    stored.type = header.type;
    stored.description = info.description;
    source = pickComponent(openBlockSource(std::move(stored), std::move(samples), header.bigEndian),
                           header.channels, picked.channel, std::move(info));
  }
  if (grid) return resampleSlices(std::move(source), std::move(*grid));
  return source;
}

}  // namespace ropecast
