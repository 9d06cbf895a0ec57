// A volume's samples stored as one block of a file, plain or deflated (a gzip or zlib stream), as NRRD,
// MetaImage and NIfTI files hold them; read by byte range as the sources' slabs ask. Plain blocks are read
// with pread; deflated ones as a forward stream, which resumes from the file's nearest access point
// (store/deflate_index.h), else from the stream's start, when a range behind it or far ahead is asked for.
// Also what the sources of such files share once their header is read: the data file a header names, and the
// VolumeSource over a block. Used by the file-format VolumeSources (store/).
//
// Threads: FileSamples and the block source, one thread at a time per object (a deflated stream is
// per-object state); the functions, any thread.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "store/source_raw.h"
#include "store/volume_source.h"

namespace ropecast {

enum class SampleEncoding : uint8_t { Raw, Deflated };

// Where a file keeps the samples, and the words its messages use.
struct SampleBlock {
  SampleEncoding encoding = SampleEncoding::Raw;
  // File offset of the samples (Raw) or of the compressed stream (Deflated); nullopt: raw samples that end
  // the file (a NRRD's byte skip of -1, a MetaImage's header size of -1).
  std::optional<uint64_t> start = 0;
  uint64_t skip = 0;     // Deflated: decompressed bytes before the samples
  uint64_t bytes = 0;    // the samples' bytes
  std::string fileKind;  // how messages name the file: "NRRD data file", "MetaImage data file", ...
  std::string volume;    // the volume, for messages: "9x6x5 uint16"
};

class DeflateStream;

class FileSamples {
 public:
  // Raw blocks are checked at once: a file shorter than the block is refused as truncated, naming the file,
  // its size and the size the block needs. Deflated ones are checked as they are read.
  FileSamples(std::unique_ptr<PosixFile> file, SampleBlock block);
  ~FileSamples();
  FileSamples(const FileSamples&) = delete;
  FileSamples& operator=(const FileSamples&) = delete;

  // Fills `out` with the samples' bytes from `offset` (within the samples) on. A deflated read that reaches
  // the samples' end also reads the stream's trailer, so a file cut after the last sample, or whose checksum
  // fails, is refused. Throws ropecast::Error naming the file: truncated or corrupt data.
  void read(uint64_t offset, std::span<std::byte> out);

  const PosixFile& file() const { return *file_; }
  // Decompressed bytes inflated so far, those skipped to reach a range included (0 for raw samples).
  uint64_t inflatedBytes() const;

 private:
  std::unique_ptr<PosixFile> file_;
  SampleBlock block_;
  uint64_t rawOffset_ = 0;                  // Raw: file offset of the first sample
  std::unique_ptr<DeflateStream> inflate_;  // Deflated only; reads file_
};

// The path of the data file a header names (`fileName` as written): relative to the header's folder unless
// absolute.
std::string pathBesideHeader(const std::string& headerPath, const std::string& fileName);

// Opens the data file at `dataPath`. When it is not the header's own file, a failure names the header and the
// file as the header wrote it too: "HEADER_KIND HEADER_PATH names data file FILE_NAME: ...".
std::unique_ptr<PosixFile> openDataFile(const std::string& dataPath, const std::string& headerKind,
                                        const std::string& headerPath, const std::string& fileName);

// The VolumeSource whose samples are `samples`, as `info` describes them, stored in the given byte order:
// what the NRRD and MetaImage sources are once their header is read. Sets the value range of uint8 volumes.
std::unique_ptr<VolumeSource> openBlockSource(VolumeInfo info, std::unique_ptr<FileSamples> samples,
                                              bool storedBigEndian);

}  // namespace ropecast
