#include "store/source_nrrd.h"

#include <zlib.h>

#include <algorithm>
#include <filesystem>
#include <limits>
#include <vector>

#include "core/error.h"
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

// A forward-only gzip (or zlib) stream over a byte range of a file, restartable from its start.
class GzipStream {
 public:
  GzipStream(const PosixFile& file, uint64_t startOffset)
      : file_(file), start_(startOffset), input_(kChunkBytes) {
    if (inflateInit2(&zs_, 15 + 32) != Z_OK)
      throw Error("NRRD data file " + file_.path() + ": inflateInit failed");
    inputStart();
  }
  ~GzipStream() { inflateEnd(&zs_); }
  GzipStream(const GzipStream&) = delete;
  GzipStream& operator=(const GzipStream&) = delete;

  uint64_t position() const { return produced_; }

  void restart() {
    if (inflateReset(&zs_) != Z_OK) throw Error("NRRD data file " + file_.path() + ": inflateReset failed");
    inputStart();
  }

  void skip(uint64_t bytes) {
    std::vector<std::byte> scratch(std::min<uint64_t>(bytes, kChunkBytes));
    while (bytes > 0) {
      const size_t n = size_t(std::min<uint64_t>(bytes, scratch.size()));
      read(std::span(scratch).first(n));
      bytes -= n;
    }
  }

  // Fills `out` completely or throws (truncated or corrupt data).
  void read(std::span<std::byte> out) {
    zs_.next_out = reinterpret_cast<Bytef*>(out.data());
    size_t left = out.size();
    while (left > 0) {
      if (zs_.avail_in == 0) refill();
      const uInt chunk = uInt(std::min<size_t>(left, size_t(1) << 30));
      zs_.avail_out = chunk;
      const int status = inflate(&zs_, Z_NO_FLUSH);
      const size_t got = chunk - zs_.avail_out;
      left -= got;
      produced_ += got;
      memberEnded_ = status == Z_STREAM_END;
      if (status == Z_STREAM_END) {
        if (left == 0) break;
        // Concatenated gzip members continue the data; anything else means it ended early.
        if (zs_.avail_in == 0 && !refill(false)) truncated();
        if (inflateReset(&zs_) != Z_OK)
          throw Error("NRRD data file " + file_.path() + ": inflateReset failed");
      } else if (status == Z_BUF_ERROR) {
        if (zs_.avail_in != 0) corrupt("no progress");
      } else if (status != Z_OK) {
        corrupt(zs_.msg ? zs_.msg : "inflate error " + std::to_string(status));
      }
    }
  }

  // Reads the rest of the current gzip member, its trailer included (zlib checks the CRC and length there):
  // throws when the file ends first or the check fails. Data past the volume is read and dropped.
  void finishMember() {
    std::vector<std::byte> scratch(kChunkBytes);
    while (!memberEnded_) {
      if (zs_.avail_in == 0 && !refill(false))
        throw Error("NRRD data file " + file_.path() +
                    ": gzip data ends before its trailer (truncated file)");
      zs_.next_out = reinterpret_cast<Bytef*>(scratch.data());
      zs_.avail_out = uInt(scratch.size());
      const int status = inflate(&zs_, Z_NO_FLUSH);
      memberEnded_ = status == Z_STREAM_END;
      if (status != Z_OK && status != Z_STREAM_END && !(status == Z_BUF_ERROR && zs_.avail_in == 0))
        corrupt(zs_.msg ? zs_.msg : "inflate error " + std::to_string(status));
    }
    produced_ = std::numeric_limits<uint64_t>::max();  // spent: the next read restarts the stream
  }

 private:
  void inputStart() {
    next_ = start_;
    produced_ = 0;
    memberEnded_ = false;
    zs_.avail_in = 0;
    zs_.next_in = nullptr;
  }

  // Reads more compressed input; at the end of the file throws (or returns false when allowed to end).
  bool refill(bool mustHaveMore = true) {
    const size_t got = file_.readSomeAt(next_, input_);
    if (got == 0) {
      if (mustHaveMore) truncated();
      return false;
    }
    next_ += got;
    zs_.next_in = reinterpret_cast<Bytef*>(input_.data());
    zs_.avail_in = uInt(got);
    return true;
  }

  [[noreturn]] void truncated() const {
    throw Error("NRRD data file " + file_.path() + ": gzip data ends after " + std::to_string(produced_) +
                " decompressed bytes, before the volume is complete (truncated file)");
  }
  [[noreturn]] void corrupt(const std::string& why) const {
    throw Error("NRRD data file " + file_.path() + ": corrupt gzip data after " + std::to_string(produced_) +
                " decompressed bytes (" + why + ")");
  }

  const PosixFile& file_;
  uint64_t start_;
  uint64_t next_ = 0;         // file offset of the next compressed input
  uint64_t produced_ = 0;     // decompressed bytes delivered since the start
  bool memberEnded_ = false;  // the last inflate() ended a gzip member (its trailer checked)
  z_stream zs_{};
  std::vector<std::byte> input_;
};

class NrrdSource final : public VolumeSource {
 public:
  NrrdSource(const std::string& path, const SourceOptions& options) {
    header_ = readNrrdHeaderFile(path);
    const std::string dataPath = nrrdDataPath(header_, path);
    uint64_t dataStart = header_.dataFile.empty() ? header_.headerBytes : 0;
    try {
      data_ = std::make_unique<PosixFile>(dataPath);
    } catch (const Error& e) {
      if (dataPath == path) throw;
      throw Error("NRRD header " + path + " names data file " + header_.dataFile + ": " + e.what());
    }
    dataStart = skipLines(*data_, dataStart, header_.lineSkip);

    const uint64_t dataBytes = header_.dataBytes();
    if (header_.encoding == NrrdEncoding::Raw) {
      if (header_.byteSkip == -1) {
        if (data_->sizeBytes() < dataBytes) truncatedRaw(dataBytes, data_->sizeBytes());
        rawOffset_ = data_->sizeBytes() - dataBytes;
      } else {
        rawOffset_ = dataStart + uint64_t(header_.byteSkip);
        if (data_->sizeBytes() < rawOffset_ || data_->sizeBytes() - rawOffset_ < dataBytes)
          truncatedRaw(rawOffset_ + dataBytes, data_->sizeBytes());
      }
    } else {
      gzip_ = std::make_unique<GzipStream>(*data_, dataStart);
    }

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
    const uint64_t offset = uint64_t(z0) * info_.sliceBytes();
    if (gzip_) {
      const uint64_t target = uint64_t(header_.byteSkip) + offset;
      if (target < gzip_->position()) gzip_->restart();
      gzip_->skip(target - gzip_->position());
      gzip_->read(out);
      // The last slice: the member's trailer (CRC and length) must follow, else the file was cut.
      if (z0 + out.size() / info_.sliceBytes() == info_.dims.z) gzip_->finishMember();
    } else {
      data_->readAt(rawOffset_ + offset, out);
    }
    samplesToNative(out, info_.type, header_.bigEndian);
  }

  [[noreturn]] void truncatedRaw(uint64_t expectedBytes, uint64_t actualBytes) const {
    throw Error("NRRD data file " + data_->path() + ": size is " + std::to_string(actualBytes) +
                " bytes, expected at least " + std::to_string(expectedBytes) + " (" +
                std::to_string(header_.sizes.x) + "x" + std::to_string(header_.sizes.y) + "x" +
                std::to_string(header_.sizes.z) + " " + std::string(sampleTypeName(header_.type)) +
                "): file is truncated");
  }

  NrrdHeader header_;
  std::unique_ptr<PosixFile> data_;
  std::unique_ptr<GzipStream> gzip_;  // gzip encoding only; reads data_
  uint64_t rawOffset_ = 0;            // raw encoding: file offset of the first sample
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
