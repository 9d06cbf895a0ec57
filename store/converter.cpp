#include "store/converter.h"

#include <zstd.h>

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <exception>
#include <limits>
#include <map>
#include <mutex>
#include <string>
#include <system_error>
#include <thread>
#include <tuple>
#include <vector>

#include "core/error.h"
#include "store/brick_source.h"
#include "store/store_format.h"
#include "store/store_writer.h"

namespace ropecast {

namespace {

// Compresses bricks on worker threads and appends them through the writer in the order they were submitted,
// whichever worker finishes first, so that a store does not depend on the thread count or on timing. The
// submitting thread blocks while the queue is full, so at most `maxQueued` raw bricks wait in memory, and
// workers wait while `maxQueued` compressed bricks wait for an earlier one.
class CompressPool {
 public:
  CompressPool(StoreWriter& writer, std::vector<StoreNodeEntry>& entries, int zstdLevel, unsigned threads,
               size_t maxQueued)
      : writer_(writer), entries_(entries), zstdLevel_(zstdLevel), maxQueued_(maxQueued) {
    try {
      for (unsigned i = 0; i < threads; ++i) workers_.emplace_back([this] { work(); });
    } catch (const std::system_error& e) {
      stop();  // the destructor does not run for a constructor that throws: join those started
      throw Error("convert: cannot start " + std::to_string(threads) + " compression threads (" +
                  std::to_string(workers_.size()) + " started): " + e.what());
    }
  }
  ~CompressPool() { stop(); }

  void submit(uint64_t nodeIndex, std::vector<std::byte>&& brick) {
    std::unique_lock lock(mutex_);
    spaceFree_.wait(lock, [&] { return queue_.size() < maxQueued_ || error_; });
    if (error_) std::rethrow_exception(error_);
    queue_.push_back({submitted_++, nodeIndex, std::move(brick)});
    workAvailable_.notify_one();
  }

  // Waits for every submitted brick; rethrows the first worker failure.
  void finish() {
    stop();
    if (error_) std::rethrow_exception(error_);
  }

  std::vector<std::byte> recycledBuffer() {
    std::lock_guard lock(mutex_);
    if (spare_.empty()) return {};
    auto b = std::move(spare_.back());
    spare_.pop_back();
    return b;
  }

 private:
  struct Job {
    uint64_t sequence;  // submission order, the order of the payloads in the file
    uint64_t nodeIndex;
    std::vector<std::byte> brick;
  };
  struct Compressed {
    uint64_t nodeIndex;
    std::vector<std::byte> payload;
  };

  void stop() {
    {
      std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    workAvailable_.notify_all();
    for (auto& w : workers_)
      if (w.joinable()) w.join();
  }

  void work() {
    ZSTD_CCtx* context = ZSTD_createCCtx();
    ZSTD_CCtx_setParameter(context, ZSTD_c_compressionLevel, zstdLevel_);
    std::vector<std::byte> compressed;
    for (;;) {
      Job job;
      {
        std::unique_lock lock(mutex_);
        // Jobs are taken in order, so the brick the file needs next is never queued behind a full reorder
        // buffer: a worker holds it.
        workAvailable_.wait(lock, [&] {
          return (!queue_.empty() && compressedWaiting_.size() < maxQueued_) || (stopping_ && queue_.empty());
        });
        if (queue_.empty()) break;
        job = std::move(queue_.front());
        queue_.pop_front();
      }
      spaceFree_.notify_one();
      try {
        compressed.resize(ZSTD_compressBound(job.brick.size()));
        const size_t n =
            ZSTD_compress2(context, compressed.data(), compressed.size(), job.brick.data(), job.brick.size());
        if (ZSTD_isError(n))
          throw Error(std::string("convert: zstd compression failed: ") + ZSTD_getErrorName(n));
        writeInOrder(job.sequence, {job.nodeIndex, std::vector(compressed.begin(), compressed.begin() + n)});
      } catch (...) {
        std::lock_guard lock(mutex_);
        if (!error_) error_ = std::current_exception();
        queue_.clear();
        spaceFree_.notify_all();
        break;
      }
      std::lock_guard lock(mutex_);
      if (spare_.size() < maxQueued_) spare_.push_back(std::move(job.brick));
    }
    ZSTD_freeCCtx(context);
  }

  // Keeps the payload until every earlier one is written; the worker that completes the next one writes it
  // and the waiting ones that follow it (one writer at a time, outside the lock).
  void writeInOrder(uint64_t sequence, Compressed compressed) {
    std::unique_lock lock(mutex_);
    compressedWaiting_.emplace(sequence, std::move(compressed));
    if (writing_) return;  // the worker writing takes this one in turn
    writing_ = true;
    while (!compressedWaiting_.empty() && compressedWaiting_.begin()->first == nextToWrite_) {
      auto next = compressedWaiting_.extract(compressedWaiting_.begin());
      lock.unlock();
      const std::vector<std::byte>& payload = next.mapped().payload;
      StoreNodeEntry& e = entries_[next.mapped().nodeIndex];  // only the writing worker touches these fields
      e.payloadCrc = storeCrc32(payload);
      e.payloadBytes = uint32_t(payload.size());
      e.payloadOffset = writer_.appendPayload(payload);
      lock.lock();
      ++nextToWrite_;
      workAvailable_.notify_all();  // room in the reorder buffer
    }
    writing_ = false;
  }

  StoreWriter& writer_;
  std::vector<StoreNodeEntry>& entries_;
  int zstdLevel_;
  size_t maxQueued_;
  std::mutex mutex_;
  std::condition_variable workAvailable_, spaceFree_;
  std::deque<Job> queue_;
  uint64_t submitted_ = 0, nextToWrite_ = 0;
  std::map<uint64_t, Compressed> compressedWaiting_;  // by sequence, none before nextToWrite_
  bool writing_ = false;
  std::vector<std::vector<std::byte>> spare_;
  bool stopping_ = false;
  std::exception_ptr error_;
  std::vector<std::thread> workers_;
};

// Samples of source type V through the mapping (the types of mapsOverValueRange): rounded to the nearest
// stored value and clamped to [0, high], the stored value of the range's high end (65535 when quantized; for
// a float range whose finite values are all one, 0, so that an infinity stays in the value range); NaN reads
// as the range's low end. With scale 1 (uint32/int32 whose range fits 16 bits) this is exact. Counts what it
// could not keep in `stats`.
template <typename V, typename T>
void mapToStored(const std::byte* in, size_t count, const ValueMapping& mapping, double high, T* out,
                 ConvertStats& stats) {
  const double inverseScale = 1.0 / mapping.scale;
  uint64_t nan = 0, infinite = 0, clamped = 0;
  for (size_t i = 0; i < count; ++i) {
    V v;
    std::memcpy(&v, in + sizeof(V) * i, sizeof(V));
    const double q = std::nearbyint((double(v) - mapping.offset) * inverseScale);
    if (std::isnan(q)) {
      out[i] = T(0);
      ++nan;
      continue;
    }
    if (std::isinf(double(v)))
      ++infinite;
    else if (q < 0.0 || q > high)
      ++clamped;
    out[i] = T(std::clamp(q, 0.0, high));
  }
  stats.nanSamples += nan;
  stats.infiniteSamples += infinite;
  stats.clampedSamples += clamped;
}

// Turns one source slice into stored values (store_format.h: uint8/uint16 kept, int8 and int16 offset, the
// others through mapToStored).
template <typename T>
void toStored(const std::byte* in, size_t count, SampleType type, const ValueMapping& mapping, double high,
              T* out, ConvertStats& stats) {
  switch (type) {
    case SampleType::UInt8:
    case SampleType::UInt16:
      std::memcpy(out, in, count * sizeof(T));
      return;
    case SampleType::Int8:
      for (size_t i = 0; i < count; ++i) out[i] = T(int32_t(int8_t(in[i])) + 128);
      return;
    case SampleType::Int16:
      for (size_t i = 0; i < count; ++i) {
        int16_t v;
        std::memcpy(&v, in + 2 * i, 2);
        out[i] = T(int32_t(v) + 32768);
      }
      return;
    case SampleType::UInt32:
      return mapToStored<uint32_t>(in, count, mapping, high, out, stats);
    case SampleType::Int32:
      return mapToStored<int32_t>(in, count, mapping, high, out, stats);
    case SampleType::Float32:
      return mapToStored<float>(in, count, mapping, high, out, stats);
    case SampleType::Float64:
      return mapToStored<double>(in, count, mapping, high, out, stats);
  }
}

uint32_t slabSlicesFor(const VolumeInfo& info) {
  const size_t target = size_t(16) << 20;  // read ~16 MiB at a time
  return std::clamp<uint32_t>(uint32_t(target / std::max<size_t>(info.sliceBytes(), 1)), 1u, info.dims.z);
}

// Widens the finite min/max [lo, hi] by samples of type V.
template <typename V>
void widenRange(std::span<const std::byte> bytes, double& lo, double& hi) {
  const size_t n = bytes.size() / sizeof(V);
  for (size_t i = 0; i < n; ++i) {
    V v;
    std::memcpy(&v, bytes.data() + sizeof(V) * i, sizeof(V));
    if (std::isfinite(double(v))) lo = std::min(lo, double(v)), hi = std::max(hi, double(v));
  }
}

// The pre-pass of a source whose mapping depends on its range (mapsOverValueRange) and that does not know it:
// the min/max of its finite values.
std::pair<double, double> scanValueRange(VolumeSource& source, const ConvertOptions& options) {
  const VolumeInfo& info = source.info();
  const uint32_t slab = slabSlicesFor(info);
  std::vector<std::byte> buffer(size_t(slab) * info.sliceBytes());
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  ConvertProgress progress{ConvertProgress::Phase::ValueRange, 0, info.dims.z, 0,
                           uint64_t(info.dims.z) * info.sliceBytes()};
  for (uint32_t z = 0; z < info.dims.z; z += slab) {
    const uint32_t count = std::min(slab, info.dims.z - z);
    const auto bytes = std::span(buffer).first(size_t(count) * info.sliceBytes());
    source.readSlab(z, count, bytes);
    forSampleType(info.type, [&](auto zero) { widenRange<decltype(zero)>(bytes, lo, hi); });
    progress.slicesDone = z + count;
    progress.bytesDone = progress.slicesDone * info.sliceBytes();
    if (options.progress) options.progress(progress);
  }
  if (lo > hi) return {0.0, 0.0};  // no finite value at all
  return {lo, hi};
}

// The cascade of per-level slice windows (see converter.h). T is the stored sample type.
template <typename T>
class Cascade {
 public:
  Cascade(const OctreeLayout& layout, const ValueMapping& mapping, std::optional<double> discardBelow,
          std::vector<StoreNodeEntry>& entries, CompressPool& pool)
      : layout_(layout), mapping_(mapping), discardBelow_(discardBelow), entries_(entries), pool_(pool) {
    for (uint32_t level = 0; level <= layout.maxDepth; ++level) {
      Level lv;
      lv.level = level;
      lv.depth = layout.maxDepth - level;
      lv.dims = layout.levelDims(level);
      lv.nodes = layout.insideNodes(lv.depth);
      levels_.push_back(std::move(lv));
    }
  }

  // A fresh level-0 slice buffer (recycled when possible).
  std::vector<T> newSlice(uint32_t level) { return takeSpare(levels_[level]); }

  void push(uint32_t level, std::vector<T>&& slice) {
    Level& lv = levels_[level];
    const uint32_t s = lv.received++;
    lv.slices.push_back(std::move(slice));
    heldBytes_ += lv.slices.back().size() * sizeof(T);
    peakHeldBytes_ = std::max(peakHeldBytes_, heldBytes_);

    const uint32_t b = layout_.brickSize, border = kBrickBorder;
    while (lv.nextRow < lv.nodes.z && s >= std::min(lv.dims.z - 1, (lv.nextRow + 1) * b + border - 1)) {
      emitRow(lv, lv.nextRow);
      ++lv.nextRow;
    }
    if (level + 1 < levels_.size() && (s % 2 == 1 || s == lv.dims.z - 1)) {
      Level& next = levels_[level + 1];
      std::vector<T> filtered = takeSpare(next);
      filterPair(lv, s - s % 2, s, next.dims, filtered);
      dropSlices(lv, s / 2 + 1);
      push(level + 1, std::move(filtered));
    } else {
      dropSlices(lv, level + 1 < levels_.size() ? levels_[level + 1].received : lv.received);
    }
  }

  uint64_t peakHeldBytes() const { return peakHeldBytes_; }

 private:
  struct Level {
    uint32_t level = 0, depth = 0;
    glm::u32vec3 dims{0}, nodes{0};
    std::deque<std::vector<T>> slices;  // slices [firstSlice, firstSlice + slices.size())
    uint32_t firstSlice = 0;
    uint32_t received = 0;
    uint32_t nextRow = 0;  // next z-row of bricks to emit
    std::vector<std::vector<T>> spare;
  };

  std::vector<T> takeSpare(Level& lv) {
    const size_t n = size_t(lv.dims.x) * lv.dims.y;
    if (!lv.spare.empty()) {
      auto v = std::move(lv.spare.back());
      lv.spare.pop_back();
      return v;
    }
    return std::vector<T>(n);
  }

  const T* slice(const Level& lv, uint32_t z) const { return lv.slices[z - lv.firstSlice].data(); }

  // Level L+1 slice from level-L slices z0 and z1 (z1 == z0 at an odd edge): 2x2x2 mean, rounded to nearest.
  void filterPair(const Level& lv, uint32_t z0, uint32_t z1, glm::u32vec3 nextDims,
                  std::vector<T>& out) const {
    const T* a = slice(lv, z0);
    const T* c = slice(lv, z1);
    const uint32_t nx = lv.dims.x, ny = lv.dims.y;
    for (uint32_t y = 0; y < nextDims.y; ++y) {
      const size_t y0 = size_t(2 * y) * nx, y1 = size_t(std::min(2 * y + 1, ny - 1)) * nx;
      T* o = out.data() + size_t(y) * nextDims.x;
      for (uint32_t x = 0; x < nextDims.x; ++x) {
        const uint32_t x0 = 2 * x, x1 = std::min(2 * x + 1, nx - 1);
        const uint32_t sum = uint32_t(a[y0 + x0]) + a[y0 + x1] + a[y1 + x0] + a[y1 + x1] + c[y0 + x0] +
                             c[y0 + x1] + c[y1 + x0] + c[y1 + x1];
        o[x] = T((sum + 4) / 8);
      }
    }
  }

  // Drops slices no longer needed by the next row of bricks nor by the next level's filter.
  void dropSlices(Level& lv, uint32_t nextLevelReceived) {
    const uint32_t b = layout_.brickSize;
    const uint32_t rowStart = lv.nextRow * b >= kBrickBorder ? lv.nextRow * b - kBrickBorder : 0;
    uint32_t keepFrom = lv.nextRow >= lv.nodes.z ? lv.received : rowStart;
    keepFrom = std::min(keepFrom, 2 * nextLevelReceived);
    while (lv.firstSlice < keepFrom && !lv.slices.empty()) {
      heldBytes_ -= lv.slices.front().size() * sizeof(T);
      lv.spare.push_back(std::move(lv.slices.front()));
      lv.slices.pop_front();
      ++lv.firstSlice;
    }
    if (lv.spare.size() > 2) lv.spare.resize(2);
  }

  void emitRow(const Level& lv, uint32_t row) {
    const uint32_t b = layout_.brickSize, edge = layout_.storedBrickEdge();
    const size_t brickSamples = size_t(edge) * edge * edge;
    std::vector<uint32_t> zIndex(edge), yIndex(edge), xIndex(edge);
    const auto clampedAxis = [&](std::vector<uint32_t>& index, uint32_t node, uint32_t n) {
      for (uint32_t i = 0; i < edge; ++i)
        index[i] = uint32_t(std::clamp<int64_t>(int64_t(node) * b - kBrickBorder + i, 0, int64_t(n) - 1));
    };
    clampedAxis(zIndex, row, lv.dims.z);
    for (uint32_t cy = 0; cy < lv.nodes.y; ++cy) {
      clampedAxis(yIndex, cy, lv.dims.y);
      for (uint32_t cx = 0; cx < lv.nodes.x; ++cx) {
        clampedAxis(xIndex, cx, lv.dims.x);
        std::vector<std::byte> bytes = pool_.recycledBuffer();
        bytes.resize(brickSamples * sizeof(T));
        // uint8 bricks are gathered in place; uint16 ones into scratch, then split into byte planes.
        if (scratch_.size() != brickSamples) scratch_.resize(brickSamples);
        T* brick = sizeof(T) == 1 ? reinterpret_cast<T*>(bytes.data()) : scratch_.data();
        T lo = std::numeric_limits<T>::max(), hi = 0;
        for (uint32_t k = 0; k < edge; ++k) {
          const T* s = slice(lv, zIndex[k]);
          for (uint32_t j = 0; j < edge; ++j) {
            const T* rowIn = s + size_t(yIndex[j]) * lv.dims.x;
            T* out = brick + (size_t(k) * edge + j) * edge;
            for (uint32_t i = 0; i < edge; ++i) out[i] = rowIn[xIndex[i]];
            for (uint32_t i = 0; i < edge; ++i) lo = std::min(lo, out[i]), hi = std::max(hi, out[i]);
          }
        }
        if constexpr (sizeof(T) == 2) splitBytePlanes(brick, brickSamples, bytes.data());
        finishNode({lv.depth, {cx, cy, row}}, lo, hi, std::move(bytes));
      }
    }
  }

  // Decides the node's kind from its own range and its children's (emitted before it: converter.h).
  void finishNode(const NodeKey& key, T ownMin, T ownMax, std::vector<std::byte>&& brick) {
    uint16_t lo = ownMin, hi = ownMax;
    if (key.depth < layout_.maxDepth) {
      for (uint32_t octant = 0; octant < 8; ++octant) {
        const NodeKey child = key.child(octant);
        if (!layout_.isInside(child)) continue;
        const StoreNodeEntry& c = entries_[layout_.nodeIndex(child)];
        if (c.kind == uint8_t(NodeKind::Outside))
          throw std::logic_error("convert: a child node was not finished before its parent");
        lo = std::min(lo, c.minValue);
        hi = std::max(hi, c.maxValue);
      }
    }
    const uint64_t index = layout_.nodeIndex(key);
    StoreNodeEntry& e = entries_[index];
    e.minValue = lo;
    e.maxValue = hi;
    e.fillValue = ownMin;
    if (discardBelow_ && mapping_.toData(hi) < *discardBelow_) {
      e.kind = uint8_t(NodeKind::Empty);
    } else if (lo == hi) {
      e.kind = uint8_t(NodeKind::Constant);
    } else {
      e.kind = uint8_t(NodeKind::Data);
      if (ownMin != ownMax) {  // a uniform brick needs no payload: fillValue says it
        pool_.submit(index, std::move(brick));
        return;
      }
    }
  }

  const OctreeLayout& layout_;
  ValueMapping mapping_;
  std::optional<double> discardBelow_;
  std::vector<StoreNodeEntry>& entries_;
  CompressPool& pool_;
  std::vector<Level> levels_;
  std::vector<T> scratch_;  // one gathered uint16 brick before its byte-plane split
  uint64_t heldBytes_ = 0, peakHeldBytes_ = 0;
};

template <typename T>
void streamSlices(VolumeSource& source, const OctreeLayout& layout, const ValueMapping& mapping,
                  double storedHigh, const ConvertOptions& options, std::vector<StoreNodeEntry>& entries,
                  CompressPool& pool, uint64_t queuedBytes, ConvertStats& stats) {
  const VolumeInfo& info = source.info();
  const bool reverseRows = mirrors(info.axes);  // see convertVolume
  Cascade<T> cascade(layout, mapping, options.discardBelow, entries, pool);
  const uint32_t slab = slabSlicesFor(info);
  const size_t sliceBytes = info.sliceBytes(), sliceSamples = size_t(info.dims.x) * info.dims.y;
  std::vector<std::byte> buffer(size_t(slab) * sliceBytes);
  ConvertProgress progress{ConvertProgress::Phase::Bricks, 0, info.dims.z, 0,
                           uint64_t(info.dims.z) * sliceBytes};
  for (uint32_t z = 0; z < info.dims.z; z += slab) {
    const uint32_t count = std::min(slab, info.dims.z - z);
    source.readSlab(z, count, std::span(buffer).first(size_t(count) * sliceBytes));
    for (uint32_t i = 0; i < count; ++i) {
      std::vector<T> slice = cascade.newSlice(0);
      toStored(buffer.data() + i * sliceBytes, sliceSamples, info.type, mapping, storedHigh, slice.data(),
               stats);
      if (reverseRows)
        for (size_t row = 0; row < sliceSamples; row += info.dims.x)
          std::reverse(slice.begin() + ptrdiff_t(row), slice.begin() + ptrdiff_t(row + info.dims.x));
      cascade.push(0, std::move(slice));
    }
    progress.slicesDone = z + count;
    progress.bytesDone = progress.slicesDone * sliceBytes;
    if (options.progress) options.progress(progress);
  }
  stats.peakWindowBytes = cascade.peakHeldBytes();
  stats.readBufferBytes = buffer.size();
  stats.brickQueueBytes = queuedBytes;
}

}  // namespace

std::string convertOptionsProblem(const ConvertOptions& options) {
  if (options.brickSize < 4 || options.brickSize > 256 || (options.brickSize & (options.brickSize - 1)) != 0)
    return "convert: --brick " + std::to_string(options.brickSize) + ": expected a power of two in [4, 256]";
  if (options.discardBelow && !std::isfinite(*options.discardBelow))
    return "convert: --discard-below " + formatNumber(*options.discardBelow) +
           ": expected a finite value in data units";
  if (options.zstdLevel < ZSTD_minCLevel() || options.zstdLevel > ZSTD_maxCLevel())
    return "convert: --zstd-level " + std::to_string(options.zstdLevel) + ": expected a value in [" +
           std::to_string(ZSTD_minCLevel()) + ", " + std::to_string(ZSTD_maxCLevel()) + "]";
  return "";
}

ConvertStats convertVolume(VolumeSource& source, const std::filesystem::path& output,
                           const ConvertOptions& options) {
  const VolumeInfo& info = source.info();
  if (info.dims.x == 0 || info.dims.y == 0 || info.dims.z == 0)
    throw Error("convert: source '" + info.description + "' has an empty volume");
  if (!isValidDims(info.dims))
    throw Error("convert: source '" + info.description + "' has dims " + std::to_string(info.dims.x) + "," +
                std::to_string(info.dims.y) + "," + std::to_string(info.dims.z) + "; a store holds at most " +
                std::to_string(kMaxDimsPerAxis) + " samples per axis");
  if (!isValidSpacing(info.spacing))
    throw Error("convert: source '" + info.description + "' has spacing " + formatSpacing(info.spacing) +
                "; expected " + validSpacingText());
  if (const std::string problem = convertOptionsProblem(options); !problem.empty()) throw Error(problem);
  const OctreeLayout layout = OctreeLayout::forVolume(info.dims, options.brickSize);

  StoreMetadata metadata;
  metadata.volume = info;
  // A mirroring orientation (a left-handed frame, as radiological NIfTI files have) is stored with its x axis
  // reversed, so that a store's axes are always a rotation: the renderers turn cameras, never mirror images.
  if (mirrors(info.axes)) {
    metadata.volume.axes[0] = -info.axes[0];
    metadata.xReversed = true;
    if (info.origin) metadata.volume.origin = originAtLastX(info);  // the store's sample 0 is the file's last
  }
  metadata.brickSize = options.brickSize;
  metadata.levels = layout.maxDepth + 1;
  metadata.storedType = storedTypeFor(info.type);
  metadata.discardBelow = options.discardBelow;
  metadata.zstdLevel = options.zstdLevel;
  metadata.creationTool = options.creationTool;
  metadata.payloadEncoding =
      metadata.storedType == SampleType::UInt16 ? PayloadEncoding::ZstdBytePlanes : PayloadEncoding::Zstd;
  double lo = 0.0, hi = 0.0;
  if (mapsOverValueRange(info.type)) {
    if (info.valueMin && info.valueMax && std::isfinite(*info.valueMin) && std::isfinite(*info.valueMax))
      std::tie(lo, hi) = std::pair(*info.valueMin, *info.valueMax);
    else
      std::tie(lo, hi) = scanValueRange(source, options);
  }
  metadata.mapping = valueMappingFor(info.type, lo, hi);
  // A float64 range can be too wide for a double (hi - lo overflows) or so narrow that its step underflows.
  const double inverseScale = 1.0 / metadata.mapping.scale;
  if (!(metadata.mapping.scale > 0.0) || !std::isfinite(metadata.mapping.scale) ||
      !std::isfinite(inverseScale))
    throw Error("convert: source '" + info.description + "' has " + std::string(sampleTypeName(info.type)) +
                " values in [" + formatNumber(lo) + ", " + formatNumber(hi) +
                "], a range that cannot be quantized to 16 bits in double precision");
  const double storedHigh = std::nearbyint(metadata.mapping.toStored(hi));

  StoreWriter writer(output);  // before the long work, so an unwritable output fails at once
  std::vector<StoreNodeEntry> entries(layout.insideNodeCount(), StoreNodeEntry{});
  const unsigned threads =
      options.workerThreads > 0 ? options.workerThreads : std::max(1u, std::thread::hardware_concurrency());
  const size_t maxQueued = 4 * threads;
  const size_t brickBytes = layout.storedBrickSamples() * bytesPerSample(metadata.storedType);
  ConvertStats stats;
  {
    CompressPool pool(writer, entries, options.zstdLevel, threads, maxQueued);
    if (metadata.storedType == SampleType::UInt8)
      streamSlices<uint8_t>(source, layout, metadata.mapping, storedHigh, options, entries, pool,
                            maxQueued * brickBytes, stats);
    else
      streamSlices<uint16_t>(source, layout, metadata.mapping, storedHigh, options, entries, pool,
                             maxQueued * brickBytes, stats);
    pool.finish();
  }
  stats.reorderBytes = maxQueued * ZSTD_compressBound(brickBytes);

  // The value range in data units: the range the mapping was made over for the types of mapsOverValueRange
  // (their quantization range; for uint32/int32 kept exactly, the root's range too), the root's range
  // otherwise.
  if (!mapsOverValueRange(info.type)) {
    lo = metadata.mapping.toData(entries[0].minValue);
    hi = metadata.mapping.toData(entries[0].maxValue);
  }
  metadata.volume.valueMin = lo;
  metadata.volume.valueMax = hi;
  stats.valueMin = lo;
  stats.valueMax = hi;
  writer.finish(metadata, entries);

  for (const StoreNodeEntry& e : entries) {
    ++stats.nodes;
    stats.emptyNodes += e.kind == uint8_t(NodeKind::Empty);
    stats.constantNodes += e.kind == uint8_t(NodeKind::Constant);
    stats.dataNodes += e.kind == uint8_t(NodeKind::Data);
    stats.payloadBytes += e.payloadBytes;
  }
  return stats;
}

}  // namespace ropecast
