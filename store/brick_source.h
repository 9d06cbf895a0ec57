// BrickSource: random access to the nodes of a bricked octree (a store file, or a procedural volume generated
// brick by brick). What the loader streams from and what `verify`/`extract` read.
//
// Threads: every method may be called from several threads at once (the loader's I/O workers read bricks in
// parallel); implementations keep no per-call shared mutable state (pread, no global lock).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "core/sample_type.h"
#include "core/transfer_function.h"
#include "store/octree_layout.h"
#include "store/volume_source.h"

namespace ropecast {

enum class NodeKind : uint8_t {
  Outside = 0,   // no sample of the node lies in the data (never stored)
  Empty = 1,     // discarded (--discard-below): treat as empty space, no payload
  Constant = 2,  // every sample it covers (borders and descendants included) equals min == max; no payload
  Data = 3,      // has a brick payload
};

// What the loader knows about a node without reading its brick. min/max are stored values (see ValueMapping)
// over everything the node covers: its own samples with borders, and all its descendants.
struct NodeInfo {
  NodeKind kind = NodeKind::Outside;
  uint16_t minValue = 0;
  uint16_t maxValue = 0;
};

struct BrickSourceInfo {
  OctreeLayout layout;
  VolumeInfo volume;                          // dims, spacing, original type and value range in data units
  SampleType storedType = SampleType::UInt8;  // UInt8 or UInt16
  ValueMapping mapping;                       // stored -> data units
  // The volume's file counts x the other way (its frame mirrors; a store keeps a turn, store/converter.h):
  // the file's sample i along x is this source's dims.x - 1 - i, at level L of dims n_L: n_L - 1 - i.
  // What the command line and the viewer show and take are the file's indices (fileVoxelX).
  bool xReversed = false;
};

// A voxel's x index along a level of `size` samples, the file's for the source's or the source's for the
// file's (the same map both ways).
inline uint32_t fileVoxelX(const BrickSourceInfo& info, uint32_t x, uint32_t size) {
  return info.xReversed ? size - 1 - x : x;
}

class BrickSource {
 public:
  virtual ~BrickSource() = default;
  virtual const BrickSourceInfo& info() const = 0;

  // Cheap (in memory). Outside nodes (layout().isInside() false) report NodeKind::Outside.
  virtual NodeInfo node(const NodeKey& key) const = 0;

  // The node's brick: storedBrickEdge()^3 samples of storedType, x fastest, border included. For Constant
  // nodes fills the constant; for Empty nodes (samples not kept) a value below the discard threshold (a
  // store: the brick's minimum); for Outside nodes zeros. Throws ropecast::Error on I/O failure or a damaged
  // brick (naming the file and the node).
  virtual void readBrick(const NodeKey& key, std::span<std::byte> out) const = 0;

  // Bytes readBrick takes from storage for the node (what the loader counts as read): a store's compressed
  // payload (0 for payload-less nodes); by default, for sources that generate their bricks (procedural), the
  // decompressed brick of a Data node and 0 for the others. Cheap (no I/O).
  virtual uint64_t compressedBytes(const NodeKey& key) const {
    return node(key).kind == NodeKind::Data ? brickBytes() : 0;
  }

  size_t brickBytes() const {
    return size_t(info().layout.storedBrickSamples()) * bytesPerSample(info().storedType);
  }
};

// The range of a brick source's data that transfer-function presets are placed in: the source's known value
// range, else what its stored type can hold.
inline TfDataRange tfDataRangeFor(const BrickSourceInfo& info) {
  TfDataRange d;
  d.sourceType = info.volume.type;
  const double storedMax = storedMaxOf(info.storedType);
  d.minValue = info.volume.valueMin.value_or(info.mapping.toData(0.0));
  d.maxValue = info.volume.valueMax.value_or(info.mapping.toData(storedMax));
  if (!(d.maxValue > d.minValue)) d.maxValue = d.minValue + 1.0;
  return d;
}

}  // namespace ropecast
