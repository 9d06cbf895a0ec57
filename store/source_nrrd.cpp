#include "store/source_nrrd.h"

#include <algorithm>
#include <filesystem>
#include <optional>
#include <vector>

#include "core/error.h"
#include "store/file_samples.h"
#include "store/nrrd_header.h"
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

class NrrdSource final : public VolumeSource {
 public:
  NrrdSource(const std::string& path, const SourceOptions& options) {
    header_ = readNrrdHeaderFile(path);
    const std::string dataPath = nrrdDataPath(header_, path);
    std::unique_ptr<PosixFile> data;
    try {
      data = std::make_unique<PosixFile>(dataPath);
    } catch (const Error& e) {
      if (dataPath == path) throw;
      throw Error("NRRD header " + path + " names data file " + header_.dataFile + ": " + e.what());
    }
    SampleBlock block;
    block.fileKind = "NRRD data file";
    block.volume = formatDims(header_.sizes) + " " + std::string(sampleTypeName(header_.type));
    block.bytes = header_.dataBytes();
    const uint64_t dataStart =
        skipLines(*data, header_.dataFile.empty() ? header_.headerBytes : 0, header_.lineSkip);
    if (header_.encoding == NrrdEncoding::Raw) {
      block.start =
          header_.byteSkip == -1 ? std::nullopt : std::optional(dataStart + uint64_t(header_.byteSkip));
    } else {
      block.encoding = SampleEncoding::Deflated;
      block.start = dataStart;
      block.skip = uint64_t(header_.byteSkip);
    }
    samples_ = std::make_unique<FileSamples>(std::move(data), std::move(block));

    info_.dims = header_.sizes;
    info_.type = header_.type;
    info_.spacing = options.spacing.value_or(header_.spacing);
    if (info_.type == SampleType::UInt8) {
      info_.valueMin = 0.0;
      info_.valueMax = 255.0;
    }
    info_.description = "nrrd:" + path;
    if (header_.directionsTurnAxes)
      info_.notes.push_back(path +
                            ": its space directions flip or rotate the axes; only their lengths are used, as "
                            "spacings, so the volume is shown unflipped and axis-aligned");
  }

  const VolumeInfo& info() const override { return info_; }

 private:
  void readSlices(uint32_t z0, uint32_t, std::span<std::byte> out) override {
    samples_->read(uint64_t(z0) * info_.sliceBytes(), out);
    samplesToNative(out, info_.type, header_.bigEndian);
  }

  NrrdHeader header_;
  std::unique_ptr<FileSamples> samples_;
  VolumeInfo info_;
};

}  // namespace

NrrdHeader readNrrdHeaderFile(const std::string& path) {
  std::string text;
  const PosixFile file(path);
  text.resize(size_t(std::min<uint64_t>(file.sizeBytes(), kMaxNrrdHeaderBytes)));
  text.resize(file.readSomeAt(0, std::as_writable_bytes(std::span(text))));
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
  if (header.dataFile.empty()) return headerPath;
  std::filesystem::path detached(header.dataFile);
  if (detached.is_relative()) detached = std::filesystem::path(headerPath).parent_path() / detached;
  return detached.string();
}

std::unique_ptr<VolumeSource> openNrrdSource(const std::string& path, const SourceOptions& options) {
  return std::make_unique<NrrdSource>(path, options);
}

}  // namespace ropecast
