// FrameRenderer: one frame of the out-of-core ray caster as named passes (docs/ARCHITECTURE.md):
//   hear back (occlusion answers) -> refine (loader WorkingSet) -> upload (BrickPool)
//   -> build index (RopeIndexBuilder, IndexTexture) -> plan tiles (VisibilityTracker)
//   -> plan recast (planRecast: on a still view, the pixels a changed cut needs cast again)
//   -> ray cast + queries (RaycastPass, OcclusionQueries) -> stats.
// A frame that would draw the last one's converged image again may end after refine, keeping that image
// (FrameRequest::keepConvergedImage).
// It owns the GL objects of a volume (pool, index texture, ray-cast pass) and the loader's WorkingSet, and is
// handed the BrickSource and the transfer function. The loader decides what to load; this class only carries
// its plan to the GPU. With RenderBackend::Multipass the ray cast is MultipassPass over the same cut and
// pool, one pass per data leaf, with no occlusion queries and no ray feedback (those passes are skipped).
//
// Render thread only, with the GlContext current. The BrickSource must outlive the FrameRenderer.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <unordered_set>
#include <vector>

#include <glm/vec3.hpp>

#include "core/camera.h"
#include "core/float_image.h"
#include "core/render_params.h"
#include "core/transfer_function.h"
#include "index/rope_index.h"
#include "loader/collapse_guard.h"
#include "loader/io_queue.h"
#include "loader/ray_feedback.h"
#include "loader/working_set.h"
#include "occlusion/visibility_tracker.h"
#include "render/feedback_buffer.h"
#include "render/frame_stats.h"
#include "render/multipass_pass.h"
#include "render/occlusion_queries.h"
#include "render/raycast_pass.h"
#include "render/recast_tracker.h"
#include "render/upload_pacer.h"
#include "store/brick_source.h"

namespace ropecast {

struct GlContextInfo;
struct BrickPoolUpload;
class BrickPool;
class GradientPool;
class IndexTexture;

struct FrameRendererConfig {
  uint64_t gpuBudgetBytes = 0;                 // --gpu-budget; 0 = defaultGpuBudgetBytes() of the context
  uint64_t cpuCacheBytes = uint64_t(1) << 30;  // --cpu-cache
  uint64_t uploadBudgetBytes = UINT64_MAX;     // --upload-budget, per frame
  // --upload-time-budget: milliseconds of uploads per asynchronous frame (0 = none), turned into bytes from
  // the throughput of earlier frames (render/upload_pacer.h); the smaller of the two budgets applies.
  double uploadTimeBudgetMs = 0.0;
  bool uploadThroughPbo = false;            // --upload-pbo (render/brick_pool.h)
  uint32_t ioThreads = defaultIoThreads();  // --io-threads
  // A GradientPool beside the brick pool, derived at every upload, for DVR requests with stored gradients
  // (RenderParams::gradients); it takes its share of the GPU budget. usesStoredGradients() says when.
  bool storedGradients = false;
  // --occlusion: occlusion queries between screen tiles steer refinement (Gobbetti et al. 2008, Sect. 6), in
  // asynchronous frames (a synchronous frame loads its whole view before any query could answer).
  bool occlusion = true;
  VisibilityConfig visibility;  // --query-budget, --visibility-threshold
  // --feedback: the rays report the leaves they used and the ones they wanted finer (Crassin et al. 2009),
  // read back frames later: requested nodes refine first, unused ones do not refine, used bricks stay in the
  // pool. Asynchronous frames only.
  bool feedback = true;
};

struct FrameRequest {
  // In the world, as the clip plane in params: render() turns both into the volume's own axes (its
  // orientation, store/volume_source.h cameraInVolume) before anything uses them.
  Camera camera;
  uint32_t width = 0, height = 0;
  RenderParams params;
  double voxelsPerPixel = 1.0;  // --voxels-per-pixel: refinement target
  const TfTable* tf = nullptr;  // required in DVR mode
  // Synchronous: refine until the working set is complete before rendering; otherwise one asynchronous
  // loader step that never waits for the disk.
  bool synchronous = false;
  // For a caller that reads the targets (readColor, readDepth) and stops once a frame is converged: an
  // asynchronous frame that would draw the last frame's image again (the same request, the same cut,
  // nothing uploaded), when that image is converged, keeps it instead of drawing it (FrameStats::drawn
  // false). Such a frame only learns that the answers about the cut left it as it is (with occlusion or
  // feedback, the answers about a cut come a frame after it is drawn). Never two such frames in a row: a
  // caller that goes on rendering the still view gets every other frame drawn (without queries or feedback,
  // the held answers renewed instead).
  bool keepConvergedImage = false;
  // For a caller that reads the targets only once the view is converged and waits for pending reads between
  // frames (render --converge): an asynchronous frame that uploads nothing while reads are pending, on the
  // last drawn frame's view, whose tree is the drawn one or a coarsening of it (nodes the answers collapsed,
  // which the rays did not see), keeps that image instead of drawing it (FrameStats::drawn false); at most a
  // few such frames in a row, so that the rays' answers are renewed before they lapse. The frame that
  // uploads what is read draws, and a converged cut is always one that was drawn. Independent of
  // keepConvergedImage's rule against two kept frames in a row, which is about kept converged frames.
  bool keepImageWhileReading = false;
  // For a caller that looks at a still view's frames as they converge (render --converge, the viewer): an
  // asynchronous frame on the last drawn view casts only the pixels whose rays meet a leaf that differs from
  // the drawn frame's (render/recast_plan.h) and keeps the others, which casting them would give again; the
  // rays' feedback about the pixels not cast is carried over from the answer about the drawn frame.
  // FrameStats::fragments counts the pixels cast. Not for frame-time measurements of a still view.
  bool recastChangesOnly = false;
};

class FrameRenderer {
 public:
  // With a synchronous `firstRequest`, the loader begins reading what that request's first refinement needs
  // (WorkingSet::prefetch) before the GPU pool is made: making a large pool takes a while (llvmpipe clears it
  // in memory), and the reads need neither the pool nor a frame. Asynchronous frames read nothing before the
  // first: with occlusion or feedback the answers of drawn frames steer the reads, and reads ahead of the
  // first answer load what it would have hidden (with a slow pool to make, the whole tree of a small store);
  // without them, frame times would no longer hold the reading that a progressive render waits for.
  FrameRenderer(const GlContextInfo& gl, const BrickSource& source, const FrameRendererConfig& config,
                const FrameRequest* firstRequest = nullptr);
  ~FrameRenderer();
  FrameRenderer(const FrameRenderer&) = delete;
  FrameRenderer& operator=(const FrameRenderer&) = delete;

  // Renders one frame; returns its stats (loader fields, index_ms, raycast_ms, frame_ms). The upload time
  // budget applies to asynchronous frames only (a synchronous frame loads everything at once). A frame may
  // keep the last one's image instead of drawing (FrameRequest::keepConvergedImage). `onLoadProgress` hears
  // a synchronous frame's load as it goes (WorkingSet::updateUntilConverged), for a progress display.
  FrameStats render(const FrameRequest& request, const LoadProgressFn& onLoadProgress = {});

  // Compiles the ray-cast program of the request's backend and mode (with feedback for an asynchronous
  // request when feedback is on) and draws it once, on a 1x1 image of an empty cut, with an occlusion query
  // when occlusion is on: drivers that compile at the first draw (llvmpipe's JIT, ~0.1-0.4 s a program) do
  // it here rather than in the first frames' times. Leaves the working set, the pool, the frame counter, the
  // feedback and the occlusion answers as they were.
  void prepare(const FrameRequest& request);

  // Between frames, never in one: blocks until no brick read is pending or `timeout` passes; returns whether
  // none is. For a loop with no one watching (render --converge) whose last frame uploaded nothing while
  // reads were pending: the next frame could only draw the same cut again.
  bool waitForReads(std::chrono::milliseconds timeout) { return workingSet_->waitForReads(timeout); }

  // The last frame's targets (row 0 at the top): RGBA and depth.
  FloatImage readColor() const { return lastMultipass_ ? multipass_.readColor() : raycast_.readColor(); }
  FloatImage readDepth() const { return lastMultipass_ ? multipass_.readDepth() : raycast_.readDepth(); }
  float readDepthAt(uint32_t x, uint32_t y) const {
    return lastMultipass_ ? multipass_.readDepthAt(x, y) : raycast_.readDepthAt(x, y);
  }

  // The last frame's cut, as handed to the index (tests and the CPU mirror).
  const Cut& lastCut() const { return cut_; }
  const WorkingSet& workingSet() const { return *workingSet_; }
  const BrickPool& pool() const { return *pool_; }
  // The occlusion side (null with FrameRendererConfig::occlusion off); tests substitute its result reader.
  OcclusionQueries* occlusionQueries() { return queries_.get(); }
  const VisibilityTracker* visibility() const { return visibility_.get(); }
  // The feedback side (null with FrameRendererConfig::feedback off); tests delay its fences.
  FeedbackBuffer* feedbackBuffer() { return feedback_.get(); }

 private:
  const GradientPool* gradientsFor(const RenderParams& params) const;
  // params.backend with Auto resolved for this GL renderer (render/backend_choice.h); Fragment, Compute or
  // Multipass.
  RenderBackend backendFor(const RenderParams& params) const;
  // Builds the rope index of `cut` into `index` and uploads it to the index texture.
  void uploadIndex(const Cut& cut, RopeIndex& index);
  RaycastFrame raycastFrame(const FrameRequest& request, uint32_t width, uint32_t height) const;
  // Hear back: the occlusion answers that arrived, into the tracker, and with `feedback` the leaves of the
  // last cut that the rays' latest answer found unused, as hidden; then the marks propagate to inner nodes.
  // After collectFeedback.
  void collectVisibility(bool feedback, FrameStats& stats);
  // Hear back: the rays' usage and requests of earlier frames, into RayFeedback.
  void collectFeedback(FrameStats& stats);
  // Plan recast: with FrameRequest::recastChangesOnly, which pixels of the last drawn view this frame's cut
  // needs cast again (nullopt: all of them); with `castFeedback`, the answer it carries over for the others.
  std::optional<RecastPlan> planRecastOf(const FrameRequest& request, const std::vector<PlannedLeaf>& leaves,
                                         bool castFeedback);
  // Plan tiles: the non-empty leaves of the cut, projected; which to query, and the tiles around them. A
  // leaf is projected and queried by the bounding box of its data parts (nodeDataParts under `isEmpty`); a
  // node collapsed on this view because its leaves were hidden is queried part by part. With `feedback`,
  // the leaves the rays' latest answer found unused are not queried but marked occluded: no ray reached
  // them, so no pixel of their box could pass the depth test, and the rays will say when one does. Without
  // `query` (a frame that draws the last one's converged image again) nothing is queried and the marks are
  // renewed (VisibilityTracker::renew): one tile.
  TileSchedule planTiles(const FrameRequest& request, const std::vector<PlannedLeaf>& leaves,
                         const EmptinessPredicate& isEmpty, bool feedback, bool query, FrameStats& stats);
  // What a frame's stats say whether it draws or keeps the last image: the loader's counts, the working set,
  // the frame number (counted here), the step and the backend.
  void finishStats(const FrameRequest& request, const WorkingSetFrame& plan, FrameStats& stats);
  // The visible and occluded leaves of the last planned cut and the query latency, into `stats`.
  void countVisibility(FrameStats& stats) const;
  // Whether the cut drawn since cutChangedFrame_ (and the view since viewChangedFrame_) is converged, given
  // whether the loader is done with it: with occlusion, a whole round of answers about it kept it; with
  // feedback, an answer about it did.
  bool cutConverged(bool loaderConverged, bool occlusion, bool feedback) const;
  // Whether this frame, planned as `plan` (its leaves' cutSetHash: `cutHash`), would draw the last frame's
  // image again and that image is converged: then it keeps that image (FrameRequest::keepConvergedImage) or,
  // drawn, queries nothing and casts no feedback.
  bool redrawsConvergedImage(const FrameRequest& request, const WorkingSetFrame& plan, uint64_t cutHash,
                             bool occlusion, bool feedback) const;
  // Whether `request` would draw the last drawn frame's view: the same camera, image, parameters and
  // emptiness (only the cut and its bricks may differ).
  bool drawsLastView(const FrameRequest& request) const;
  // Whether the frame keeps the last image: a converged one it would draw again, or, while reading, one
  // that shows nothing new (FrameRequest::keepConvergedImage, keepImageWhileReading).
  bool keepsLastImage(const FrameRequest& request, const WorkingSetFrame& plan, bool redraw) const;

  const BrickSource& source_;
  std::string glRenderer_;  // GL_RENDERER, for RenderBackend::Auto
  std::unique_ptr<BrickPool> pool_;
  std::unique_ptr<GradientPool> gradients_;  // config.storedGradients only
  std::vector<glm::u32vec3> uploadedOrigins_;
  std::unique_ptr<IndexTexture> indexTexture_;
  std::unique_ptr<WorkingSet> workingSet_;
  UploadPacer uploadPacer_;
  std::vector<BrickPoolUpload> uploadBatch_;
  RaycastPass raycast_;
  MultipassPass multipass_;
  bool lastMultipass_ = false;  // which pass drew the last frame
  RopeIndexBuilder indexBuilder_;
  RopeIndex index_;
  Cut cut_;
  uint64_t frame_ = 0;

  std::unique_ptr<OcclusionQueries> queries_;      // config.occlusion only
  std::unique_ptr<VisibilityTracker> visibility_;  // config.occlusion only
  std::vector<NodeKey> dataLeaves_;                // the non-empty leaves of the last asynchronous frame
  std::vector<float> leafMaxima_;                  // MIP: RaycastFrame::leafMaxima of the frame's cut
  std::vector<QueryBox> queryBoxes_;               // this frame's queries
  std::vector<NodeDataParts> dataParts_;           // this frame's queryable leaves' data parts, as planned
  uint64_t emptinessKey_ = 0;                      // what decided emptiness when the marks were made
  std::unordered_set<NodeKey, NodeKeyHash> lastInnerNodes_;  // of the last frame's tree
  CollapseGuard collapseGuard_;           // reset when the camera moves or the emptiness changes
  std::optional<FrameRequest> lastView_;  // the last asynchronous frame's request

  std::unique_ptr<FeedbackBuffer> feedback_;  // config.feedback only
  RayFeedback rayFeedback_;
  uint64_t currentCutHash_ = 0;
  // The last frame whose cut differed from the one before: every frame since has this cut, so an answer
  // about one of them is about it.
  uint64_t cutChangedFrame_ = 0;
  // The last asynchronous frame whose camera or image size differed from the frame before: answers about
  // an earlier view describe another image, so convergence waits for answers about this one.
  uint64_t viewChangedFrame_ = 0;
  // The last asynchronous frame whose rays sample otherwise than the frame before's (another step, mode or
  // voxels per pixel): where their rays stop moves, so answers about earlier frames describe another image.
  uint64_t samplingChangedFrame_ = 0;
  std::optional<FrameRequest> lastDrawn_;  // the request of the last frame drawn
  uint64_t lastDrawnEmptinessKey_ = 0;     // its transfer function's content too (emptinessKeyOf)
  bool keptConvergedImage_ = false;        // the last frame kept the converged image before it
  uint64_t framesKeptWhileReading_ = 0;    // frames in a row that kept the image while reading
  // The inner nodes of the last drawn frame's tree, once a later frame has begun (with
  // FrameRequest::keepImageWhileReading only).
  std::unordered_set<NodeKey, NodeKeyHash> drawnInnerNodes_;
  // The frame whose image the ray-cast pass's targets hold, and the rays' answer about it: what a frame
  // recasting only what changed needs.
  RecastTracker recast_;
};

// The refinement's emptiness test for a mode: iso: the node's stored range misses the isovalue; DVR: the
// transfer function gives no value of the range any opacity; MIP: nor any value up to the range's maximum;
// MinIP: nor any from the range's minimum up.
EmptinessPredicate emptinessFor(const RenderParams& params, const BrickSourceInfo& info, const TfTable* tf);

}  // namespace ropecast
