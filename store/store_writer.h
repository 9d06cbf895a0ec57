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

#include "core/temporary_file.h"
#include "store/store_format.h"

namespace ropecast {

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
