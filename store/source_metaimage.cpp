#include "store/source_metaimage.h"

#include <algorithm>
#include <optional>
#include <vector>

#include "core/error.h"
#include "core/header_text.h"
#include "store/file_samples.h"
#include "store/picked_volume.h"
#include "store/placed_stack.h"
#include "store/source_raw.h"

namespace ropecast {
namespace {

// A MetaImage whose slices are each a file of their own (ElementDataFile LIST, or a pattern): raw samples,
// after HeaderSize bytes (or ending the file, for -1), or with CompressedData a zlib stream of the slice each
// (as MetaIO writes them). Every file is opened when the source opens, and a raw one's size checked, so that
// a missing or short one is named before any conversion work; a compressed one is inflated when its slice is
// read (its stream then, not a file handle and buffers for each of thousands of slices).
class ListedSlicesSource final : public VolumeSource {
 public:
  ListedSlicesSource(VolumeInfo info, const MetaImageHeader& header, const std::string& headerPath)
      : info_(std::move(info)), bigEndian_(header.bigEndian), compressed_(header.compressed) {
    const uint64_t sliceBytes = info_.sliceBytes();
    for (const std::string& name : header.sliceFiles) {
      auto file = openDataFile(pathBesideHeader(headerPath, name), "MetaImage header", headerPath, name);
      const uint64_t skip = header.headerSize == -1 ? 0 : uint64_t(header.headerSize);
      if (compressed_) {
        paths_.push_back(file->path());
        starts_.push_back(skip);
        continue;
      }
      const bool fits =
          header.headerSize == -1 ? file->sizeBytes() >= sliceBytes : file->sizeBytes() == skip + sliceBytes;
      if (!fits)
        throw Error("MetaImage data file " + file->path() + " holds " + std::to_string(file->sizeBytes()) +
                    " bytes; a slice of " + formatDims({info_.dims.x, info_.dims.y, 1}) + " " +
                    std::string(sampleTypeName(info_.type)) + " samples is " + std::to_string(sliceBytes) +
                    (skip ? " after " + std::to_string(skip) + " header bytes" : std::string()) +
                    (header.headerSize == -1 ? " at its end" : ""));
      starts_.push_back(header.headerSize == -1 ? file->sizeBytes() - sliceBytes : skip);
      files_.push_back(std::move(file));
    }
  }

  const VolumeInfo& info() const override { return info_; }

 protected:
  void readSlices(uint32_t z0, uint32_t count, std::span<std::byte> out) override {
    const size_t sliceBytes = info_.sliceBytes();
    for (uint32_t i = 0; i < count; ++i) {
      const std::span<std::byte> slice = out.subspan(i * sliceBytes, sliceBytes);
      if (!compressed_) {
        files_[z0 + i]->readAt(starts_[z0 + i], slice);
        continue;
      }
      SampleBlock block;
      block.encoding = SampleEncoding::Deflated;
      block.start = starts_[z0 + i];
      block.bytes = sliceBytes;
      block.fileKind = "MetaImage data file";
      block.volume =
          formatDims({info_.dims.x, info_.dims.y, 1}) + " " + std::string(sampleTypeName(info_.type));
      FileSamples(std::make_unique<PosixFile>(paths_[z0 + i]), std::move(block)).read(0, slice);
    }
    samplesToNative(out, info_.type, bigEndian_);
  }

 private:
  VolumeInfo info_;
  bool bigEndian_;
  bool compressed_;
  std::vector<std::unique_ptr<PosixFile>> files_;  // a slice's each (raw slices)
  std::vector<std::string> paths_;                 // a slice's each (compressed slices)
  std::vector<uint64_t> starts_;                   // where each file's slice (or its stream) starts
};

}  // namespace

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

std::vector<std::string> metaImageDataPaths(const MetaImageHeader& header, const std::string& headerPath) {
  if (header.sliceFiles.empty()) return {metaImageDataPath(header, headerPath)};
  std::vector<std::string> paths;
  for (const std::string& name : header.sliceFiles) paths.push_back(pathBesideHeader(headerPath, name));
  return paths;
}

std::unique_ptr<VolumeSource> openMetaImageSource(const std::string& path, const SourceOptions& options) {
  const MetaImageHeader header = readMetaImageHeaderFile(path);
  const bool listed = !header.sliceFiles.empty();
  auto data = listed
                  ? nullptr
                  : openDataFile(metaImageDataPath(header, path), "MetaImage header", path, header.dataFile);
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
  // The samples of every channel, as the file or files store them.
  const auto stored = [&](VolumeInfo all) -> std::unique_ptr<VolumeSource> {
    if (listed) return std::make_unique<ListedSlicesSource>(std::move(all), header, path);
    return openBlockSource(std::move(all), std::make_unique<FileSamples>(std::move(data), std::move(block)),
                           header.bigEndian);
  };
  std::unique_ptr<VolumeSource> source;
  if (header.channels == 1) {
    source = stored(std::move(info));
  } else {
    // Channels are interleaved: read as rows of channels times as many samples, one channel kept.
    if (uint64_t(header.sizes.x) * header.channels > UINT32_MAX)
      throw Error("MetaImage " + path + ": rows of " + std::to_string(header.sizes.x) + " samples of " +
                  std::to_string(header.channels) + " channels each are too long to read");
    VolumeInfo all;
    all.dims = {header.sizes.x * header.channels, header.sizes.y, header.sizes.z};
    all.type = header.type;
    all.description = info.description;
    source = pickComponent(stored(std::move(all)), header.channels, picked.channel, std::move(info));
  }
  if (grid) return resampleSlices(std::move(source), std::move(*grid));
  return source;
}

}  // namespace ropecast
