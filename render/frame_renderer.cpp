#include "render/frame_renderer.h"

#include <chrono>
#include <cmath>

#include "core/error.h"
#include "render/backend_choice.h"
#include "render/brick_pool.h"
#include "render/gl_context.h"
#include "render/gradient_pool.h"
#include "render/index_texture.h"

namespace ropecast {

namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}
}  // namespace

EmptinessPredicate emptinessFor(const RenderParams& params, const BrickSourceInfo& info, const TfTable* tf) {
  if (params.mode == RenderMode::Iso) {
    const double isoStored = info.mapping.toStored(params.isoValue);
    return [isoStored](uint16_t lo, uint16_t hi) { return double(hi) < isoStored || double(lo) > isoStored; };
  }
  if (!tf) throw Error("emptinessFor: DVR needs a transfer function");
  return [tf](uint16_t lo, uint16_t hi) { return !tf->hasOpacity(lo, hi); };
}

FrameRenderer::FrameRenderer(const GlContextInfo& gl, const BrickSource& source,
                             const FrameRendererConfig& config)
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
  pool_ = std::make_unique<BrickPool>(poolConfig, gl.max3DTextureSize);
  if (config.storedGradients) gradients_ = std::make_unique<GradientPool>(pool_->geometry().textureDims);
  indexTexture_ = std::make_unique<IndexTexture>(kRopeTexelComponents, gl.maxTextureBufferTexels);

  WorkingSetConfig wsConfig;
  wsConfig.cpuCacheBytes = config.cpuCacheBytes;
  wsConfig.gpuSlots = pool_->slotCount();
  wsConfig.uploadBudgetBytes = config.uploadBudgetBytes;
  wsConfig.ioThreads = config.ioThreads;
  workingSet_ = std::make_unique<WorkingSet>(source, wsConfig);
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

void FrameRenderer::prepare(const FrameRequest& request) {
  Cut empty;
  empty.leaves.push_back(CutLeaf{});  // the root, an empty leaf: rays traverse it and take no sample
  RopeIndex index;
  uploadIndex(empty, index);
  raycast_.render(raycastFrame(request, 1, 1));
  raycast_.lastRaycastMs();  // waits for the draw
}

FrameStats FrameRenderer::render(const FrameRequest& request) {
  const auto frameStart = Clock::now();
  if (request.width == 0 || request.height == 0) throw Error("FrameRenderer::render: empty image size");

  // Pass 1, refine: the loader plans the cut and the uploads of this frame.
  FrameInput input;
  input.view.camera = request.camera;
  input.view.viewportWidth = request.width;
  input.view.viewportHeight = request.height;
  input.view.voxelsPerPixel = request.voxelsPerPixel;
  input.isEmpty = emptinessFor(request.params, source_.info(), request.tf);
  if (!request.synchronous) input.uploadBudgetBytes = uploadPacer_.allowanceBytes();
  WorkingSetFrame plan =
      request.synchronous ? workingSet_->updateUntilConverged(input) : workingSet_->update(input);

  // Pass 2, upload: bricks into their pool slots.
  const auto uploadStart = Clock::now();
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
  const double uploadMs = msSince(uploadStart);
  if (!request.synchronous) uploadPacer_.record(plan.stats.bytesUploaded, uploadMs);

  // Pass 3, build index: the rope octree over the cut, into the index texture.
  const auto indexStart = Clock::now();
  cut_.leaves.clear();
  cut_.leaves.reserve(plan.leaves.size());
  for (const PlannedLeaf& leaf : plan.leaves) {
    CutLeaf cutLeaf;
    cutLeaf.depth = leaf.key.depth;
    cutLeaf.coord = leaf.key.coord;
    cutLeaf.kind = leaf.content == LeafContent::Brick ? LeafKind::Data : LeafKind::Empty;
    cutLeaf.brickSlot = leaf.content == LeafContent::Brick ? leaf.slot : 0;
    cut_.leaves.push_back(cutLeaf);
  }
  uploadIndex(cut_, index_);
  const double indexMs = msSince(indexStart);

  // Pass 4, ray cast.
  const RaycastFrame frame = raycastFrame(request, request.width, request.height);
  raycast_.render(frame);

  FrameStats stats;
  static_cast<LoaderStats&>(stats) = plan.stats;
  stats.frame = frame_++;
  stats.indexMs = indexMs;
  stats.stepVoxels = request.params.stepVoxels;
  stats.backend = frame.params.backend;
  stats.uploadMs = uploadMs;
  stats.raycastMs = raycast_.lastRaycastMs();  // waits for the GPU: the frame time includes the ray cast
  stats.raycastWallClock = raycast_.raycastTimerUsedWallClock();
  stats.frameMs = msSince(frameStart);
  return stats;
}

}  // namespace ropecast
