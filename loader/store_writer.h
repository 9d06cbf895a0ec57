// StoreWriter: writes an octree store file (store_format.h) under a temporary name next to the output and
// renames it when finish() completes; destroying an unfinished writer (a failure, an exception) removes the
// temporary, so a failure never leaves a half-written store.
//
// Owned by the converter (or a test). appendPayload() may be called from several threads at once (each call
// reserves its byte range under a short lock, then writes with pwrite); finish() from one thread after all
// appends have returned.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <mutex>
#include <span>
#include <string>

#include "loader/store_format.h"

namespace ropecast {

// A file being written under a temporary name next to `output` ("OUT.tmp-XXXXXX"); commit() renames it onto
// `output`, destruction without commit removes it. writeAt() may be called from several threads at once.
class TemporaryFile {
 public:
  // `who` names the caller in errors ("StoreWriter", "extract"). Throws ropecast::Error naming `output`.
  TemporaryFile(std::filesystem::path output, std::string who);
  ~TemporaryFile();
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;

  void writeAt(uint64_t offset, std::span<const std::byte> bytes);
  void commit();  // closes and renames onto the output path
  const std::filesystem::path& output() const { return output_; }
  const std::filesystem::path& path() const { return temporary_; }

 private:
  std::filesystem::path output_, temporary_;
  std::string who_;
  int fd_ = -1;
  int signalSlot_ = -1;  // where removeTemporaryFilesOnSignals finds the temporary name
  bool committed_ = false;
};

// A temporary file name written by someone else (an image library that opens files by name): while the guard
// lives, the handlers of removeTemporaryFilesOnSignals remove that file too. Any thread.
class TemporaryNameGuard {
 public:
  explicit TemporaryNameGuard(const std::string& path);
  ~TemporaryNameGuard();
  TemporaryNameGuard(const TemporaryNameGuard&) = delete;
  TemporaryNameGuard& operator=(const TemporaryNameGuard&) = delete;

 private:
  int signalSlot_ = -1;
};

// For the command-line tools: installs SIGINT/SIGTERM/SIGHUP handlers that remove every TemporaryFile still
// open in the process (async-signal-safe: unlink only) and then die of the signal as before, so an
// interrupted convert, extract or render leaves nothing behind either. Main thread, once.
void removeTemporaryFilesOnSignals();

class StoreWriter {
 public:
  // Creates the temporary file. Throws ropecast::Error naming `output` if it cannot be created.
  explicit StoreWriter(std::filesystem::path output);
  StoreWriter(const StoreWriter&) = delete;
  StoreWriter& operator=(const StoreWriter&) = delete;

  // Appends a compressed payload; returns its file offset. Thread-safe.
  uint64_t appendPayload(std::span<const std::byte> payload);

  // Writes metadata, node table and header, syncs, closes and renames onto the output path.
  void finish(const StoreMetadata& metadata, std::span<const StoreNodeEntry> nodes);

  const std::filesystem::path& output() const { return file_.output(); }
  const std::filesystem::path& temporaryPath() const { return file_.path(); }

 private:
  TemporaryFile file_;
  std::mutex reserveMutex_;
  uint64_t endOffset_ = sizeof(StoreHeader);
  bool finished_ = false;
};

// The metadata as the JSON text stored in the file (also used by `info --json`).
std::string storeMetadataToJson(const StoreMetadata& metadata);

}  // namespace ropecast
