#include "loader/working_set.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstring>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>

#include "core/elapsed.h"
#include "core/error.h"

namespace ropecast {

namespace {

std::string describe(const NodeKey& k) {
  return "node (depth " + std::to_string(k.depth) + ", " + std::to_string(k.coord.x) + "," +
         std::to_string(k.coord.y) + "," + std::to_string(k.coord.z) + ")";
}

}  // namespace

SharedBrick makeConstantBrick(const BrickSourceInfo& info, uint16_t storedValue) {
  const uint64_t samples = info.layout.storedBrickSamples();
  auto brick = std::make_shared<BrickBytes>(samples * bytesPerSample(info.storedType));
  if (info.storedType == SampleType::UInt8) {
    std::memset(brick->data(), int(storedValue & 0xFF), brick->size());
  } else {
    const std::byte lo{uint8_t(storedValue & 0xFF)}, hi{uint8_t(storedValue >> 8)};  // little-endian
    for (uint64_t i = 0; i < samples; ++i) {
      (*brick)[2 * i] = lo;
      (*brick)[2 * i + 1] = hi;
    }
  }
  return brick;
}

// The data path as the refiner sees it during one update(): GPU slots, CPU cache, requests, upload budget.
class WorkingSet::Residency final : public BrickResidency {
 public:
  Residency(WorkingSet& ws, uint64_t uploadBudgetBytes, size_t poolFullReadAhead)
      : ws_(ws),
        uploadBudgetBytes_(uploadBudgetBytes),
        poolFullReadAhead_(poolFullReadAhead),
        keepRoom_(ws.cache_.budgetBytes() / ws.brickBytes_ - ws.maxRequests_) {}  // requests: half the cache

  Outcome acquire(std::span<const NodeKey> keys, double priority, std::span<uint32_t> slotsOut) override {
    SlotTable& slots = ws_.slots_;
    if (keys.size() + reservedSlots_ > slots.availableCount()) return Outcome::PoolFull;

    // A node's children, or the root: each looked up once.
    std::array<std::optional<uint32_t>, 8> resident;
    if (keys.size() > resident.size()) throw Error("WorkingSet: internal error, more than 8 keys at once");
    bool missing = false;
    uint64_t uploadCount = 0;
    for (size_t i = 0; i < keys.size(); ++i) {
      const NodeKey& k = keys[i];
      resident[i] = slots.find(k);
      if (resident[i]) continue;
      ++uploadCount;
      if (ws_.cache_.contains(k)) {
        ++stats.cacheHits;
      } else if (ws_.source_.node(k).kind != NodeKind::Constant) {
        ++stats.cacheMisses;
        requests.push_back({k, priority});
        missing = true;
      }
    }
    if (missing) {
      holdForLater(keys, /*uploadWithinBudget=*/false);
      keepInCache(keys);
      return Outcome::NotInCore;
    }
    if (uploadCount * ws_.brickBytes_ > uploadBudgetBytes_ - stats.bytesUploaded) {
      holdForLater(keys, /*uploadWithinBudget=*/true);
      keepInCache(keys);
      return Outcome::UploadBudget;
    }

    // Pin the resident children first so that acquiring slots for the others cannot evict them.
    for (size_t i = 0; i < keys.size(); ++i) {
      if (resident[i]) {
        slots.pin(*resident[i]);
        slotsOut[i] = *resident[i];
      }
    }
    for (size_t i = 0; i < keys.size(); ++i) {
      if (resident[i]) continue;
      const NodeKey& k = keys[i];
      const std::optional<uint32_t> slot = slots.acquire(k);
      if (!slot) throw Error("WorkingSet: internal error, no GPU slot left for " + describe(k));
      slotsOut[i] = *slot;
      upload(*slot, k);
    }
    return Outcome::Ready;
  }

  size_t readAheadRoom() const override {
    const uint64_t poolRoom =
        ws_.slots_.availableCount() - std::min<uint64_t>(reservedSlots_, ws_.slots_.availableCount());
    const size_t requestRoom = ws_.maxRequests_ - std::min(requests.size(), ws_.maxRequests_);
    return size_t(std::min<uint64_t>(poolRoom, requestRoom));
  }

  size_t poolFullReadAheadRoom() const override {
    const size_t requestRoom = ws_.maxRequests_ - std::min(requests.size(), ws_.maxRequests_);
    return std::min(poolFullReadAhead_, requestRoom);
  }

  // Marks the kept bricks most recently used, the highest priority last: the reads the next frames take into
  // the cache evict other bricks first. Once, after the refinement.
  void touchKeptBricks() {
    for (auto it = kept_.rbegin(); it != kept_.rend(); ++it) ws_.cache_.get(*it);
  }

  std::vector<BrickRequest> requests;
  std::vector<BrickUpload> uploads;
  LoaderStats stats;

 private:
  // A node waits for its children (not all in core, or beyond the upload budget): those in the CPU cache and
  // not uploaded are kept there for the frames it waits, as long as the waiting nodes' children, read or
  // still to read, fit beside the reads the workers may land (at most maxRequests_) in priority order.
  // Without this, a cache of a few nodes' children churned by reads evicts a node's children before its last
  // ones arrive or are uploaded, and the refinement never ends.
  void keepInCache(std::span<const NodeKey> keys) {
    uint64_t wanted = 0;
    for (const NodeKey& k : keys) wanted += !ws_.slots_.find(k);  // uploaded ones have their slot now
    if (keptCount_ + wanted > keepRoom_) return;
    keptCount_ += wanted;
    for (const NodeKey& k : keys)
      if (!ws_.slots_.find(k) && ws_.cache_.contains(k)) kept_.push_back(k);
  }

  // The children cannot all be had this frame (not in core, or beyond the upload budget); the parent refines
  // in a later frame. For the rest of this frame their slots stay pinned and the missing ones reserved, so
  // that lower-priority nodes neither take (and evict) them nor request bricks the pool will have no room
  // for: the pool goes to nodes in priority order, as when nothing waits. With uploadWithinBudget, those in
  // core are uploaded now as far as the budget allows (without this, a budget under 8 bricks could never
  // refine).
  void holdForLater(std::span<const NodeKey> keys, bool uploadWithinBudget) {
    SlotTable& slots = ws_.slots_;
    // Pin the resident ones first, so that acquiring slots for the others cannot evict them.
    std::vector<uint8_t> resident(keys.size(), 0);
    for (size_t i = 0; i < keys.size(); ++i) {
      if (const auto slot = slots.find(keys[i])) {
        slots.pin(*slot);
        resident[i] = 1;
      }
    }
    for (size_t i = 0; i < keys.size(); ++i) {
      if (resident[i]) continue;
      const NodeKey& k = keys[i];
      if (!uploadWithinBudget || ws_.brickBytes_ > uploadBudgetBytes_ - stats.bytesUploaded) {
        ++reservedSlots_;
        continue;
      }
      const std::optional<uint32_t> slot = slots.acquire(k);
      if (!slot) {
        ++reservedSlots_;
        continue;
      }
      upload(*slot, k);
    }
  }

  void upload(uint32_t slot, const NodeKey& k) {
    SharedBrick brick = ws_.cache_.get(k);
    if (!brick) {
      const NodeInfo info = ws_.source_.node(k);
      if (info.kind != NodeKind::Constant) {
        throw Error("WorkingSet: internal error, the brick of " + describe(k) +
                    " left the CPU cache before upload");
      }
      brick = makeConstantBrick(ws_.source_.info(), info.minValue);
    }
    uploads.push_back({slot, k, std::move(brick)});
    ++stats.bricksUploaded;
    stats.bytesUploaded += ws_.brickBytes_;
  }

  WorkingSet& ws_;
  uint64_t uploadBudgetBytes_;  // this frame's: config and FrameInput, at least one brick
  size_t poolFullReadAhead_;    // the most bricks read below PoolFull leaves this frame
  uint64_t reservedSlots_ = 0;  // children held back by the upload budget that have no slot yet
  uint64_t keepRoom_;           // CPU cache bricks beside the reads the workers may land
  uint64_t keptCount_ = 0;      // kept bricks, and those still to read for the same nodes
  std::vector<NodeKey> kept_;   // in priority order
};

// The data path of a refinement that only asks for reads (WorkingSet::prefetch): no slot is taken, pinned or
// uploaded to. The slots each node would take are counted instead, so that the requests stop where the GPU
// pool would have no room, as update()'s do.
class WorkingSet::ReadPlan final : public BrickResidency {
 public:
  explicit ReadPlan(const WorkingSet& ws) : ws_(ws) {}

  Outcome acquire(std::span<const NodeKey> keys, double priority, std::span<uint32_t> slotsOut) override {
    if (keys.size() > poolRoom()) return Outcome::PoolFull;
    bool missing = false;
    for (const NodeKey& k : keys) {
      if (ws_.slots_.find(k) || ws_.cache_.contains(k) || ws_.source_.node(k).kind == NodeKind::Constant)
        continue;
      requests.push_back({k, priority});
      missing = true;
    }
    taken_ += keys.size();  // in core or waited for, these nodes take their slots
    if (missing) return Outcome::NotInCore;
    std::fill(slotsOut.begin(), slotsOut.end(), 0u);  // the plan is not drawn: no slot is real
    return Outcome::Ready;
  }

  size_t readAheadRoom() const override {
    const size_t requestRoom = ws_.maxRequests_ - std::min(requests.size(), ws_.maxRequests_);
    return size_t(std::min<uint64_t>(poolRoom(), requestRoom));
  }

  std::vector<BrickRequest> requests;

 private:
  uint64_t poolRoom() const {
    const uint64_t available = ws_.slots_.availableCount();
    return available - std::min(taken_, available);
  }

  const WorkingSet& ws_;
  uint64_t taken_ = 0;
};

namespace {

// The budgets' checks, before the members they size are made: the messages name the options and the least
// that works for this source.
const WorkingSetConfig& checkedBudgets(const WorkingSetConfig& config, uint64_t brickBytes) {
  if (config.cpuCacheBytes < kMinCpuCacheBricks * brickBytes) {
    throw UsageError("--cpu-cache " + std::to_string(config.cpuCacheBytes) + " bytes is below " +
                     std::to_string(kMinCpuCacheBricks) + " bricks of " + std::to_string(brickBytes) +
                     " bytes (" + std::to_string(kMinCpuCacheBricks * brickBytes) +
                     " bytes: the children of a few nodes must fit at once)");
  }
  if (config.uploadBudgetBytes < brickBytes) {
    throw UsageError("--upload-budget " + std::to_string(config.uploadBudgetBytes) +
                     " bytes cannot carry one brick of " + std::to_string(brickBytes) + " bytes");
  }
  return config;
}

}  // namespace

WorkingSet::WorkingSet(const BrickSource& source, const WorkingSetConfig& config)
    : source_(source),
      config_(checkedBudgets(config, source.brickBytes())),
      brickBytes_(source.brickBytes()),
      cache_(config.cpuCacheBytes, source.brickBytes()),
      slots_(config.gpuSlots) {
  // Ask for no more than half the CPU cache holds: more would evict each other before the refinement (which
  // needs all children of a node at once) could use them. The workers may read all of it without waiting for
  // a frame to take what they read.
  maxRequests_ = std::max<uint64_t>(cache_.budgetBytes() / brickBytes_ / 2, 1);
  poolFullReadAhead_ =
      size_t(std::min<uint64_t>(std::max<uint64_t>(kMinPoolFullReadAhead, config.gpuSlots / 32),
                                cache_.budgetBytes() / brickBytes_ / 8));
  if (poolFullReadAhead_ < kMinPoolFullReadAhead)
    poolFullReadAhead_ = 0;  // part of a node's children: no use
  io_ = std::make_unique<IoQueue>(source, config.ioThreads, maxRequests_);
}

WorkingSet::~WorkingSet() = default;

void WorkingSet::takeLoadedBricks() {
  std::string firstError;
  for (LoadedBrick& b : io_->takeLoaded()) {
    bytesReadSinceUpdate_ += b.bytesRead;
    if (b.brick) {
      cache_.put(b.key, std::move(b.brick));
      ++bricksTaken_;
    } else if (firstError.empty()) {
      firstError = "WorkingSet: reading the brick of " + describe(b.key) + " failed: " + b.error;
    }
  }
  if (!firstError.empty()) throw Error(firstError);
}

void WorkingSet::askForReads(std::vector<BrickRequest> requests, const RefineResult& refined) {
  // The bricks the refinement waits for by priority, then those read ahead in their order; the queue reads
  // them in this order (priority by rank).
  std::stable_sort(requests.begin(), requests.end(),
                   [](const BrickRequest& a, const BrickRequest& b) { return a.priority > b.priority; });
  for (const NodeKey& k : refined.readAhead) {
    if (!slots_.find(k) && !cache_.contains(k)) requests.push_back({k, 0.0});
  }
  for (const NodeKey& k : refined.poolFullReadAhead) {
    if (!slots_.find(k) && !cache_.contains(k)) requests.push_back({k, 0.0});
  }
  if (requests.size() > maxRequests_) requests.resize(maxRequests_);
  for (size_t i = 0; i < requests.size(); ++i) requests[i].priority = double(requests.size() - i);
  io_->replaceRequests(std::move(requests));
}

void WorkingSet::prefetch(const FrameInput& input) {
  takeLoadedBricks();
  ReadPlan plan(*this);
  const RefineResult refined = refine(source_, input.view, input.isEmpty, plan, input.hints);
  askForReads(std::move(plan.requests), refined);
}

WorkingSetFrame WorkingSet::update(const FrameInput& input) {
  return update(input, std::min(config_.uploadBudgetBytes, input.uploadBudgetBytes), /*progressive=*/true);
}

WorkingSetFrame WorkingSet::update(const FrameInput& input, uint64_t uploadBudgetBytes, bool progressive) {
  const auto start = SteadyClock::now();
  takeLoadedBricks();

  for (const NodeKey& k : input.usedNodes) {
    if (const auto slot = slots_.find(k)) slots_.touch(*slot);
  }
  slots_.beginCut();
  hidden_.clear();
  hidden_.insert(input.hiddenNodes.begin(), input.hiddenNodes.end());
  for (const NodeKey& k : input.hiddenNodes) {
    if (k.depth == 0 || !hidden_.contains(k.parent())) continue;
    if (const auto slot = slots_.find(k)) slots_.demote(*slot);
  }
  const uint64_t usedEvictionsBefore = slots_.usedEvictions();
  // Only hints free pool slots on a still view, and only progressive frames come back for what was read.
  Residency residency(*this, std::max(uploadBudgetBytes, brickBytes_),
                      progressive && input.hints ? poolFullReadAhead_ : 0);
  // A node whose children the rays asked for and whose uploads the budget spreads over frames keeps the rank
  // of a request until they are all up, though the rays ask for something else meanwhile (a nearer node
  // that its uploads displaced): else each takes the other's slots in turn and a still view never settles.
  NodeHints hints = input.hints;
  if (hints && !uploadingForRays_.empty()) {
    hints = [&](const NodeKey& k) {
      const NodeHint h = input.hints(k);
      return h == NodeHint::None && uploadingForRays_.contains(k) ? NodeHint::Requested : h;
    };
  }
  RefineResult refined = refine(source_, input.view, input.isEmpty, residency, hints);
  residency.touchKeptBricks();
  std::unordered_set<NodeKey, NodeKeyHash> uploading;  // by this frame's hints, kept ranks included
  for (const PlannedLeaf& l : refined.leaves)
    if (l.reason == LeafReason::UploadBudget && hints && hints(l.key) == NodeHint::Requested)
      uploading.insert(l.key);
  uploadingForRays_ = std::move(uploading);
  askForReads(std::move(residency.requests), refined);

  WorkingSetFrame out;
  out.leaves = std::move(refined.leaves);
  out.uploads = std::move(residency.uploads);
  out.converged = refined.complete;
  LoaderStats& s = out.stats;
  s = residency.stats;
  ++frame_;
  s.leaves = out.leaves.size();
  s.leavesPoolFull = uint64_t(std::count_if(out.leaves.begin(), out.leaves.end(), [](const PlannedLeaf& l) {
    return l.reason == LeafReason::PoolFull;
  }));
  s.bricksResident = slots_.occupiedCount();
  s.gpuPoolUsedBytes = uint64_t(slots_.occupiedCount()) * brickBytes_;
  s.usedBricksEvicted = slots_.usedEvictions() - usedEvictionsBefore;
  s.cpuCacheBytes = cache_.bytes();
  s.bytesRead = std::exchange(bytesReadSinceUpdate_, 0);
  s.requestsPending = io_->pendingCount();
  s.converged = refined.complete;
  s.refineMs = millisecondsSince(start);
  return out;
}

WorkingSetFrame WorkingSet::updateUntilConverged(const FrameInput& input, const LoadProgressFn& progress,
                                                 uint32_t maxFrames) {
  std::vector<BrickUpload> merged;
  std::unordered_map<uint32_t, size_t> indexOfSlot;
  double refineMs = 0.0;
  uint64_t usedBricksEvicted = 0, bytesRead = 0;
  const uint64_t takenBefore = bricksTaken_;
  const auto report = [&] {
    if (progress)
      progress({bricksTaken_ - takenBefore, io_->pendingCount(), bytesRead + bytesReadSinceUpdate_});
  };
  WorkingSetFrame frame;
  for (uint32_t i = 0; i < std::max(maxFrames, 1u); ++i) {
    // No upload budget: it paces the uploads of progressive frames, and these passes make one frame whose
    // uploads are merged anyway.
    frame = update(input, std::numeric_limits<uint64_t>::max(), /*progressive=*/false);
    refineMs += frame.stats.refineMs;
    usedBricksEvicted += frame.stats.usedBricksEvicted;
    bytesRead += frame.stats.bytesRead;
    for (BrickUpload& u : frame.uploads) {
      const auto [it, inserted] = indexOfSlot.emplace(u.slot, merged.size());
      if (inserted)
        merged.push_back(std::move(u));
      else
        merged[it->second] = std::move(u);  // the slot was reused: only its last brick matters
    }
    report();
    if (frame.converged) break;
    // Wait for all the reads this frame asked for (they fit in the CPU cache: requests are capped), taking
    // them into the cache as they come, so that each refinement pass gets a whole wave of bricks. An
    // upload-budget stop needs no wait, just the next pass.
    while (io_->pendingCount() > 0) {
      io_->waitForLoaded(std::chrono::milliseconds(1000));
      takeLoadedBricks();
      report();
    }
  }
  frame.uploads = std::move(merged);
  frame.stats.bricksUploaded = frame.uploads.size();
  frame.stats.bytesUploaded = frame.uploads.size() * brickBytes_;
  frame.stats.refineMs = refineMs;
  frame.stats.usedBricksEvicted = usedBricksEvicted;
  frame.stats.bytesRead = bytesRead;
  return frame;
}

}  // namespace ropecast
