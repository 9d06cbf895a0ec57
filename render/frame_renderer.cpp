#include "render/frame_renderer.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <string_view>

#include "core/elapsed.h"
#include "core/error.h"
#include "index/rope_layout.h"
#include "render/backend_choice.h"
#include "render/brick_pool.h"
#include "render/gl_context.h"
#include "render/gradient_pool.h"
#include "render/index_texture.h"
#include "render/visibility_from_rays.h"

namespace ropecast {

namespace {
// The same camera and image size: the occlusion marks of the last frame describe this one.
bool sameView(const FrameRequest& a, const FrameRequest& b) {
  return a.camera == b.camera && a.width == b.width && a.height == b.height;
}

// What decides which nodes are empty or cut away (mode, isovalue, transfer function, crop box, clip plane)
// and where an isosurface's rays stop (caps), as a hash: occlusion marks made under another one describe
// another image (cutting an occluder away shows what it hid).
uint64_t emptinessKeyOf(const FrameRequest& request) {
  std::string_view tfBytes;
  if (usesTransferFunction(request.params.mode) && request.tf)
    tfBytes = {reinterpret_cast<const char*>(request.tf->entries().data()),
               request.tf->entries().size() * sizeof(glm::vec4)};
  uint64_t h = std::hash<std::string_view>{}(tfBytes);
  h = h * 0x9E3779B97F4A7C15ull ^ uint64_t(request.params.mode);
  if (request.params.mode == RenderMode::Iso) {
    h = h * 0x9E3779B97F4A7C15ull ^ std::hash<double>{}(request.params.isoValue);
    // Caps stop rays that the open surface lets by.
    h = h * 0x9E3779B97F4A7C15ull ^ uint64_t(request.params.isoCaps);
  }
  const ClipPlane& plane = request.params.clipPlane;
  for (const glm::dvec3& v : {request.params.crop.lo, request.params.crop.hi, plane.point, plane.normal})
    for (int axis = 0; axis < 3; ++axis) h = h * 0x9E3779B97F4A7C15ull ^ std::hash<double>{}(v[axis]);
  h = h * 0x9E3779B97F4A7C15ull ^ std::hash<double>{}(plane.slab);
  return h;
}

// While caps are drawn: whether an empty leaf is Solid, wholly inside the isosurface (its stored values all
// above isoStored) and inside the box the rays sample. A ray entering it through a cut is capped there
// without its brick.
bool isSolidLeaf(const PlannedLeaf& leaf, const BrickSource& source, double isoStored,
                 const WorldBox& sampled) {
  if (leaf.content != LeafContent::Empty || leaf.reason != LeafReason::Empty) return false;
  const NodeInfo node = source.node(leaf.key);
  if (!(node.kind == NodeKind::Data || node.kind == NodeKind::Constant) ||
      !(double(node.minValue) > isoStored))
    return false;
  const BrickSourceInfo& info = source.info();
  return hasVolume(intersection(nodeWorldBox(info.layout, info.volume.spacing, leaf.key), sampled));
}

// The index's cut of the planned leaves, in their order; `isSolid` (null: none) picks the Solid leaves.
Cut cutOf(const std::vector<PlannedLeaf>& leaves, const std::function<bool(const PlannedLeaf&)>& isSolid) {
  Cut cut;
  cut.leaves.reserve(leaves.size());
  for (const PlannedLeaf& leaf : leaves) {
    CutLeaf cutLeaf;
    cutLeaf.depth = leaf.key.depth;
    cutLeaf.coord = leaf.key.coord;
    cutLeaf.kind = leaf.content == LeafContent::Brick ? LeafKind::Data
                   : isSolid && isSolid(leaf)         ? LeafKind::Solid
                                                      : LeafKind::Empty;
    cutLeaf.brickSlot = leaf.content == LeafContent::Brick ? leaf.slot : 0;
    cut.leaves.push_back(cutLeaf);
  }
  return cut;
}

// The cut as a set of leaves and their content: the refiner's leaf order follows its heap, which hints
// reorder without changing the cut.
uint64_t cutSetHash(const std::vector<PlannedLeaf>& leaves) {
  uint64_t hash = leaves.size();
  for (const PlannedLeaf& leaf : leaves) {
    uint64_t h = NodeKeyHash{}(leaf.key) ^ (uint64_t(leaf.content) << 61);  // splitmix64's finalizer
    h = (h ^ (h >> 30)) * 0xBF58476D1CE4E5B9ull;
    h = (h ^ (h >> 27)) * 0x94D049BB133111EBull;
    hash += h ^ (h >> 31);
  }
  return hash;
}
}  // namespace

EmptinessPredicate emptinessFor(const RenderParams& params, const BrickSourceInfo& info, const TfTable* tf) {
  if (params.mode == RenderMode::Iso) {
    const double isoStored = info.mapping.toStored(params.isoValue);
    return [isoStored](uint16_t lo, uint16_t hi) { return double(hi) < isoStored || double(lo) > isoStored; };
  }
  if (!tf) throw Error("emptinessFor: DVR and MIP need a transfer function");
  if (params.mode == RenderMode::Mip) {
    // A ray's maximum m shows only where the function has opacity at m. A node whose values all lie below
    // every such value cannot raise a maximum into sight: skipped, the ray's maximum is either the same or,
    // like the node's, where the function is transparent. A node with values above it is not empty, even
    // where the function is transparent there: such a maximum hides smaller visible ones.
    return [tf](uint16_t, uint16_t hi) { return !tf->hasOpacity(0, hi); };
  }
  if (params.mode == RenderMode::MinIp) {
    // The same for the smallest value: a node whose values all lie above every value with opacity.
    const uint32_t top = uint32_t(storedMaxOf(info.storedType));
    return [tf, top](uint16_t lo, uint16_t) { return !tf->hasOpacity(lo, top); };
  }
  if (params.mode == RenderMode::Aip) {
    // Every value counts toward a mean: only zeros may be skipped (the rays count them by length alone).
    return [](uint16_t, uint16_t hi) { return hi == 0; };
  }
  return [tf](uint16_t lo, uint16_t hi) { return !tf->hasOpacity(lo, hi); };
}

namespace {

// The request as the volume's own axes see it: its camera and clip plane turned (store/volume_source.h).
// Everything past a renderer's entry works in those axes.
FrameRequest inVolume(const FrameRequest& world, const VolumeInfo& volume) {
  FrameRequest request = world;
  request.camera = cameraInVolume(world.camera, volume);
  request.params.clipPlane = clipPlaneInVolume(world.params.clipPlane, volume);
  return request;
}

// What the loader needs of a request before any hint: the view and the emptiness.
FrameInput viewInputOf(const FrameRequest& request, const BrickSourceInfo& info) {
  FrameInput input;
  input.view.camera = request.camera;
  input.view.viewportWidth = request.width;
  input.view.viewportHeight = request.height;
  input.view.voxelsPerPixel = request.voxelsPerPixel;
  input.view.sampled = sampledWorldBox(request.params, info.volume.dims, info.volume.spacing);
  input.view.clipPlane = request.params.clipPlane;
  input.view.slice = request.params.mode == RenderMode::Slice;
  input.isEmpty = emptinessFor(request.params, info, request.tf);
  return input;
}

}  // namespace

FrameRenderer::FrameRenderer(const GlContextInfo& gl, const BrickSource& source,
                             const FrameRendererConfig& config, const FrameRequest* firstRequest)
    : source_(source),
      glRenderer_(gl.renderer),
      uploadPacer_(config.uploadTimeBudgetMs, source.brickBytes()) {
  const BrickSourceInfo& info = source.info();
  BrickPoolConfig poolConfig;
  poolConfig.brickSize = info.layout.brickSize;
  poolConfig.storedType = info.storedType;
  poolConfig.budgetBytes = config.gpuBudgetBytes ? config.gpuBudgetBytes : defaultGpuBudgetBytes(gl);
  poolConfig.uploadThroughPbo = config.uploadThroughPbo;
  if (config.storedGradients) poolConfig.extraBytesPerTexel = GradientPool::kBytesPerTexel;
  poolConfig.maxSlots = info.layout.insideNodeCount();
  const BrickPoolGeometry poolGeometry =
      planBrickPool(poolConfig.brickSize, poolConfig.storedType, poolConfig.budgetBytes, gl.max3DTextureSize,
                    poolConfig.extraBytesPerTexel, poolConfig.maxSlots);

  WorkingSetConfig wsConfig;
  wsConfig.cpuCacheBytes = config.cpuCacheBytes;
  wsConfig.gpuSlots = poolGeometry.slotCount();
  wsConfig.uploadBudgetBytes = config.uploadBudgetBytes;
  wsConfig.ioThreads = config.ioThreads;
  workingSet_ = std::make_unique<WorkingSet>(source, wsConfig);
  if (firstRequest && firstRequest->synchronous)
    workingSet_->prefetch(viewInputOf(inVolume(*firstRequest, info.volume), info));

  pool_ = std::make_unique<BrickPool>(poolConfig, gl.max3DTextureSize);
  if (pool_->slotCount() != poolGeometry.slotCount())
    throw Error("FrameRenderer: internal error, the pool has other slots than planned");
  if (config.storedGradients) gradients_ = std::make_unique<GradientPool>(pool_->geometry().textureDims);
  indexTexture_ = std::make_unique<IndexTexture>(kRopeTexelComponents, gl.maxTextureBufferTexels);
  if (config.feedback) feedback_ = std::make_unique<FeedbackBuffer>();
  if (config.occlusion) {
    queries_ = std::make_unique<OcclusionQueries>();
    visibility_ = std::make_unique<VisibilityTracker>(config.visibility);
  }
}

FrameRenderer::~FrameRenderer() = default;

const GradientPool* FrameRenderer::gradientsFor(const RenderParams& params) const {
  if (!usesStoredGradients(params)) return nullptr;
  if (!gradients_)
    throw Error(
        "FrameRenderer: DVR with stored gradients, but the renderer was configured without them "
        "(FrameRendererConfig::storedGradients)");
  return gradients_.get();
}

RenderBackend FrameRenderer::backendFor(const RenderParams& params) const {
  const RenderBackend backend = resolveBackend(params.backend, glRenderer_);
  if (backend == RenderBackend::Brute)
    throw Error("FrameRenderer: the brute backend is BruteForcePass's (render/brute_force_pass.h)");
  return backend;
}

void FrameRenderer::uploadIndex(const Cut& cut, RopeIndex& index) {
  indexBuilder_.build(cut, index);
  indexTexture_->upload(std::span<const uint32_t>(reinterpret_cast<const uint32_t*>(index.texels.data()),
                                                  index.texels.size() * kRopeTexelComponents));
}

RaycastFrame FrameRenderer::raycastFrame(const FrameRequest& request, uint32_t width, uint32_t height) const {
  RaycastFrame frame;
  frame.pool = pool_.get();
  frame.index = indexTexture_.get();
  frame.camera = request.camera;
  frame.volume = VolumeGeometry::of(source_.info());
  frame.params = request.params;
  frame.params.backend = backendFor(request.params);
  frame.gradients = gradientsFor(request.params);
  frame.tf = request.tf;
  frame.width = width;
  frame.height = height;
  return frame;
}

void FrameRenderer::prepare(const FrameRequest& worldRequest) {
  const FrameRequest request = inVolume(worldRequest, source_.info().volume);
  if (backendFor(request.params) == RenderBackend::Multipass) {
    // One block of the root over pool slot 0, whatever it holds: the draw that makes the driver compile.
    multipass_.render(raycastFrame(request, 1, 1), {MultipassLeaf{}});
    multipass_.lastRaycastMs();
    return;
  }
  Cut empty;
  empty.leaves.push_back(CutLeaf{});  // the root, an empty leaf: rays traverse it and take no sample
  RopeIndex index;
  uploadIndex(empty, index);
  RaycastFrame frame = raycastFrame(request, 1, 1);
  // An asynchronous frame casts the variant with feedback and issues queries (their programs, and the
  // compute entry point's stop-depth copy): those draw here too, and what they would answer is dropped.
  const bool async = !request.synchronous;
  if (feedback_ && async) {
    feedback_->begin(1);
    frame.feedback = feedback_.get();
    frame.voxelsPerPixel = request.voxelsPerPixel;
  }
  TileSchedule schedule;
  std::vector<QueryBox> volumeBox;
  // Only with no query pending: dropPending() below forgets them all.
  const bool query = queries_ && async && queries_->pendingCount() == 0;
  const glm::dvec3 extent = source_.info().volume.worldMax();  // outlives the draw that reads it
  if (query) {
    volumeBox.push_back({NodeKey{}, {{WorldBox{glm::dvec3(0.0), extent}}, 1}});
    schedule.afterFirstTile = [&] {
      queries_->issue(volumeBox, request.camera, 1, 1, windowDepthRange(request.camera, extent), frame_);
    };
  }
  raycast_.render(frame, schedule);
  if (frame.feedback) feedback_->discard();
  raycast_.lastRaycastMs();  // waits for the draw
  if (query) queries_->dropPending();
  recast_.forget();  // the targets hold the 1x1 image
}

void FrameRenderer::collectVisibility(bool feedback, FrameStats& stats) {
  const auto start = SteadyClock::now();
  for (const QueryAnswer& a : queries_->collect()) {
    visibility_->answer(a.key, a.issuedFrame, a.samplesPassed);
    ++stats.occlusionAnswered;
  }
  // What the rays' latest answer says about the last cut's leaves (render/visibility_from_rays.h), marked
  // before the marks propagate, so that this frame's refinement hears it with the answers that arrived with
  // it (marked only when the tiles are planned, it would reach the refinement a frame after the cut it
  // changes was declared converged).
  if (feedback) markVisibilityFromRays(dataLeaves_, rayFeedback_, collapseGuard_, frame_, *visibility_);
  visibility_->propagate(dataLeaves_);
  stats.occlusionMs += millisecondsSince(start);
}

void FrameRenderer::collectFeedback(FrameStats& stats) {
  const auto start = SteadyClock::now();
  // Every readback that arrived; the latest one's nodes are what the hints say.
  while (std::optional<FeedbackReadback> readback = feedback_->poll()) {
    // A frame cast in part: the rays it did not cast answer as they did about the frame drawn before it.
    recast_.addCarried(*readback);
    if (!rayFeedback_.answer(readback->frame, readback->usedLeaves, readback->requestedLeaves,
                             readback->hitLeaves))
      continue;
    recast_.heard(*readback);
    stats.feedbackRequests = readback->requestedLeaves.size();
    stats.feedbackHits = readback->hitLeaves.size();
    stats.feedbackDropped = readback->usedDropped + readback->requestedDropped + readback->hitDropped;
    stats.bricksUsed = readback->usedLeaves.size();
  }
  if (rayFeedback_.answered()) stats.feedbackLatencyFrames = frame_ - rayFeedback_.answeredFrame();
  stats.feedbackMs += millisecondsSince(start);
}

void FrameRenderer::countVisibility(FrameStats& stats) const {
  const VisibilityCounts counts = visibility_->counts(frame_);
  stats.nodesVisible = counts.visible;
  stats.nodesOccluded = counts.occluded;
  stats.occlusionLatencyFrames = visibility_->lastRoundFrames();
}

TileSchedule FrameRenderer::planTiles(const FrameRequest& request, const std::vector<PlannedLeaf>& leaves,
                                      const EmptinessPredicate& isEmpty, bool feedback, bool query,
                                      FrameStats& stats) {
  const auto start = SteadyClock::now();
  const BrickSourceInfo& info = source_.info();
  const WorldBox sampled = sampledWorldBox(request.params, info.volume.dims, info.volume.spacing);
  std::vector<LeafToQuery> toQuery;
  dataLeaves_.clear();
  dataParts_.clear();
  // Hits spare a query only when they describe this image: while the camera moves, a query drawn now answers
  // about a newer view than the rays' last answer, and a leaf the move hides is caught a frame sooner; while
  // the step changes (--target-frame-ms), the rays stop elsewhere, and hits about another step kept a cut
  // that this one's answers changed after it was called converged.
  const bool hitsAboutThisImage =
      feedback && rayFeedback_.answered() &&
      rayFeedback_.answeredFrame() >= std::max(viewChangedFrame_, samplingChangedFrame_);
  for (const PlannedLeaf& leaf : leaves) {
    if (leaf.content != LeafContent::Brick) continue;
    dataLeaves_.push_back(leaf.key);  // marks propagate over all of them, queried or not
    if (feedback && rayFeedback_.hint(leaf.key, frame_) == NodeHint::Unused) {
      visibility_->markUnseen(leaf.key, frame_);  // again for the last cut's leaves (collectVisibility)
      continue;
    }
    if (!query) continue;
    if (hitsAboutThisImage && rayFeedback_.hitByRays(leaf.key, frame_) &&
        !collapseGuard_.collapsed(leaf.key)) {
      visibility_->markHit(leaf.key, rayFeedback_.answeredFrame());  // as for the unused leaves
      dataParts_.emplace_back();
      toQuery.push_back({leaf.key, {}, true});
      continue;
    }
    NodeDataParts& parts = dataParts_.emplace_back(nodeDataParts(source_, isEmpty, leaf.key, sampled));
    const WorldBox box = boundingBox(parts);
    // A node collapsed because its leaves were hidden is queried as they were, part by part; the others by
    // the parts' bounding box, which draws fewer fragments.
    if (!collapseGuard_.collapsed(leaf.key)) parts = {{box}, 1};
    toQuery.push_back({leaf.key, projectBox(box.lo, box.hi, request.camera, request.width, request.height)});
  }
  if (!query) {
    visibility_->renew(frame_);
    countVisibility(stats);
    queryBoxes_.clear();
    stats.occlusionMs += millisecondsSince(start);
    return {};
  }
  const FrameQueryPlan plan = visibility_->plan(frame_, request.width, request.height, toQuery);
  countVisibility(stats);

  queryBoxes_.clear();
  for (const uint32_t i : plan.queriedIndices) queryBoxes_.push_back({toQuery[i].key, dataParts_[i]});
  TileSchedule schedule;
  for (const ScreenRect& r : plan.tiles)
    if (!r.empty())
      schedule.tiles.push_back({uint32_t(r.x0), uint32_t(r.y0), uint32_t(r.width()), uint32_t(r.height())});
  stats.occlusionQueries = queryBoxes_.size();
  if (!queryBoxes_.empty()) {
    const DepthRange depth = windowDepthRange(request.camera, info.volume.worldMax());
    schedule.afterFirstTile = [this, &request, depth, &stats] {
      const auto issueStart = SteadyClock::now();
      queries_->issue(queryBoxes_, request.camera, request.width, request.height, depth, frame_);
      stats.occlusionMs += millisecondsSince(issueStart);
    };
  }
  stats.occlusionMs += millisecondsSince(start);
  return schedule;
}

std::optional<RecastPlan> FrameRenderer::planRecastOf(const FrameRequest& request,
                                                      const std::vector<PlannedLeaf>& leaves,
                                                      bool castFeedback) {
  if (!request.recastChangesOnly || !drawsLastView(request)) return std::nullopt;
  const BrickSourceInfo& info = source_.info();
  RecastInput view;
  view.camera = request.camera;
  view.width = request.width;
  view.height = request.height;
  view.layout = &info.layout;
  view.spacing = info.volume.spacing;
  return recast_.plan(view, leaves, frame_, castFeedback);
}

bool FrameRenderer::cutConverged(bool loaderConverged, bool occlusion, bool feedback) const {
  // Answers about another view (the camera moved, the window was resized) or another sampling (the step
  // --target-frame-ms sets) may have kept this cut: a node hidden there can be in sight here. They steer the
  // refinement, but only answers about this image and cut may say it is converged.
  const uint64_t since = std::max({cutChangedFrame_, viewChangedFrame_, samplingChangedFrame_});
  // With occlusion, the refinement kept the cut with a whole round of answers about it.
  if (occlusion && !visibility_->answeredSince(since)) return false;
  // With feedback, also an answer about this very cut: its hints are what kept the cut as it is.
  if (feedback && !(rayFeedback_.answered() && rayFeedback_.answeredFrame() >= since)) return false;
  return loaderConverged;
}

bool FrameRenderer::drawsLastView(const FrameRequest& request) const {
  if (request.synchronous || !lastDrawn_) return false;
  const FrameRequest& last = *lastDrawn_;
  return sameView(last, request) && last.params == request.params &&
         last.voxelsPerPixel == request.voxelsPerPixel && !last.synchronous &&
         lastDrawnEmptinessKey_ == emptinessKey_;
}

bool FrameRenderer::redrawsConvergedImage(const FrameRequest& request, const WorkingSetFrame& plan,
                                          uint64_t cutHash, bool occlusion, bool feedback) const {
  // The last frame's leaves, and nothing uploaded: every brick in the slot it had. With the last frame's cut,
  // cutChangedFrame_ still says since when it is drawn.
  return plan.uploads.empty() && drawsLastView(request) && cutHash == currentCutHash_ &&
         cutConverged(plan.stats.converged, occlusion, feedback);
}

bool FrameRenderer::keepsLastImage(const FrameRequest& request, const WorkingSetFrame& plan,
                                   bool redraw) const {
  if (redraw) return request.keepConvergedImage && !keptConvergedImage_;
  // Answers age by frames, kept ones too (RayFeedbackConfig::answerLifetimeFrames): a drawn frame now and
  // then answers again before the held answers lapse.
  constexpr uint64_t kMaxKeptInARow = RayFeedbackConfig{}.answerLifetimeFrames / 2;
  if (!request.keepImageWhileReading || !plan.uploads.empty() || plan.stats.requestsPending == 0 ||
      framesKeptWhileReading_ >= kMaxKeptInARow || !drawsLastView(request))
    return false;
  // The drawn tree or a coarsening of it (nodes the answers collapsed), whose image the rays have drawn but
  // for what they did not see: a node refined from bricks still in the pool needs no upload, and is drawn.
  return std::all_of(lastInnerNodes_.begin(), lastInnerNodes_.end(),
                     [this](const NodeKey& k) { return drawnInnerNodes_.contains(k); });
}

void FrameRenderer::finishStats(const FrameRequest& request, const WorkingSetFrame& plan, FrameStats& stats) {
  static_cast<LoaderStats&>(stats) = plan.stats;
  stats.workingSetBricks = workingSet_->slots().pinnedCount();
  stats.frame = frame_++;
  stats.stepVoxels = request.params.stepVoxels;
  stats.backend = backendFor(request.params);
  // The multi-pass backend draws its blocks with fragment shaders.
  stats.stage = stats.backend == RenderBackend::Compute ? RenderBackend::Compute : RenderBackend::Fragment;
}

FrameStats FrameRenderer::render(const FrameRequest& worldRequest, const LoadProgressFn& onLoadProgress) {
  const auto frameStart = SteadyClock::now();
  const FrameRequest request = inVolume(worldRequest, source_.info().volume);
  if (request.width == 0 || request.height == 0) throw Error("FrameRenderer::render: empty image size");
  FrameStats stats;
  const bool multipass = backendFor(request.params) == RenderBackend::Multipass;
  // Nothing opaque stops an intensity projection's or an average's rays, so no box lies hidden behind them,
  // and nothing behind a slice's plane is drawn: no query.
  const bool occlusion =
      visibility_ && !request.synchronous && !multipass && !showsOneValue(request.params.mode);
  const bool feedback = feedback_ && !request.synchronous && !multipass;

  // Pass 0, hear back: the occlusion answers and the rays' feedback of earlier frames (never waiting for
  // one). Marks and answers made under another isovalue, transfer function, crop box or clip plane describe
  // another image.
  if (const uint64_t key = emptinessKeyOf(request); key != emptinessKey_) {
    emptinessKey_ = key;
    if (visibility_) {
      visibility_->reset();
      queries_->dropPending();
    }
    rayFeedback_.reset();
    // CollapseGuard's rules (below) hold on one view of one image: a node that collapsed, or that the rays
    // requested, under the old emptiness may need to collapse under the new one.
    collapseGuard_.reset();
  }
  if (feedback) collectFeedback(stats);
  if (occlusion) collectVisibility(feedback, stats);

  // Pass 1, refine: the loader plans the cut and the uploads of this frame.
  FrameInput input = viewInputOf(request, source_.info());
  // Occluded or unused leaves do not refine, and a refined node whose leaves are all occluded or unused
  // collapses: while the view changes, every frame; on a still view (and emptiness, above) as CollapseGuard
  // allows, so that the tree converges.
  if (!lastView_ || !sameView(*lastView_, request)) {
    collapseGuard_.reset();
    viewChangedFrame_ = frame_;
  }
  if (!lastView_ || !(lastView_->params == request.params) ||
      lastView_->voxelsPerPixel != request.voxelsPerPixel)
    samplingChangedFrame_ = frame_;
  if (occlusion || feedback) {
    input.hints = [this, occlusion, feedback](const NodeKey& key) {
      const bool refinedNow = lastInnerNodes_.contains(key);
      NodeHint hint = NodeHint::None;
      if (occlusion && visibility_->isOccluded(key, frame_))
        hint = NodeHint::Occluded;
      else if (feedback)
        hint = rayFeedback_.hint(key, frame_, refinedNow);
      return collapseGuard_.filter(key, hint, refinedNow);
    };
  }
  if (feedback) input.usedNodes = rayFeedback_.usedNodes();
  // The pool reuses the bricks of nodes that stay occluded first (Gobbetti et al. 2008, Sect. 6).
  if (occlusion) visibility_->occludedNodes(frame_, input.hiddenNodes);
  if (!request.synchronous) lastView_ = request;
  if (!request.synchronous) input.uploadBudgetBytes = uploadPacer_.allowanceBytes();
  WorkingSetFrame plan = request.synchronous ? workingSet_->updateUntilConverged(input, onLoadProgress)
                                             : workingSet_->update(input);
  // The last frame's tree, when that frame drew, is the tree a frame kept while reading must coarsen: moved
  // rather than copied at every drawn frame.
  const bool lastFrameDrew = lastDrawn_ && !keptConvergedImage_ && framesKeptWhileReading_ == 0;
  if (request.keepImageWhileReading && lastFrameDrew) std::swap(drawnInnerNodes_, lastInnerNodes_);
  lastInnerNodes_.clear();
  for (const PlannedLeaf& leaf : plan.leaves)
    for (NodeKey k = leaf.key; k.depth > 0 && lastInnerNodes_.insert(k.parent()).second;) k = k.parent();
  const uint64_t cutHash = cutSetHash(plan.leaves);

  // The frame would draw the last one's converged image again: the targets keep it, or, drawn, it queries
  // nothing and casts no feedback (the answers could only repeat what is held).
  const bool redraw = redrawsConvergedImage(request, plan, cutHash, occlusion, feedback);
  const bool keep = keepsLastImage(request, plan, redraw);
  // With caps, the cut's empty leaves wholly inside the isosurface (LeafKind::Solid), counted for a kept
  // frame too, as the rest of its cut.
  std::function<bool(const PlannedLeaf&)> isSolid;
  if (const BrickSourceInfo& info = source_.info(); capBoundsOf(request.params, info.volume.dims) != 0) {
    isSolid = [this, isoStored = info.mapping.toStored(request.params.isoValue),
               sampled = sampledWorldBox(request.params, info.volume.dims, info.volume.spacing)](
                  const PlannedLeaf& leaf) { return isSolidLeaf(leaf, source_, isoStored, sampled); };
    stats.leavesSolid = uint64_t(std::count_if(plan.leaves.begin(), plan.leaves.end(), isSolid));
  }
  keptConvergedImage_ = keep && redraw;
  framesKeptWhileReading_ = keep && !redraw ? framesKeptWhileReading_ + 1 : 0;
  if (keep) {
    if (occlusion) countVisibility(stats);  // of the cut it keeps, as the last frame counted them
    finishStats(request, plan, stats);
    stats.converged = redraw;
    stats.drawn = false;
    stats.tiles = 0;
    stats.frameMs = millisecondsSince(frameStart);
    return stats;
  }

  // Pass 2, upload: bricks into their pool slots.
  const auto uploadStart = SteadyClock::now();
  uploadBatch_.clear();
  for (const BrickUpload& upload : plan.uploads)
    uploadBatch_.push_back(
        {upload.slot, std::span<const std::byte>(upload.brick->data(), upload.brick->size())});
  pool_->uploadBatch(uploadBatch_);
  if (gradients_) {
    uploadedOrigins_.clear();
    for (const BrickUpload& upload : plan.uploads)
      uploadedOrigins_.push_back(pool_->geometry().slotOrigin(upload.slot));
    gradients_->derive(pool_->texture(), uploadedOrigins_, glm::u32vec3(pool_->geometry().slotEdge));
  }
  const double uploadMs = millisecondsSince(uploadStart);
  if (!request.synchronous) uploadPacer_.record(plan.stats.bytesUploaded, uploadMs);

  // Pass 3, build index: the rope octree over the cut, into the index texture.
  const auto indexStart = SteadyClock::now();
  cut_ = cutOf(plan.leaves, isSolid);
  uploadIndex(cut_, index_);
  const double indexMs = millisecondsSince(indexStart);

  // Pass 4, plan tiles: the leaves to query and the screen tiles that put them first.
  TileSchedule schedule =
      occlusion ? planTiles(request, plan.leaves, input.isEmpty, feedback, !redraw, stats) : TileSchedule{};
  // A frame that draws the converged image again is cast without feedback: its rays would say what the held
  // answers say, which are renewed instead.
  const bool castFeedback = feedback && !redraw;
  // Pass 5, plan recast: on the last drawn view, only the pixels whose rays meet a leaf that changed; none
  // when the cut holds neither a brick to sample nor a solid leaf to cap (a cold start's first frame), whose
  // rays would all miss.
  schedule.nothingToSample = std::none_of(cut_.leaves.begin(), cut_.leaves.end(), [](const CutLeaf& leaf) {
    return leaf.kind == LeafKind::Data || leaf.kind == LeafKind::Solid;
  });
  if (!multipass && !schedule.nothingToSample)
    if (const std::optional<RecastPlan> recast = planRecastOf(request, plan.leaves, castFeedback))
      schedule.castOnly = recast->rects;

  // Pass 6, ray cast, with the occlusion queries after the first tile and the rays' feedback.
  RaycastFrame frame = raycastFrame(request, request.width, request.height);
  if (isIntensityProjection(request.params.mode)) {
    // Each leaf's largest value (its node's maximum; MinIP: minus its minimum): a ray skips the leaves that
    // cannot raise its maximum.
    const double storedMax = storedMaxOf(source_.info().storedType);
    const bool minimum = request.params.mode == RenderMode::MinIp;
    leafMaxima_.clear();
    for (const PlannedLeaf& leaf : plan.leaves) {
      if (leaf.content != LeafContent::Brick) {
        leafMaxima_.push_back(-1.0f);
        continue;
      }
      const NodeInfo node = source_.node(leaf.key);
      leafMaxima_.push_back(minimum ? float(-node.minValue / storedMax) : float(node.maxValue / storedMax));
    }
    frame.leafMaxima = leafMaxima_;
  }
  if (castFeedback) {
    // With occlusion queries, the rays count the hits that spare them (planTiles).
    feedback_->begin(uint32_t(cut_.leaves.size()), occlusion ? uint32_t(visibility_->thresholdPixels()) : 0);
    frame.feedback = feedback_.get();
    frame.voxelsPerPixel = request.voxelsPerPixel;
  } else if (feedback) {
    rayFeedback_.renew(frame_);
  }
  if (multipass) {
    // The multi-pass renderer over the same cut: one pass per data leaf and per solid leaf, which caps (empty
    // leaves are not drawn).
    std::vector<MultipassLeaf> leaves;
    for (size_t i = 0; i < plan.leaves.size(); ++i) {
      if (plan.leaves[i].content == LeafContent::Brick)
        leaves.push_back(
            {plan.leaves[i].key, plan.leaves[i].slot, frame.leafMaxima.empty() ? 1.0f : leafMaxima_[i]});
      else if (cut_.leaves[i].kind == LeafKind::Solid)
        leaves.push_back({plan.leaves[i].key, kRopeNoBrick});
    }
    multipass_.render(frame, std::move(leaves));
  } else {
    raycast_.render(frame, schedule);
  }
  lastMultipass_ = multipass;
  if (multipass)
    recast_.forget();
  else
    recast_.drew(frame_, plan.leaves, redraw);
  if (cutHash != currentCutHash_) cutChangedFrame_ = frame_;
  currentCutHash_ = cutHash;
  if (castFeedback) {
    feedback_->end(frame_);
    std::vector<NodeKey> keys;
    std::vector<uint8_t> dataLeaf;
    keys.reserve(plan.leaves.size());
    dataLeaf.reserve(plan.leaves.size());
    for (const PlannedLeaf& leaf : plan.leaves) {
      keys.push_back(leaf.key);
      dataLeaf.push_back(leaf.content == LeafContent::Brick);
    }
    rayFeedback_.rememberCut(frame_, std::move(keys), std::move(dataLeaf));
  }

  finishStats(request, plan, stats);
  stats.tiles = std::max<uint64_t>(schedule.tiles.size(), 1);
  if (multipass) {
    stats.drawCalls = multipass_.lastCounts().blocks;
    stats.glDrawCalls = multipass_.lastCounts().glDrawCalls;
    stats.fragments = multipass_.lastCounts().fragments;
  } else {
    stats.fragments = raycast_.lastPixelsCast();
    stats.drawCalls = stats.tiles;  // one pass over the image per screen tile
    stats.glDrawCalls = raycast_.lastDrawCalls();
  }
  stats.converged = cutConverged(stats.converged, occlusion, feedback);
  lastDrawn_ = request;
  lastDrawnEmptinessKey_ = emptinessKey_;
  stats.indexMs = indexMs;
  stats.uploadMs = uploadMs;
  // Waits for the GPU: the frame time includes the ray cast.
  stats.raycastMs = multipass ? multipass_.lastRaycastMs() : raycast_.lastRaycastMs();
  if (!multipass) stats.occlusionDrawMs = raycast_.lastAfterFirstTileMs();
  stats.raycastWallClock =
      multipass ? multipass_.raycastTimerUsedWallClock() : raycast_.raycastTimerUsedWallClock();
  stats.frameMs = millisecondsSince(frameStart);
  return stats;
}

}  // namespace ropecast
