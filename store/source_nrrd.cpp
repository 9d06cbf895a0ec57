#include "store/source_nrrd.h"

#include <algorithm>
#include <optional>
#include <vector>

#include "core/error.h"
#include "store/file_samples.h"
#include "store/nrrd_header.h"
#include "store/picked_volume.h"
#include "store/placed_stack.h"
#include "store/source_raw.h"

namespace ropecast {
namespace {

constexpr size_t kChunkBytes = size_t(1) << 18;  // compressed input read at a time, and skip buffer

// Offset just after `lines` newlines starting at `offset`.
uint64_t skipLines(const PosixFile& file, uint64_t offset, int64_t lines) {
  std::vector<std::byte> buffer(kChunkBytes);
  while (lines > 0) {
    const size_t got = file.readSomeAt(offset, buffer);
    if (got == 0)
      throw Error("NRRD data file " + file.path() + ": ends before the lines 'line skip' asks to skip");
    size_t i = 0;
    for (; i < got && lines > 0; ++i)
      if (buffer[i] == std::byte('\n')) --lines;
    offset += i;
  }
  return offset;
}

}  // namespace

NrrdHeader readNrrdHeaderFile(const std::string& path) {
  const PosixFile file(path);
  const std::string text = file.readStart(kMaxNrrdHeaderBytes);
  NrrdHeader header = parseNrrdHeader(text, path);
  if (!header.endsWithBlankLine && file.sizeBytes() > kMaxNrrdHeaderBytes)
    throw Error("NRRD header " + path + ": longer than the " + std::to_string(kMaxNrrdHeaderBytes) +
                " bytes read as a header");
  if (header.dataFile.empty() && !header.endsWithBlankLine)
    throw Error("NRRD header of " + path +
                ": no blank line ends the header (and no 'data file' field names detached data)");
  return header;
}

std::string nrrdDataPath(const NrrdHeader& header, const std::string& headerPath) {
  return header.dataFile.empty() ? headerPath : pathBesideHeader(headerPath, header.dataFile);
}

std::unique_ptr<VolumeSource> openNrrdSource(const std::string& path, const SourceOptions& options) {
  const NrrdHeader header = readNrrdHeaderFile(path);
  auto data = openDataFile(nrrdDataPath(header, path), "NRRD header", path, header.dataFile);
  SampleBlock block;
  block.fileKind = "NRRD data file";
  block.volume = formatDims(header.sizes) + " " + std::string(sampleTypeName(header.type)) +
                 (header.volumes > 1 ? " times " + std::to_string(header.volumes) : "");
  block.bytes = header.dataBytes() * header.volumes;
  const uint64_t dataStart =
      skipLines(*data, header.dataFile.empty() ? header.headerBytes : 0, header.lineSkip);
  if (header.encoding == NrrdEncoding::Raw) {
    block.start = header.byteSkip == -1 ? std::nullopt : std::optional(dataStart + uint64_t(header.byteSkip));
  } else {
    block.encoding = SampleEncoding::Deflated;
    block.start = dataStart;
    block.skip = uint64_t(header.byteSkip);
  }

  VolumeInfo info;
  info.dims = header.sizes;
  info.type = header.type;
  info.spacing = options.spacing.value_or(header.spacing);
  const PickedVolume picked =
      pickVolume(options,
                 header.volumesAreTimePoints ? VolumeCounts{header.volumes, 1}
                                             : VolumeCounts{1, header.volumes, "component"},
                 "NRRD file " + path);
  info.description = "nrrd:" + path;
  describePicked(info, picked);
  info.axes = header.axes;
  info.origin = header.origin;
  if (header.originNotRead)
    info.notes.push_back(path + ": its space origin is not three numbers; the volume is placed without it");
  // Directions whose third alone is off the slices' normal (a gantry's tilt kept in the file): the slices are
  // placed where they lie.
  std::optional<SliceGrid> grid;
  const bool placed = header.shearedDirections && !options.spacing &&
                      placeSkewedSlices(info, *header.shearedDirections, "the slices of " + path, grid);
  info.patientFrame = header.anatomicalSpace && (placed || !header.directionsNotApplied);
  if (header.directionsNotApplied && !placed)
    info.notes.push_back(path +
                         ": its space directions are not three vectors at right angles; only their lengths "
                         "are used, as spacings, so the volume is shown unsheared and axis-aligned");
  auto samples = std::make_unique<FileSamples>(std::move(data), std::move(block));
  std::unique_ptr<VolumeSource> source;
  if (header.volumes == 1) {
    source = openBlockSource(std::move(info), std::move(samples), header.bigEndian);
  } else {
    // Every volume's samples are read as one volume: rows of all their values (interleaved), or all their
    // slices (one after another); the picked one is kept.
    VolumeInfo stored;
    stored.dims = header.sizes;
    stored.type = header.type;
    stored.description = info.description;
    uint32_t& longer = header.volumesInterleaved ? stored.dims.x : stored.dims.z;
    const uint32_t across = header.volumesInterleaved ? header.sizes.x : header.sizes.z;
    if (uint64_t(across) * header.volumes > UINT32_MAX)
      throw Error("NRRD file " + path + ": " + std::to_string(header.volumes) + " volumes of " +
                  formatDims(header.sizes) + " samples are too many to read");
    longer = uint32_t(uint64_t(across) * header.volumes);
    auto all = openBlockSource(std::move(stored), std::move(samples), header.bigEndian);
    const uint32_t index = header.volumesAreTimePoints ? picked.timePoint : picked.channel;
    source = header.volumesInterleaved ? pickComponent(std::move(all), header.volumes, index, std::move(info))
                                       : pickStacked(std::move(all), index, std::move(info));
  }
  if (grid) return resampleSlices(std::move(source), std::move(*grid));
  return source;
}

}  // namespace ropecast
