// Access points into a deflated stream (gzip or zlib) over a file, so that a read far into its decompressed
// bytes starts from the nearest point before it rather than from the stream's start, and a member whose
// trailer (CRC and length) has been checked is not inflated again only to check it. A point is taken at the
// end of a deflate block: the input's bit position, the member's running check and the last 32 KiB of output,
// from which inflation resumes (the method of zlib's zran example). Indexes are kept for the process, for the
// files read lately, keyed by the file's identity (device, inode, size, modification time): the volumes of a
// compressed series, read one after another by fresh sources, share one. Used by FileSamples
// (store/file_samples.h).
//
// Threads: any; each index guards itself, and the registry too.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <utility>
#include <vector>

#include "store/source_raw.h"

namespace ropecast {

// Where inflation may resume: at the end of a deflate block inside a member.
struct DeflateAccessPoint {
  uint64_t output = 0;            // decompressed bytes before the point, from the stream's start
  uint64_t input = 0;             // file offset of the first compressed byte inflate had not taken
  int bits = 0;                   // bits of the byte before `input` not yet consumed (0-7)
  uint32_t check = 0;             // the member's running CRC-32 (gzip) or Adler-32 (zlib) up to the point
  uint64_t memberOutput = 0;      // decompressed bytes of the member before the point
  bool gzip = true;               // the member's wrapper: gzip, else zlib
  std::vector<std::byte> window;  // the output's last 32 KiB before the point (less near the stream's start)
};

class DeflateIndex {
 public:
  // At most this many points are kept: past it, every other one is dropped and the spacing doubled.
  static constexpr size_t kMaxPoints = 256;
  static constexpr uint64_t kFirstSpacingBytes = uint64_t(1) << 20;

  // The last point at or before `output` (decompressed bytes); nullopt when there is none, or when it does
  // not lie past `past` (a reader there gains nothing from it, and its window is not copied).
  std::optional<DeflateAccessPoint> pointBefore(uint64_t output, std::optional<uint64_t> past = {}) const;
  // Whether a point at `output` would be kept: past the last point by the spacing.
  bool wantsPointAt(uint64_t output) const;
  // Keeps `point` if wantsPointAt(point.output) still holds.
  void add(DeflateAccessPoint point);

  // The member spanning decompressed bytes [first, end) was inflated through its trailer and found whole.
  void memberChecked(uint64_t first, uint64_t end);
  // Whether the member holding decompressed byte `output` (or ending there) has been checked.
  bool memberCheckedAt(uint64_t output) const;

  size_t pointCount() const;

 private:
  mutable std::mutex mutex_;
  std::vector<DeflateAccessPoint> points_;  // by output, increasing
  uint64_t spacing_ = kFirstSpacingBytes;
  std::vector<std::pair<uint64_t, uint64_t>> checkedMembers_;
};

// The index of the deflated stream starting at `startOffset` in `file`, shared by every reader of the file as
// it is now (a file rewritten since gets a new one). The registry keeps the last few files' indexes.
std::shared_ptr<DeflateIndex> deflateIndexFor(const PosixFile& file, uint64_t startOffset);

}  // namespace ropecast
