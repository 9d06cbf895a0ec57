#include "store/file_samples.h"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <limits>
#include <vector>

#include "core/error.h"
#include "store/deflate_index.h"

namespace ropecast {
namespace {

constexpr size_t kInflateChunkBytes = size_t(1) << 18;  // compressed input read at a time, and skip buffer

}  // namespace

// A gzip (or zlib) stream over a file from an offset on, read forward; a read behind the position, or one far
// ahead, resumes from the nearest of the file's access points (store/deflate_index.h) at or before it, else
// from the stream's start. Points are taken as the stream passes them.
class DeflateStream {
 public:
  DeflateStream(const PosixFile& file, uint64_t startOffset, std::string fileKind)
      : file_(file),
        fileKind_(std::move(fileKind)),
        start_(startOffset),
        input_(kInflateChunkBytes),
        index_(deflateIndexFor(file, startOffset)) {
    if (inflateInit2(&zs_, kAnyHeader) != Z_OK)
      throw Error(fileKind_ + " " + file_.path() + ": inflateInit failed");
    std::array<uint8_t, 2> magic{};
    file_.readSomeAt(start_, std::as_writable_bytes(std::span(magic)));
    gzip_ = magic[0] == 0x1f && magic[1] == 0x8b;
    inputStart();
  }
  ~DeflateStream() { inflateEnd(&zs_); }
  DeflateStream(const DeflateStream&) = delete;
  DeflateStream& operator=(const DeflateStream&) = delete;

  uint64_t inflatedBytes() const { return inflated_; }

  // Makes the next read start at decompressed byte `target`.
  void seek(uint64_t target) {
    const bool behind = target < produced_;
    // Reading on reaches the target unless a point lies between: only then is one worth its window's copy.
    const std::optional<DeflateAccessPoint> point =
        index_->pointBefore(target, behind ? std::nullopt : std::optional(produced_));
    if (point)
      resumeAt(*point);
    else if (behind)
      restart();
    skip(target - produced_);
  }

  // Fills `out` completely or throws (truncated or corrupt data).
  void read(std::span<std::byte> out) {
    size_t done = 0;
    while (done < out.size()) {
      if (memberEnded_) nextMember();
      done += inflateSome(out.subspan(done));
    }
  }

  // Reads the rest of the current member, its trailer included (its CRC and length checked there): throws
  // when the file ends first or the check fails. Data past the volume is read and dropped, unless the member
  // was checked before. Leaves the stream spent: the next read seeks anew.
  void finishMember() {
    if (!memberEnded_ && !index_->memberCheckedAt(produced_)) {
      std::vector<std::byte> scratch(kInflateChunkBytes);
      finishing_ = true;
      while (!memberEnded_) inflateSome(scratch);
      finishing_ = false;
    }
    abandon();
  }

  // Spent: the next read seeks anew, from a point or the stream's start.
  void abandon() {
    produced_ = std::numeric_limits<uint64_t>::max();
    finishing_ = false;
  }

 private:
  static constexpr int kAnyHeader = 15 + 32;  // inflateInit2: a zlib or gzip header, detected
  static constexpr int kNoHeader = -15;       // raw deflate data, resumed inside a member

  void skip(uint64_t bytes) {
    std::vector<std::byte> scratch(std::min<uint64_t>(bytes, kInflateChunkBytes));
    while (bytes > 0) {
      const size_t n = size_t(std::min<uint64_t>(bytes, scratch.size()));
      read(std::span(scratch).first(n));
      bytes -= n;
    }
  }

  void inputStart() {
    next_ = start_;
    zs_.avail_in = 0;
    zs_.next_in = nullptr;
  }

  void restart() {
    if (inflateReset2(&zs_, kAnyHeader) != Z_OK) fail("inflateReset failed");
    inputStart();
    produced_ = 0;
    memberStart_ = 0;
    memberEnded_ = false;
    resumed_ = false;
  }

  // Inflation resumed at a block's end: raw deflate data primed with the point's bits and window, the
  // member's check carried on here and compared with its trailer at the member's end.
  void resumeAt(const DeflateAccessPoint& point) {
    if (inflateReset2(&zs_, kNoHeader) != Z_OK) fail("inflateReset failed");
    inputStart();
    next_ = point.input - (point.bits > 0 ? 1 : 0);
    if (point.bits > 0) {
      if (!refill()) truncated();
      const int partial = *zs_.next_in;
      ++zs_.next_in;
      --zs_.avail_in;
      if (inflatePrime(&zs_, point.bits, partial >> (8 - point.bits)) != Z_OK) fail("inflatePrime failed");
    }
    if (inflateSetDictionary(&zs_, reinterpret_cast<const Bytef*>(point.window.data()),
                             uInt(point.window.size())) != Z_OK)
      fail("inflateSetDictionary failed");
    gzip_ = point.gzip;
    check_ = point.check;
    produced_ = point.output;
    memberStart_ = point.output - point.memberOutput;
    memberEnded_ = false;
    resumed_ = true;
  }

  // Concatenated gzip members continue the data; anything else after a member means the data ended early.
  void nextMember() {
    if (zs_.avail_in == 0 && !refill()) truncated();
    if (inflateReset2(&zs_, kAnyHeader) != Z_OK) fail("inflateReset failed");
    memberStart_ = produced_;
    memberEnded_ = false;
    resumed_ = false;
  }

  // One inflate() into `out`, which stops at the end of a deflate block (where a point may be taken) or of
  // the member (whose trailer is then checked); returns the bytes written.
  size_t inflateSome(std::span<std::byte> out) {
    if (zs_.avail_in == 0) refill();
    auto* first = reinterpret_cast<Bytef*>(out.data());
    const uInt room = uInt(std::min<size_t>(out.size(), size_t(1) << 30));
    zs_.next_out = first;
    zs_.avail_out = room;
    const int status = inflate(&zs_, Z_BLOCK);
    const uInt got = room - zs_.avail_out;
    if (resumed_)
      check_ = gzip_ ? uint32_t(crc32(check_, first, got)) : uint32_t(adler32(check_, first, got));
    produced_ += got;
    inflated_ += got;
    if (status == Z_STREAM_END) {
      if (resumed_) checkTrailer();
      index_->memberChecked(memberStart_, produced_);
      memberEnded_ = true;
    } else if (status == Z_BUF_ERROR) {
      if (zs_.avail_in != 0) corrupt("no progress");
      truncated();  // input was asked for before inflating, and none came
    } else if (status != Z_OK) {
      corrupt(zs_.msg ? zs_.msg : "inflate error " + std::to_string(status));
    } else if ((zs_.data_type & kBlockEnded) != 0 && (zs_.data_type & kInLastBlock) == 0 &&
               index_->wantsPointAt(produced_)) {
      takePoint();
    }
    return got;
  }

  // zlib's data_type after inflate(Z_BLOCK): the unused bits of the last byte taken, and these flags.
  static constexpr int kInLastBlock = 64;
  static constexpr int kBlockEnded = 128;

  void takePoint() {
    DeflateAccessPoint point;
    point.output = produced_;
    point.input = next_ - zs_.avail_in;
    point.bits = zs_.data_type & 7;
    point.check = resumed_ ? check_ : uint32_t(zs_.adler);
    point.memberOutput = produced_ - memberStart_;
    point.gzip = gzip_;
    point.window.resize(kWindowBytes);
    uInt windowBytes = 0;
    if (inflateGetDictionary(&zs_, reinterpret_cast<Bytef*>(point.window.data()), &windowBytes) != Z_OK)
      return;
    point.window.resize(windowBytes);
    index_->add(std::move(point));
  }

  // A resumed member's trailer, which zlib does not read in raw mode: CRC-32 and length (gzip, little-endian)
  // or Adler-32 (zlib, big-endian).
  void checkTrailer() {
    std::array<uint8_t, 8> trailer{};
    const size_t size = gzip_ ? 8 : 4;
    for (size_t i = 0; i < size; ++i) {
      if (zs_.avail_in == 0 && !refill()) {
        finishing_ = true;
        truncated();
      }
      trailer[i] = *zs_.next_in++;
      --zs_.avail_in;
    }
    const auto word = [&](size_t at, bool bigEndian) {
      uint32_t value = 0;
      for (size_t i = 0; i < 4; ++i) value |= uint32_t(trailer[at + i]) << (8 * (bigEndian ? 3 - i : i));
      return value;
    };
    if (word(0, !gzip_) != check_) corrupt("incorrect data check");
    if (gzip_ && word(4, false) != uint32_t(produced_ - memberStart_)) corrupt("incorrect length check");
  }

  // Reads more compressed input; false at the end of the file.
  bool refill() {
    const size_t got = file_.readSomeAt(next_, input_);
    if (got == 0) return false;
    next_ += got;
    zs_.next_in = reinterpret_cast<Bytef*>(input_.data());
    zs_.avail_in = uInt(got);
    return true;
  }

  [[noreturn]] void truncated() const {
    if (finishing_)
      throw Error(fileKind_ + " " + file_.path() +
                  ": compressed data ends before its trailer (truncated file)");
    throw Error(fileKind_ + " " + file_.path() + ": compressed data ends after " + std::to_string(produced_) +
                " decompressed bytes, before the volume is complete (truncated file)");
  }
  [[noreturn]] void corrupt(const std::string& why) const {
    throw Error(fileKind_ + " " + file_.path() + ": corrupt compressed data after " +
                std::to_string(produced_) + " decompressed bytes (" + why + ")");
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw Error(fileKind_ + " " + file_.path() + ": " + what);
  }

  static constexpr size_t kWindowBytes = size_t(1) << 15;

  const PosixFile& file_;
  std::string fileKind_;
  uint64_t start_;
  uint64_t next_ = 0;         // file offset of the next compressed input
  uint64_t produced_ = 0;     // decompressed bytes before the next one read, from the stream's start
  uint64_t memberStart_ = 0;  // decompressed bytes before the current member
  uint64_t inflated_ = 0;     // decompressed bytes produced in all, skipped ones included
  bool memberEnded_ = false;  // the last inflate() ended a member (its trailer checked)
  bool gzip_ = true;          // the members' wrapper: gzip, else zlib
  bool resumed_ = false;      // raw inflation from an access point: check_ is kept here, not by zlib
  bool finishing_ = false;    // reading for the trailer only (how a cut file is named)
  uint32_t check_ = 0;        // resumed_: the member's running CRC-32 or Adler-32
  z_stream zs_{};
  std::vector<std::byte> input_;
  std::shared_ptr<DeflateIndex> index_;
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

uint64_t FileSamples::inflatedBytes() const {
  return inflate_ ? inflate_->inflatedBytes() : 0;
}

void FileSamples::read(uint64_t offset, std::span<std::byte> out) {
  if (!inflate_) {
    file_->readAt(rawOffset_ + offset, out);
    return;
  }
  try {
    inflate_->seek(block_.skip + offset);
    inflate_->read(out);
    // The samples' end: the stream's trailer (CRC and length) must follow, else the file was cut.
    if (offset + out.size() == block_.bytes) inflate_->finishMember();
  } catch (...) {
    inflate_->abandon();  // zlib's state after an error is no place to go on from
    throw;
  }
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
