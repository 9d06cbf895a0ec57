// FrameStats: what one rendered frame measured, written by `ropecast render --stats` as one JSON object per
// line: the loader's LoaderStats (WorkingSet::update) and the renderer's timing and index fields and the
// backend used. Plain data, owned by whoever renders the frame; any thread may read a copy.
#pragma once

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "core/render_params.h"
#include "loader/loader_stats.h"

namespace ropecast {

struct FrameStats : LoaderStats {
  uint64_t frame = 0;
  double frameMs = 0.0;  // wall time of the whole frame
  // False when the frame kept the last drawn image instead of drawing it (FrameRequest::keepConvergedImage,
  // keepImageWhileReading): no upload, index, tiles or rays, and raycast_ms 0.
  bool drawn = true;
  // GL timestamp queries around the ray-cast pass (see GpuTimer), without the occlusion queries' draws.
  double raycastMs = 0.0;
  bool raycastWallClock =
      false;                // raycast_ms is the wall-clock bound: the driver's timestamps were implausible
  double uploadMs = 0.0;    // handing this frame's bricks to the GPU pool (CPU side of the texture uploads)
  double indexMs = 0.0;     // building and uploading the rope index
  double stepVoxels = 0.0;  // the sample step of this frame (--step, scaled by --target-frame-ms)
  RenderBackend backend = RenderBackend::Fragment;  // the backend that drew it (never Auto: resolved)
  // The shader stage that cast its rays, Fragment or Compute: the fragment and compute backends their own,
  // multi-pass Fragment, brute force the entry point of --brute-stage (resolved as --backend auto is).
  RenderBackend stage = RenderBackend::Fragment;
  uint64_t workingSetBricks = 0;  // bricks of this frame's refined tree (the cut and the nodes above it)
  // Empty leaves wholly inside the isosurface, which cap the rays entering them through a cut without a
  // brick (LeafKind::Solid); 0 without caps.
  uint64_t leavesSolid = 0;
  // Passes that cast rays over (part of) the image: the single pass casts each screen tile in one pass (1
  // without occlusion queries); the multi-pass backend one per data (or solid) leaf drawn; brute force 1.
  uint64_t drawCalls = 0;
  // The GL draws and dispatches behind them: the fragment entry point's triangles of RaycastPass::kTileSize
  // pixels square, the compute entry point's dispatches; multi-pass: each block, its early-ray-termination
  // mark and the final resolve.
  uint64_t glDrawCalls = 0;
  // Fragments (or compute invocations) that cast rays: the single pass one per pixel; multi-pass the
  // fragments of its blocks and marks that passed the depth test (MultipassCounts::fragments).
  uint64_t fragments = 0;
  // Occlusion queries (Gobbetti et al. 2008, Sect. 6); zero with --occlusion off and in synchronous frames.
  uint64_t occlusionQueries = 0;   // issued this frame
  uint64_t occlusionAnswered = 0;  // answers collected this frame (issued in earlier frames)
  uint64_t nodesVisible = 0;       // non-empty leaves of the cut counted visible
  uint64_t nodesOccluded = 0;      // non-empty leaves of the cut marked occluded
  double occlusionMs = 0.0;        // CPU side: collecting, planning the tiles, issuing the queries
  // GPU side: drawing the query boxes after the first tile, timed as raycast_ms is and not part of it. On
  // llvmpipe the driver rasterizes while the queries are issued, so there this also holds that part of
  // occlusion_ms.
  double occlusionDrawMs = 0.0;
  uint64_t tiles = 0;                   // screen tiles cast (1 without queries)
  uint64_t occlusionLatencyFrames = 0;  // frames the last round of queries took to cover every leaf
  // The rays' feedback (Crassin et al. 2009); zero with --feedback off and in synchronous frames. The counts
  // are of the answer that arrived this frame.
  uint64_t feedbackRequests = 0;  // leaves the rays wanted finer
  // Leaves in which --visibility-threshold rays stopped (with occlusion queries): visible without a query.
  uint64_t feedbackHits = 0;
  uint64_t feedbackDropped = 0;        // entries past the lists' capacity (they come back in a later frame)
  uint64_t bricksUsed = 0;             // leaves the rays sampled
  double feedbackMs = 0.0;             // CPU side: reading the answers back and mapping them to nodes
  uint64_t feedbackLatencyFrames = 0;  // frames between the latest answer's frame and this one
};

inline nlohmann::json toJson(const FrameStats& s) {
  return nlohmann::json{{"frame", s.frame},
                        {"frame_ms", s.frameMs},
                        {"drawn", s.drawn},
                        {"raycast_ms", s.raycastMs},
                        {"raycast_timer", s.raycastWallClock ? "wall" : "gpu"},
                        {"upload_ms", s.uploadMs},
                        {"index_ms", s.indexMs},
                        {"step_voxels", s.stepVoxels},
                        {"backend", renderBackendName(s.backend)},
                        {"stage", renderBackendName(s.stage)},
                        {"refine_ms", s.refineMs},
                        {"leaves", s.leaves},
                        {"bricks_resident", s.bricksResident},
                        {"working_set_bricks", s.workingSetBricks},
                        {"bricks_uploaded", s.bricksUploaded},
                        {"bytes_uploaded", s.bytesUploaded},
                        {"requests_pending", s.requestsPending},
                        {"cache_hits", s.cacheHits},
                        {"cache_misses", s.cacheMisses},
                        {"cpu_cache_bytes", s.cpuCacheBytes},
                        {"bytes_read", s.bytesRead},
                        {"gpu_pool_used", s.gpuPoolUsedBytes},
                        {"used_evictions", s.usedBricksEvicted},
                        {"leaves_pool_full", s.leavesPoolFull},
                        {"leaves_solid", s.leavesSolid},
                        {"occlusion_queries", s.occlusionQueries},
                        {"occlusion_answered", s.occlusionAnswered},
                        {"nodes_visible", s.nodesVisible},
                        {"nodes_occluded", s.nodesOccluded},
                        {"occlusion_ms", s.occlusionMs},
                        {"occlusion_draw_ms", s.occlusionDrawMs},
                        {"tiles", s.tiles},
                        {"draw_calls", s.drawCalls},
                        {"gl_draw_calls", s.glDrawCalls},
                        {"fragments", s.fragments},
                        {"occlusion_latency_frames", s.occlusionLatencyFrames},
                        {"feedback_requests", s.feedbackRequests},
                        {"feedback_hits", s.feedbackHits},
                        {"feedback_dropped", s.feedbackDropped},
                        {"bricks_used", s.bricksUsed},
                        {"feedback_ms", s.feedbackMs},
                        {"feedback_latency_frames", s.feedbackLatencyFrames},
                        {"converged", s.converged}};
}

// One line of a --stats file (no trailing newline).
inline std::string toJsonLine(const FrameStats& s) {
  return toJson(s).dump();
}

}  // namespace ropecast
