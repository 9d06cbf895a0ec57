// FrameStats: what one rendered frame measured, written by `ropecast render --stats` as one JSON object per
// line. Plain data; the loader fills its fields in WorkingSet::update, the renderer fills the timing and
// index fields. Owned by whoever renders the frame; any thread may read a copy.
#pragma once

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

namespace ropecast {

struct FrameStats {
  uint64_t frame = 0;
  // Filled by the renderer.
  double frameMs = 0.0;    // wall time of the whole frame
  double raycastMs = 0.0;  // GL timestamp queries around the ray-cast pass (see GpuTimer)
  bool raycastWallClock =
      false;                // raycast_ms is the wall-clock bound: the driver's timestamps were implausible
  double uploadMs = 0.0;    // handing this frame's bricks to the GPU pool (CPU side of the texture uploads)
  double indexMs = 0.0;     // building and uploading the rope index
  double stepVoxels = 0.0;  // the sample step of this frame (--step, scaled by --target-frame-ms)
  // Filled by the loader (WorkingSet::update).
  double refineMs = 0.0;         // refinement, request submission and draining completed reads
  uint64_t leaves = 0;           // leaves of the cut (empty ones included)
  uint64_t bricksResident = 0;   // GPU pool slots holding a brick (in the cut or kept for reuse)
  uint64_t bricksUploaded = 0;   // uploads handed to the renderer this frame
  uint64_t bytesUploaded = 0;    // their bytes
  uint64_t requestsPending = 0;  // brick reads queued or in flight after this frame's requests
  uint64_t cacheHits = 0;        // bricks refinement needed that were in the CPU cache (not yet on the GPU)
  uint64_t cacheMisses = 0;      // bricks refinement needed that were in neither cache (a read was requested)
  uint64_t cpuCacheBytes = 0;    // decompressed bricks held by the CPU cache
  uint64_t gpuPoolUsedBytes = 0;  // bricksResident * brick bytes
  bool converged = false;         // nothing pending, nothing held back by the upload budget
};

inline nlohmann::json toJson(const FrameStats& s) {
  return nlohmann::json{{"frame", s.frame},
                        {"frame_ms", s.frameMs},
                        {"raycast_ms", s.raycastMs},
                        {"raycast_timer", s.raycastWallClock ? "wall" : "gpu"},
                        {"upload_ms", s.uploadMs},
                        {"index_ms", s.indexMs},
                        {"step_voxels", s.stepVoxels},
                        {"refine_ms", s.refineMs},
                        {"leaves", s.leaves},
                        {"bricks_resident", s.bricksResident},
                        {"bricks_uploaded", s.bricksUploaded},
                        {"bytes_uploaded", s.bytesUploaded},
                        {"requests_pending", s.requestsPending},
                        {"cache_hits", s.cacheHits},
                        {"cache_misses", s.cacheMisses},
                        {"cpu_cache_bytes", s.cpuCacheBytes},
                        {"gpu_pool_used", s.gpuPoolUsedBytes},
                        {"converged", s.converged}};
}

// One line of a --stats file (no trailing newline).
inline std::string toJsonLine(const FrameStats& s) {
  return toJson(s).dump();
}

}  // namespace ropecast
