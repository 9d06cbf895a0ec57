// The streaming converter: turns a VolumeSource into an octree store file (store_format.h).
//
// It reads the source in slabs of z slices and pushes them through a cascade of per-level windows: level L
// keeps only the B + 2*border slices its next row of bricks needs (plus one for the filter), emits that row
// of bricks when complete, and box-filters pairs of its slices into level L+1. Memory is O(nx*ny*(B +
// 2*border)) whatever nz is. Bricks are compressed (zstd) by a small pool of worker threads and appended by
// StoreWriter; the file appears under `output` only when complete.
//
// Threads: convertVolume runs on the calling thread (which reads the source and builds bricks) and starts its
// own compression workers; the progress callback is called on the calling thread.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "store/octree_layout.h"
#include "store/volume_source.h"

namespace ropecast {

struct ConvertProgress {
  // ValueRange: the min/max pre-pass of a source whose mapping depends on its range (float32, float64,
  // uint32, int32; core/sample_type.h mapsOverValueRange).
  enum class Phase { ValueRange, Bricks };
  Phase phase = Phase::Bricks;
  uint64_t slicesDone = 0;
  uint64_t slicesTotal = 0;
  uint64_t bytesDone = 0;  // source bytes read in this phase
  uint64_t bytesTotal = 0;
};

struct ConvertOptions {
  uint32_t brickSize = kDefaultBrickSize;
  std::optional<double> discardBelow;  // data units: nodes whose max is below become Empty
  int zstdLevel = 3;
  unsigned workerThreads = 0;  // compression threads; 0 = std::thread::hardware_concurrency()
  std::string creationTool = "ropecast convert";
  std::function<void(const ConvertProgress&)> progress;
};

struct ConvertStats {
  uint64_t nodes = 0, emptyNodes = 0, constantNodes = 0, dataNodes = 0;
  uint64_t payloadBytes = 0;
  // The memory that depends on the volume (it grows with nx*ny, never with nz):
  uint64_t peakWindowBytes = 0;  // slices held by the per-level windows at their peak
  uint64_t readBufferBytes = 0;  // the slab read from the source (~16 MiB, at least one slice)
  uint64_t brickQueueBytes = 0;  // raw bricks waiting for a compression worker, at most
  uint64_t reorderBytes = 0;     // compressed bricks waiting for an earlier one to be written, at most
  uint64_t peakBufferedBytes() const {
    return peakWindowBytes + readBufferBytes + brickQueueBytes + reorderBytes;
  }
  // Samples the value mapping could not keep (sources of the types whose mapping depends on their range):
  // NaN, stored as the range's low end; infinities, and finite values outside a range the source knows
  // (VolumeInfo::valueMin, valueMax), clamped to the nearer end. docs/FORMAT.md "Stored values".
  uint64_t nanSamples = 0, infiniteSamples = 0, clampedSamples = 0;
  double valueMin = 0.0, valueMax = 0.0;  // the value range written, in data units
};

// What is wrong with the options, whatever the source ("convert: --brick 3: expected ..."), or "".
std::string convertOptionsProblem(const ConvertOptions& options);

// Throws ropecast::Error (source failures, unwritable output, bad options); leaves no file behind on failure.
ConvertStats convertVolume(VolumeSource& source, const std::filesystem::path& output,
                           const ConvertOptions& options = {});

}  // namespace ropecast
