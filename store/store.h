// Store: the reader of an octree store file (store_format.h, docs/FORMAT.md), a BrickSource for the loader,
// `verify`, `extract` and `info`.
//
// open() validates header, metadata and node table (a damaged or truncated file is an Error naming it) and
// keeps the node table in memory. Threads: after open, every method may be called from any number of threads
// at once; readBrick uses pread and a per-thread zstd context, no lock.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "store/brick_source.h"
#include "store/store_format.h"

namespace ropecast {

// Whether `path` is a regular file that begins as a store does (its magic): a store, perhaps damaged, not a
// volume.
bool isStoreFile(const std::string& path);
// Whether a command that takes a store or a volume reads `path` as a store: a store file, or a name a store
// has (.rcast), so that a damaged or missing store is refused as a store, not read as a volume.
bool isStoreInput(const std::string& path);

class Store final : public BrickSource {
 public:
  static std::unique_ptr<Store> open(const std::filesystem::path& path);
  // The same from bytes in memory (fuzzing, tests); `name` appears in error messages.
  static std::unique_ptr<Store> openMemory(std::vector<std::byte> bytes, std::string name);
  ~Store() override;

  const BrickSourceInfo& info() const override { return info_; }
  NodeInfo node(const NodeKey& key) const override;
  void readBrick(const NodeKey& key, std::span<std::byte> out) const override;
  uint64_t compressedBytes(const NodeKey& key) const override;

  const StoreMetadata& metadata() const { return metadata_; }
  std::span<const StoreNodeEntry> entries() const { return entries_; }
  const std::string& name() const { return name_; }
  uint64_t fileBytes() const { return fileBytes_; }
  // Bytes after the node table, which ends the layout a store is written in (`verify` reports them).
  uint64_t bytesAfterNodeTable() const { return fileBytes_ - nodeTableEnd_; }
  // "depth 3 (2, 0, 5)": how errors and `verify` name a node.
  static std::string describeNode(const NodeKey& key);

 private:
  Store() = default;
  void load();
  void readAt(uint64_t offset, std::span<std::byte> out) const;

  std::string name_;
  int fd_ = -1;
  std::vector<std::byte> memory_;  // used instead of fd_ by openMemory
  uint64_t fileBytes_ = 0;
  uint64_t nodeTableEnd_ = 0;
  StoreMetadata metadata_;
  BrickSourceInfo info_;
  std::vector<StoreNodeEntry> entries_;
};

// What `ropecast info` prints.
struct StoreSummary {
  struct Level {
    uint32_t level = 0;  // resolution level (0 = full)
    uint32_t depth = 0;
    glm::u32vec3 dims{0};   // samples per axis
    glm::u32vec3 nodes{0};  // inside nodes per axis
    uint64_t total = 0, empty = 0, constant = 0, data = 0;
    uint64_t payloadBytes = 0;
  };
  std::vector<Level> levels;  // finest first
  uint64_t total = 0, empty = 0, constant = 0, data = 0;
  uint64_t payloadBytes = 0;       // compressed brick payloads
  uint64_t uncompressedBytes = 0;  // the payload-carrying bricks uncompressed
  uint64_t allBricksBytes = 0;     // every inside node's brick uncompressed
  uint64_t rawBytes = 0;           // the source volume in its original type
  uint64_t fileBytes = 0;
};
StoreSummary summarizeStore(const Store& store);

}  // namespace ropecast
