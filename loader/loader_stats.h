// LoaderStats: what the loader did for one frame (WorkingSet::update), the loader's part of a frame's
// statistics (render/frame_stats.h adds the renderer's). Plain data; any thread may read a copy.
#pragma once

#include <cstdint>

namespace ropecast {

struct LoaderStats {
  double refineMs = 0.0;         // refinement, request submission and draining completed reads
  uint64_t leaves = 0;           // leaves of the cut (empty ones included)
  uint64_t bricksResident = 0;   // GPU pool slots holding a brick (in the cut or kept for reuse)
  uint64_t bricksUploaded = 0;   // uploads handed to the renderer this frame
  uint64_t bytesUploaded = 0;    // their bytes
  uint64_t requestsPending = 0;  // brick reads queued or in flight after this frame's requests
  uint64_t cacheHits = 0;        // bricks refinement needed that were in the CPU cache (not yet on the GPU)
  uint64_t cacheMisses = 0;      // bricks refinement needed that were in neither cache (a read was requested)
  uint64_t cpuCacheBytes = 0;    // decompressed bricks held by the CPU cache
  // Bytes the I/O workers read from the brick source since the previous frame's update (taken into the CPU
  // cache by this one): compressed payloads for a store, decompressed bricks for a procedural source
  // (BrickSource::compressedBytes).
  uint64_t bytesRead = 0;
  uint64_t gpuPoolUsedBytes = 0;  // bricksResident * brick bytes
  // GPU pool slots reused this frame whose brick the rays used in the latest answered frame
  // (FrameInput::usedNodes): 0 while the used bricks and the cut fit the pool together.
  uint64_t usedBricksEvicted = 0;
  // Leaves of the cut left coarser than the view asks because the GPU pool had no room for their children
  // (LeafReason::PoolFull): while above 0, more --gpu-budget would show more detail.
  uint64_t leavesPoolFull = 0;
  bool converged = false;  // nothing pending, nothing held back by the upload budget
};

}  // namespace ropecast
