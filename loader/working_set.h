// WorkingSet: the per-frame loader (Gobbetti et al. 2008, Sect. 4 and 7). Each update() drains the bricks the
// I/O workers read into the CPU cache, refines the cut for the frame's camera with what is in core, assigns
// GPU pool slots (LRU, occluded ones first, never one of the cut being built), asks the I/O workers for the
// bricks the refinement lacked and for those the next refinements will lack (read-ahead, and with a full pool
// in progressive frames with hints, below the leaves it had no room for; dropping requests no longer wanted)
// and returns a plain plan: the cut with its slots, and the uploads to do now within the upload budget. A
// frame always renders what is present: a node whose children are not all ready stays a leaf at its coarser
// level, and update() never waits for the disk; nor do the I/O workers wait for frames (up to half the CPU
// cache is read without being taken).
// updateUntilConverged() is the synchronous mode (for `render` without progression, and tests): the same
// code, repeated until the cut is complete.
//
// The loader never touches GL: the renderer uploads `uploads` into the pool slots, then builds the index over
// `leaves`. Owned by the render thread, which alone calls it; the I/O workers are internal. The BrickSource
// must outlive the WorkingSet.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <unordered_set>
#include <vector>

#include "loader/brick_cache.h"
#include "loader/io_queue.h"
#include "loader/loader_stats.h"
#include "loader/refiner.h"
#include "loader/slot_table.h"
#include "store/brick_source.h"

namespace ropecast {

// The smallest CPU cache a WorkingSet accepts, in bricks: refinement needs all 8 children of a node in core.
inline constexpr uint64_t kMinCpuCacheBricks = 16;

struct WorkingSetConfig {
  uint64_t cpuCacheBytes = uint64_t(1) << 30;  // --cpu-cache: decompressed bricks kept in system memory
  uint32_t gpuSlots = 0;                       // bricks the GPU pool holds (from --gpu-budget); required
  uint64_t uploadBudgetBytes = std::numeric_limits<uint64_t>::max();  // --upload-budget, per frame
  uint32_t ioThreads = 2;
};

struct FrameInput {
  RefineView view;
  EmptinessPredicate isEmpty;  // null: only NodeKind::Empty/Outside nodes are empty
  NodeHints hints;             // null: no hints (refiner.h); called on the render thread during update()
  // Nodes whose bricks the rays used in the latest answered frame (the feedback readback); empty when
  // unknown. Their GPU slots become the most recently used before refinement, so the pool evicts least
  // recently used bricks, not least recently resident ones (Crassin et al. 2009).
  std::vector<NodeKey> usedNodes;
  // Nodes hidden in the latest answered occlusion queries (those hinted Occluded); empty when unknown. The
  // GPU slots of those below a hidden node are reused first, right after the free ones (Gobbetti et al. 2008,
  // Sect. 6: bricks of nodes that stay occluded are dropped first when the pool is full): the refinement
  // stops at that node or above, so they are not in the tree being built. Kept in their place: a node whose
  // parent is not hidden (an occluded leaf of a visible node is in the cut), a node of usedNodes (use wins),
  // and a node of the last frame's tree (SlotTable::demote).
  std::vector<NodeKey> hiddenNodes;
  // This frame's upload limit on top of WorkingSetConfig::uploadBudgetBytes (the smaller one applies, never
  // less than one brick): the renderer's time budget (render/upload_pacer.h) arrives here as bytes.
  uint64_t uploadBudgetBytes = std::numeric_limits<uint64_t>::max();
};

struct BrickUpload {
  uint32_t slot = 0;
  NodeKey key;
  SharedBrick brick;  // storedBrickEdge()^3 samples of the stored type, kept alive by this pointer
};

// How far a synchronous load (WorkingSet::updateUntilConverged) has come, for a progress display: the bricks
// read so far and the reads outstanding. The total is not known ahead: each refinement pass asks for the next
// level's bricks once the level above is in, so readsPending grows in waves until the cut is complete.
struct LoadProgress {
  uint64_t bricksRead = 0;    // bricks the I/O workers delivered since the load began
  uint64_t readsPending = 0;  // brick reads queued or in flight
  uint64_t bytesRead = 0;     // what those reads took from the source (LoaderStats::bytesRead)
};
using LoadProgressFn = std::function<void(const LoadProgress&)>;

struct WorkingSetFrame {
  std::vector<PlannedLeaf> leaves;   // the cut, a tiling of the root cube
  std::vector<BrickUpload> uploads;  // to upload before rendering this frame (at most one per slot)
  LoaderStats stats;
  bool converged = false;  // same as stats.converged
};

class WorkingSet {
 public:
  // Throws ropecast::Error for budgets that cannot work: no GPU slot, a CPU cache or an upload budget smaller
  // than a brick.
  WorkingSet(const BrickSource& source, const WorkingSetConfig& config);
  ~WorkingSet();

  // One frame, never waiting for I/O. Throws ropecast::Error when a brick read failed (naming the node).
  WorkingSetFrame update(const FrameInput& input);

  // Repeats update(), waiting for the reads it asked for, until the cut is complete or maxFrames updates were
  // made, without an upload budget (one frame). The uploads of all those updates are merged (the last one per
  // slot); the stats are the last update's, with the counts of work done (uploads, refine time, evictions,
  // bytes read) summed over all of them. `progress`, if set, hears how far the load has come after each
  // update and each wave of reads taken (on the calling thread).
  WorkingSetFrame updateUntilConverged(const FrameInput& input, const LoadProgressFn& progress = {},
                                       uint32_t maxFrames = 100000);

  // Asks the I/O workers for the bricks update() with this input would ask for now, its read-ahead included,
  // without planning a frame: no GPU slot is taken, no upload planned, no frame counted. For a renderer
  // about to spend time before its first frame (making its GPU pool, compiling its programs): the reads need
  // neither, so they need not wait for them. The next update() takes what arrived and asks again.
  void prefetch(const FrameInput& input);

  // Blocks until no read is pending, or the read bricks fill what the workers may hold, or the timeout passes
  // (IoQueue::waitUntilIdle); update() takes what arrived. Between frames only: update() itself never waits.
  bool waitForReads(std::chrono::milliseconds timeout) { return io_->waitUntilIdle(timeout); }
  const BrickSourceInfo& info() const { return source_.info(); }
  uint64_t brickBytes() const { return brickBytes_; }
  const SlotTable& slots() const { return slots_; }
  const BrickCache& cache() const { return cache_; }
  const IoQueue& io() const { return *io_; }
  uint64_t frameCount() const { return frame_; }

 private:
  class Residency;
  class ReadPlan;
  void takeLoadedBricks();
  // Hands the I/O workers a refinement's requests (in priority order), then its read-ahead, at most
  // maxRequests_; the queue drops what it was reading that is no longer asked for.
  void askForReads(std::vector<BrickRequest> requests, const RefineResult& refined);
  // progressive: a frame of update(), not a pass of updateUntilConverged().
  WorkingSetFrame update(const FrameInput& input, uint64_t uploadBudgetBytes, bool progressive);

  const BrickSource& source_;
  WorkingSetConfig config_;
  uint64_t brickBytes_;
  // Bricks requested at once, and read without being taken: half the CPU cache. Memory for bricks is thus at
  // most 1.5x --cpu-cache while frames are slower than the reads.
  size_t maxRequests_ = 1;
  // Bricks read below the leaves a full GPU pool had no room for (RefineResult::poolFullReadAhead), in
  // progressive frames with hints: a thirty-second of the pool (what one round of answers may free is a small
  // share of it), at least one node's children, at most an eighth of the CPU cache (they must not evict each
  // other, nor the bricks of waiting nodes); none when that eighth cannot hold one node's children.
  static constexpr size_t kMinPoolFullReadAhead = 8;
  size_t poolFullReadAhead_ = 0;
  BrickCache cache_;
  SlotTable slots_;
  // FrameInput::hiddenNodes, during update().
  std::unordered_set<NodeKey, NodeKeyHash> hidden_;
  // Leaves of the last cut that the rays requested and that waited for upload budget (update()).
  std::unordered_set<NodeKey, NodeKeyHash> uploadingForRays_;
  uint64_t bytesReadSinceUpdate_ = 0;  // by the reads taken since the last update()'s stats
  uint64_t bricksTaken_ = 0;           // bricks read and taken into the CPU cache, ever
  std::unique_ptr<IoQueue> io_;        // last member: its workers stop before the rest goes away
  uint64_t frame_ = 0;
};

// The brick of a Constant node (every sample `storedValue`), made without I/O.
SharedBrick makeConstantBrick(const BrickSourceInfo& info, uint16_t storedValue);

}  // namespace ropecast
