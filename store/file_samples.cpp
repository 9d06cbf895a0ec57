#include "store/file_samples.h"

#include <zlib.h>

#include <algorithm>
#include <filesystem>
#include <limits>
#include <vector>

#include "core/error.h"

namespace ropecast {
namespace {

constexpr size_t kInflateChunkBytes = size_t(1) << 18;  // compressed input read at a time, and skip buffer

}  // namespace

// A forward-only gzip (or zlib) stream over a file from an offset on, restartable from there.
class DeflateStream {
 public:
  DeflateStream(const PosixFile& file, uint64_t startOffset, std::string fileKind)
      : file_(file), fileKind_(std::move(fileKind)), start_(startOffset), input_(kInflateChunkBytes) {
    if (inflateInit2(&zs_, 15 + 32) != Z_OK)
      throw Error(fileKind_ + " " + file_.path() + ": inflateInit failed");
    inputStart();
  }
  ~DeflateStream() { inflateEnd(&zs_); }
  DeflateStream(const DeflateStream&) = delete;
  DeflateStream& operator=(const DeflateStream&) = delete;

  uint64_t position() const { return produced_; }

  void restart() {
    if (inflateReset(&zs_) != Z_OK) throw Error(fileKind_ + " " + file_.path() + ": inflateReset failed");
    inputStart();
  }

  void skip(uint64_t bytes) {
    std::vector<std::byte> scratch(std::min<uint64_t>(bytes, kInflateChunkBytes));
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
        if (inflateReset(&zs_) != Z_OK) throw Error(fileKind_ + " " + file_.path() + ": inflateReset failed");
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
    std::vector<std::byte> scratch(kInflateChunkBytes);
    while (!memberEnded_) {
      if (zs_.avail_in == 0 && !refill(false))
        throw Error(fileKind_ + " " + file_.path() +
                    ": compressed data ends before its trailer (truncated file)");
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
    throw Error(fileKind_ + " " + file_.path() + ": compressed data ends after " + std::to_string(produced_) +
                " decompressed bytes, before the volume is complete (truncated file)");
  }
  [[noreturn]] void corrupt(const std::string& why) const {
    throw Error(fileKind_ + " " + file_.path() + ": corrupt compressed data after " +
                std::to_string(produced_) + " decompressed bytes (" + why + ")");
  }

  const PosixFile& file_;
  std::string fileKind_;
  uint64_t start_;
  uint64_t next_ = 0;         // file offset of the next compressed input
  uint64_t produced_ = 0;     // decompressed bytes delivered since the start
  bool memberEnded_ = false;  // the last inflate() ended a gzip member (its trailer checked)
  z_stream zs_{};
  std::vector<std::byte> input_;
};

FileSamples::FileSamples(std::unique_ptr<PosixFile> file, SampleBlock block)
    : file_(std::move(file)), block_(std::move(block)) {
  if (block_.encoding == SampleEncoding::Deflated) {
    if (!block_.start) throw Error(block_.fileKind + " " + file_->path() + ": deflated samples need a start");
    inflate_ = std::make_unique<DeflateStream>(*file_, *block_.start, block_.fileKind);
    return;
  }
  const uint64_t size = file_->sizeBytes();
  rawOffset_ = block_.start.value_or(size - std::min(size, block_.bytes));
  if (size < rawOffset_ || size - rawOffset_ < block_.bytes)
    throw Error(block_.fileKind + " " + file_->path() + ": size is " + std::to_string(size) +
                " bytes, expected at least " + std::to_string(rawOffset_ + block_.bytes) + " (" +
                block_.volume + "): file is truncated");
}

FileSamples::~FileSamples() = default;

void FileSamples::read(uint64_t offset, std::span<std::byte> out) {
  if (!inflate_) {
    file_->readAt(rawOffset_ + offset, out);
    return;
  }
  const uint64_t target = block_.skip + offset;
  if (target < inflate_->position()) inflate_->restart();
  inflate_->skip(target - inflate_->position());
  inflate_->read(out);
  // The samples' end: the stream's trailer (CRC and length) must follow, else the file was cut.
  if (offset + out.size() == block_.bytes) inflate_->finishMember();
}

namespace {

class BlockSource final : public VolumeSource {
 public:
  BlockSource(VolumeInfo info, std::unique_ptr<FileSamples> samples, bool storedBigEndian)
      : info_(std::move(info)), samples_(std::move(samples)), bigEndian_(storedBigEndian) {
    if (info_.type == SampleType::UInt8) {
      info_.valueMin = 0.0;
      info_.valueMax = 255.0;
    }
  }

  const VolumeInfo& info() const override { return info_; }

 private:
  void readSlices(uint32_t z0, uint32_t, std::span<std::byte> out) override {
    samples_->read(uint64_t(z0) * info_.sliceBytes(), out);
    samplesToNative(out, info_.type, bigEndian_);
  }

  VolumeInfo info_;
  std::unique_ptr<FileSamples> samples_;
  bool bigEndian_;
};

}  // namespace

std::string pathBesideHeader(const std::string& headerPath, const std::string& fileName) {
  std::filesystem::path path(fileName);
  if (path.is_relative()) path = std::filesystem::path(headerPath).parent_path() / path;
  return path.string();
}

std::unique_ptr<PosixFile> openDataFile(const std::string& dataPath, const std::string& headerKind,
                                        const std::string& headerPath, const std::string& fileName) {
  try {
    return std::make_unique<PosixFile>(dataPath);
  } catch (const Error& e) {
    if (dataPath == headerPath) throw;
    throw Error(headerKind + " " + headerPath + " names data file " + fileName + ": " + e.what());
  }
}

std::unique_ptr<VolumeSource> openBlockSource(VolumeInfo info, std::unique_ptr<FileSamples> samples,
                                              bool storedBigEndian) {
  return std::make_unique<BlockSource>(std::move(info), std::move(samples), storedBigEndian);
}

}  // namespace ropecast
