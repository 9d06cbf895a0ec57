#include "store/source_raw.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <regex>

#include <glm/vector_relational.hpp>

#include "core/error.h"
#include "core/input_file.h"

namespace ropecast {
namespace {

class RawSource final : public VolumeSource {
 public:
  RawSource(const std::string& path, VolumeInfo info, uint64_t headerBytes, bool bigEndian)
      : file_(path), info_(std::move(info)), headerBytes_(headerBytes), bigEndian_(bigEndian) {
    // At most 2^60 samples of at most 8 bytes, after a header of at most kMaxRawHeaderBytes: no overflow.
    const uint64_t dataBytes = info_.sampleCount() * bytesPerSample(info_.type);
    const uint64_t expected = headerBytes_ + dataBytes;
    const std::string volume = formatDims(info_.dims) + " " + std::string(sampleTypeName(info_.type));
    if (file_.sizeBytes() != expected)
      throw Error("raw file " + path + ": size is " + std::to_string(file_.sizeBytes()) +
                  " bytes, expected " + std::to_string(expected) + " (" +
                  (headerBytes_ > 0 ? std::to_string(headerBytes_) + " header bytes + " + volume + " = " +
                                          std::to_string(dataBytes) + " bytes"
                                    : volume) +
                  "): file is " + (file_.sizeBytes() < expected ? "truncated" : "too long"));
  }

  const VolumeInfo& info() const override { return info_; }

 private:
  void readSlices(uint32_t z0, uint32_t, std::span<std::byte> out) override {
    file_.readAt(headerBytes_ + uint64_t(z0) * info_.sliceBytes(), out);
    samplesToNative(out, info_.type, bigEndian_);
  }

  PosixFile file_;
  VolumeInfo info_;
  uint64_t headerBytes_;
  bool bigEndian_;
};

}  // namespace

std::optional<RawFileName> parseRawFileName(std::string_view path) {
  // ".RAW" too (files from Windows tools); the type name's case is parseSampleType's business.
  static const std::regex pattern(R"(_([0-9]+)x([0-9]+)x([0-9]+)_([A-Za-z0-9]+)\.[rR][aA][wW]$)");
  const std::string name = std::filesystem::path(path).filename().string();
  std::smatch match;
  if (!std::regex_search(name, match, pattern)) return std::nullopt;
  RawFileName parsed;
  for (int axis = 0; axis < 3; ++axis) {
    const std::string digits = match[axis + 1].str();
    if (digits.size() > 10) return std::nullopt;
    const uint64_t n = std::stoull(digits);
    if (n > UINT32_MAX) return std::nullopt;
    parsed.dims[axis] = uint32_t(n);
  }
  parsed.typeName = match[4].str();
  parsed.type = parseSampleType(parsed.typeName);
  return parsed;
}

std::unique_ptr<VolumeSource> openRawSource(const std::string& path, const SourceOptions& options) {
  const auto fromName = parseRawFileName(path);
  VolumeInfo info;
  if (options.dims) {
    info.dims = *options.dims;
  } else if (fromName) {
    info.dims = fromName->dims;
  } else {
    throw UsageError(
        "raw file " + path +
        ": dimensions unknown; give --dims X,Y,Z and --type T, or name the file name_XxYxZ_type.raw");
  }
  // Before the size check, whose product of dims would overflow.
  if (!isValidDims(info.dims))
    throw Error("raw file " + path + ": dimensions " + formatDims(info.dims) + ": each must be 1 to " +
                std::to_string(kMaxDimsPerAxis));
  if (options.type) {
    info.type = *options.type;
  } else if (fromName && fromName->type) {
    info.type = *fromName->type;
  } else if (fromName) {
    throw Error("raw file " + path + ": unsupported sample type '" + fromName->typeName +
                "' in the file name; expected " + std::string(kSampleTypeList) + " (or give --type)");
  } else {
    throw UsageError("raw file " + path + ": sample type unknown; give --type (" +
                     std::string(kSampleTypeList) + ")");
  }
  const uint64_t headerBytes = options.headerBytes.value_or(0);
  if (headerBytes > kMaxRawHeaderBytes)
    throw UsageError("raw file " + path + ": --header-bytes " + std::to_string(headerBytes) +
                     ": expected at most " + std::to_string(kMaxRawHeaderBytes));
  info.spacing = options.spacing.value_or(glm::dvec3(1.0));
  if (info.type == SampleType::UInt8) {
    info.valueMin = 0.0;
    info.valueMax = 255.0;
  }
  const bool bigEndian = options.byteOrder.value_or(ByteOrder::Little) == ByteOrder::Big;
  // How the file was read, beside its name: what another reading of it would need.
  std::string readAs;
  if (bigEndian && bytesPerSample(info.type) > 1) readAs = "big-endian";
  if (headerBytes > 0)
    readAs += (readAs.empty() ? "" : ", ") + std::to_string(headerBytes) + " header bytes skipped";
  info.description = "raw:" + path + (readAs.empty() ? "" : " (" + readAs + ")");
  return std::make_unique<RawSource>(path, std::move(info), headerBytes, bigEndian);
}

PosixFile::PosixFile(std::string path) : path_(std::move(path)) {
  requireRegularFile(path_, "cannot read " + path_);  // before open(), which waits on a FIFO
  fd_ = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) throw Error("cannot open " + path_ + ": " + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd_, &st) != 0) {
    const int err = errno;
    ::close(fd_);
    throw Error("cannot stat " + path_ + ": " + std::strerror(err));
  }
  if (S_ISDIR(st.st_mode)) {
    ::close(fd_);
    throw Error("cannot read " + path_ + ": is a directory");
  }
  identity_ = {.device = uint64_t(st.st_dev),
               .inode = uint64_t(st.st_ino),
               .sizeBytes = uint64_t(st.st_size),
               .modifiedNs = int64_t(st.st_mtim.tv_sec) * 1'000'000'000 + st.st_mtim.tv_nsec};
}

PosixFile::~PosixFile() {
  if (fd_ >= 0) ::close(fd_);
}

size_t PosixFile::readSomeAt(uint64_t offsetBytes, std::span<std::byte> out) const {
  size_t done = 0;
  while (done < out.size()) {
    const ssize_t n = ::pread(fd_, out.data() + done, out.size() - done, off_t(offsetBytes + done));
    if (n < 0) {
      if (errno == EINTR) continue;
      throw Error("cannot read " + path_ + " at byte " + std::to_string(offsetBytes + done) + ": " +
                  std::strerror(errno));
    }
    if (n == 0) break;
    done += size_t(n);
  }
  return done;
}

std::string PosixFile::readStart(size_t maxBytes) const {
  std::string text(size_t(std::min<uint64_t>(identity_.sizeBytes, maxBytes)), '\0');
  text.resize(readSomeAt(0, std::as_writable_bytes(std::span(text))));
  return text;
}

void PosixFile::readAt(uint64_t offsetBytes, std::span<std::byte> out) const {
  const size_t got = readSomeAt(offsetBytes, out);
  if (got != out.size())
    throw Error("cannot read " + path_ + ": file ends at byte " + std::to_string(offsetBytes + got) +
                ", expected data up to byte " + std::to_string(offsetBytes + out.size()));
}

void samplesToNative(std::span<std::byte> samples, SampleType type, bool storedBigEndian) {
  const size_t width = bytesPerSample(type);
  if (width == 1 || storedBigEndian == (std::endian::native == std::endian::big)) return;
  for (size_t i = 0; i + width <= samples.size(); i += width)
    std::reverse(samples.begin() + i, samples.begin() + i + width);
}

}  // namespace ropecast
