// The raw VolumeSource (a file of samples, x fastest, little-endian unless told otherwise, after a header of
// any length that is skipped), plus the small file helpers the file-based sources share (PosixFile,
// byte-order conversion). Owned by loader/.
//
// Threads: as VolumeSource. PosixFile::readAt uses pread, so one PosixFile may be read from several threads.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include <glm/vec3.hpp>

#include "store/volume_source.h"

namespace ropecast {

// What an Open SciVis-style name says: `name_XxYxZ_type.raw`, e.g. bonsai_256x256x256_uint8.raw.
struct RawFileName {
  glm::u32vec3 dims{0};
  std::string typeName;            // as written, e.g. "uint8"
  std::optional<SampleType> type;  // parseSampleType(typeName); nullopt for types we cannot read
};

// Parses the file name part of `path`; nullopt if it does not have the `_XxYxZ_type.raw` form.
std::optional<RawFileName> parseRawFileName(std::string_view path);

// The longest header a raw file may have (options.headerBytes): 2^53 bytes, so that the expected file size,
// header and samples, is exact in a uint64 and in a double.
inline constexpr uint64_t kMaxRawHeaderBytes = uint64_t(1) << 53;

// Opens a raw file. Dims and type from options, else from the file name; spacing, byte order (default
// little) and header bytes (default 0) from options. Throws ropecast::Error naming the file if dims/type are
// unknown or the file size is not the header plus dims * bytes per sample (saying expected and actual size).
std::unique_ptr<VolumeSource> openRawSource(const std::string& path, const SourceOptions& options);

// Which file, as it was when opened: two opens of a file unchanged between them compare equal.
struct FileIdentity {
  uint64_t device = 0;
  uint64_t inode = 0;
  uint64_t sizeBytes = 0;
  int64_t modifiedNs = 0;
  bool operator==(const FileIdentity&) const = default;
};

// A read-only file descriptor, closed on destruction. Errors name the path.
class PosixFile {
 public:
  explicit PosixFile(std::string path);  // throws ropecast::Error if it cannot be opened
  ~PosixFile();
  PosixFile(const PosixFile&) = delete;
  PosixFile& operator=(const PosixFile&) = delete;

  const std::string& path() const { return path_; }
  uint64_t sizeBytes() const { return identity_.sizeBytes; }
  const FileIdentity& identity() const { return identity_; }
  // Reads exactly out.size() bytes at `offsetBytes` (pread; no shared file offset). Throws if the file ends
  // first.
  void readAt(uint64_t offsetBytes, std::span<std::byte> out) const;
  // The file's first bytes, at most `maxBytes` (a header read as text).
  std::string readStart(size_t maxBytes) const;
  // Reads up to out.size() bytes; returns how many (fewer only at the end of the file).
  size_t readSomeAt(uint64_t offsetBytes, std::span<std::byte> out) const;

 private:
  std::string path_;
  int fd_ = -1;
  FileIdentity identity_;
};

// Converts samples of `type` stored in the given byte order to native order, in place.
void samplesToNative(std::span<std::byte> samples, SampleType type, bool storedBigEndian);

}  // namespace ropecast
