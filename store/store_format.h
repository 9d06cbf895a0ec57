// The on-disk layout of an octree store file (docs/FORMAT.md describes it byte by byte). Plain data shared by
// the writer (store_writer.h) and the reader (store.h); any thread.
//
// A store is one little-endian file:
//   [StoreHeader, 64 bytes] [zstd brick payloads ...] [metadata JSON] [node table: StoreNodeEntry per node]
// The header is written last (the payloads are streamed first), so a file whose header is complete was
// completely written. Node entries follow OctreeLayout::nodeIndex (inside nodes only, root first).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "core/sample_type.h"
#include "store/octree_layout.h"
#include "store/volume_source.h"

namespace ropecast {

inline constexpr char kStoreMagic[8] = {'R', 'O', 'P', 'E', 'S', 'T', 'O', 'R'};
inline constexpr uint32_t kStoreVersion = 1;

// File offset 0. Every field little-endian; crc32 is zlib's crc32.
struct StoreHeader {
  char magic[8];             // 0:  "ROPESTOR"
  uint32_t version;          // 8:  kStoreVersion
  uint32_t headerBytes;      // 12: sizeof(StoreHeader) = 64
  uint64_t metadataOffset;   // 16: byte offset of the metadata JSON (UTF-8, no terminator)
  uint64_t metadataBytes;    // 24
  uint64_t nodeTableOffset;  // 32: byte offset of nodeCount StoreNodeEntry records
  uint64_t nodeCount;        // 40: OctreeLayout::insideNodeCount()
  uint32_t metadataCrc;      // 48: crc32 of the metadata bytes
  uint32_t nodeTableCrc;     // 52: crc32 of the node table bytes
  uint32_t nodeEntryBytes;   // 56: sizeof(StoreNodeEntry) = 24
  uint32_t headerCrc;        // 60: crc32 of bytes [0, 60)
};
static_assert(sizeof(StoreHeader) == 64);
static_assert(offsetof(StoreHeader, version) == 8);
static_assert(offsetof(StoreHeader, headerBytes) == 12);
static_assert(offsetof(StoreHeader, metadataOffset) == 16);
static_assert(offsetof(StoreHeader, metadataBytes) == 24);
static_assert(offsetof(StoreHeader, nodeTableOffset) == 32);
static_assert(offsetof(StoreHeader, nodeCount) == 40);
static_assert(offsetof(StoreHeader, metadataCrc) == 48);
static_assert(offsetof(StoreHeader, nodeTableCrc) == 52);
static_assert(offsetof(StoreHeader, nodeEntryBytes) == 56);
static_assert(offsetof(StoreHeader, headerCrc) == 60);

// One per inside node. A Data node with payloadBytes == 0 has a uniform brick of fillValue (its own samples
// are uniform although a descendant's are not, so it is not Constant). Empty and Constant nodes have no
// payload.
struct StoreNodeEntry {
  uint64_t payloadOffset;  // 0:  byte offset of the zstd frame (0 when there is none)
  uint32_t payloadBytes;   // 8:  compressed bytes (0 when there is none)
  uint32_t payloadCrc;     // 12: crc32 of the compressed bytes
  uint16_t minValue;       // 16: stored values over the brick with borders and all descendants
  uint16_t maxValue;       // 18
  uint8_t kind;            // 20: NodeKind (Empty 1, Constant 2, Data 3)
  uint8_t reserved;        // 21: 0
  uint16_t fillValue;      // 22: the value of a payload-less Data, Constant or Empty node
};
static_assert(sizeof(StoreNodeEntry) == 24);
static_assert(offsetof(StoreNodeEntry, payloadBytes) == 8);
static_assert(offsetof(StoreNodeEntry, payloadCrc) == 12);
static_assert(offsetof(StoreNodeEntry, minValue) == 16);
static_assert(offsetof(StoreNodeEntry, maxValue) == 18);
static_assert(offsetof(StoreNodeEntry, kind) == 20);
static_assert(offsetof(StoreNodeEntry, reserved) == 21);
static_assert(offsetof(StoreNodeEntry, fillValue) == 22);

// How a brick payload encodes its samples before zstd. uint16 stores split the samples into two byte planes
// (all low bytes, then all high bytes): the smooth high bytes then compress well and fast, and zstd wastes no
// time looking for matches across the noisy low bytes (less CPU and smaller payloads on noisy 12-bit CT-like
// data).
enum class PayloadEncoding : uint8_t {
  Zstd = 0,            // the samples as they are (uint8 stores)
  ZstdBytePlanes = 1,  // uint16 only: n low bytes, then n high bytes
};

inline void splitBytePlanes(const uint16_t* samples, size_t n, std::byte* out) {
  for (size_t i = 0; i < n; ++i) {
    out[i] = std::byte(samples[i] & 0xFF);
    out[n + i] = std::byte(samples[i] >> 8);
  }
}
inline void joinBytePlanes(const std::byte* planes, size_t n, uint16_t* samples) {
  for (size_t i = 0; i < n; ++i) samples[i] = uint16_t(uint16_t(planes[i]) | uint16_t(planes[n + i]) << 8);
}

// What the metadata JSON holds (field names in docs/FORMAT.md).
struct StoreMetadata {
  VolumeInfo volume;  // dims, spacing, original type, value range (data units), source description
  // The source's x axis runs the other way: its frame mirrors, and the store keeps a turn
  // (store/converter.h); the source's sample i along x is the store's dims.x - 1 - i.
  bool xReversed = false;
  uint32_t brickSize = kDefaultBrickSize;
  uint32_t border = kBrickBorder;
  uint32_t levels = 0;  // maxDepth + 1
  SampleType storedType = SampleType::UInt8;
  ValueMapping mapping;                // stored -> data units
  std::optional<double> discardBelow;  // data units, when --discard-below was given
  int zstdLevel = 3;
  PayloadEncoding payloadEncoding = PayloadEncoding::Zstd;
  std::string creationTool;
};

// zlib's crc32 of `bytes` (the checksum of header, metadata, node table and payloads).
uint32_t storeCrc32(std::span<const std::byte> bytes);

}  // namespace ropecast
