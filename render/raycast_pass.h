// RaycastPass: the single-pass stackless GPU ray caster (Gobbetti et al. 2008, Sect. 5; docs/RENDERING.md).
// Given the brick pool, the rope index texture, a camera, the volume's geometry, RenderParams and (DVR) a
// baked transfer function, it renders W x H into its own RGBA32F color target and R32F world-depth target,
// through either entry point over the one shared include shaders/raycast_common.glsl:
//   fragment: screen tiles (kTileSize pixels square) drawn one by one, each one triangle cut to the tile
//             by the scissor, with the depth where each ray stopped written to a depth attachment;
//   compute:  8x8 workgroups with imageStore (shaders/compute_tile.glsl, which brute force's compute entry
//             point shares), the stop depth copied into the depth attachment by a pass.
// A frame's TileSchedule casts the first tile, runs a callback (the occlusion queries, Gobbetti et al. 2008,
// Sect. 6) against that depth, then casts the other tiles.
// Composition, not inheritance: the pass owns its programs and targets and is handed everything else.
//
// Owns GL objects: render thread only, with the GlContext current.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <tuple>
#include <vector>

#include <glm/vec3.hpp>

#include "core/camera.h"
#include "core/float_image.h"
#include "core/render_params.h"
#include "core/sample_type.h"
#include "render/gpu_timer.h"
#include "render/raycast_uniforms.h"
#include "render/render_target.h"
#include "store/brick_source.h"

namespace ropecast {

class BrickPool;
class FeedbackBuffer;
class GradientPool;
class IndexTexture;
class ShaderProgram;
class TfTable;

// What the ray caster needs to know about the volume (docs/RENDERING.md "Spaces").
struct VolumeGeometry {
  glm::u32vec3 dims{0};     // level-0 samples per axis
  glm::dvec3 spacing{1.0};  // world units per sample
  uint32_t brickSize = 32;  // B
  uint32_t maxDepth = 0;    // depth of the full-resolution leaves
  SampleType storedType = SampleType::UInt8;
  ValueMapping mapping;  // stored -> data units

  static VolumeGeometry of(const BrickSourceInfo& info);
  double storedMax() const { return storedMaxOf(storedType); }
};

struct RaycastFrame {
  const BrickPool* pool = nullptr;
  const IndexTexture* index = nullptr;  // uvec4 texels of index/rope_layout.h
  Camera camera;
  VolumeGeometry volume;
  RenderParams params;  // params.backend picks the entry point
  // The pool's DVR sample texture, required when usesStoredGradients(params) (render/gradient_pool.h).
  const GradientPool* gradients = nullptr;
  const TfTable* tf = nullptr;  // required in DVR mode
  uint32_t width = 0, height = 0;
  // Usage and miss feedback (docs/RENDERING.md "Feedback"): the rays write into this buffer, between the
  // caller's FeedbackBuffer::begin and end; null: off, and the programs have no feedback code
  // (RAYCAST_FEEDBACK). voxelsPerPixel is the refinement target the requests are measured against.
  FeedbackBuffer* feedback = nullptr;
  double voxelsPerPixel = 1.0;
  // MIP: per leaf of the cut (RopeLeaf.leafIndex), the largest value its node holds, normalized as the
  // samples are (stored / storedMax; a bound on every sample of its brick, borders included); MinIP: minus
  // its smallest value (the largest of -v). A ray skips a data leaf whose bound cannot raise its maximum
  // (docs/RENDERING.md "Maximum intensity projection"). Empty: no leaf is skipped. Only read in the
  // projection modes; must outlive render().
  std::span<const float> leafMaxima;
};

// The uniform block of a frame: camera, volume, the pool's geometry, window depth range and feedback
// distances (shaders/raycast_block.h). Shared by the passes that walk the cut's bricks (RaycastPass,
// MultipassPass). Any thread.
RaycastBlock raycastFrameBlock(const RaycastFrame& frame);

// The order a frame is cast in. With tiles, tiles[0] is cast first, then afterFirstTile runs with the pass's
// framebuffer bound and its depth attachment holding, over tiles[0], the window depth where each ray stopped
// (shaders/window_depth.glsl); then the other tiles are cast. The tiles must cover the image exactly once.
// Empty: the whole image at once, no callback.
// With castOnly, only the pixels of those rectangles are cast (each tile's part of them, in the order above)
// and the targets keep the last render's pixels elsewhere, their stop depths included: a still view whose cut
// changed in places (render/recast_plan.h). The last render must have had the same size and entry point.
// With nothingToSample (the cut holds no brick: every leaf empty, or the root's brick not in core yet), every
// ray would meet only leaves it skips and end as a miss, so the targets are set to a miss everywhere instead
// of casting (no pixel counts as cast), and afterFirstTile runs against that depth.
struct TileSchedule {
  std::vector<PixelRect> tiles;
  std::function<void()> afterFirstTile;
  std::optional<std::vector<PixelRect>> castOnly;
  bool nothingToSample = false;
};

class RaycastPass {
 public:
  static constexpr uint32_t kTileSize = 64;  // fragment entry point: pixels per tile side

  RaycastPass();
  ~RaycastPass();
  RaycastPass(const RaycastPass&) = delete;
  RaycastPass& operator=(const RaycastPass&) = delete;

  // Renders the frame into the targets (resized to width x height as needed). Programs compile on first use
  // of a (backend, mode) variant. Throws ropecast::Error on bad inputs (naming the field), shader errors or
  // GL errors.
  void render(const RaycastFrame& frame, const TileSchedule& schedule = {});

  // GPU time of the last render()'s ray cast (GL timestamps, see GpuTimer; waits for the result), without the
  // schedule's callback, which is timed on its own: lastAfterFirstTileMs() (0 when there was none).
  double lastRaycastMs();
  double lastAfterFirstTileMs();
  // Pixels the last render() cast: its castOnly rectangles' or the whole image's.
  uint64_t lastPixelsCast() const { return lastPixelsCast_; }
  // GL draws (or compute dispatches) of the last render()'s ray cast: one per kTileSize square of each tile
  // for the fragment entry point, one per tile for the compute one.
  uint64_t lastDrawCalls() const { return lastDrawCalls_; }
  bool raycastTimerUsedWallClock() const { return timer_.usedWallClock(); }
  // The targets of the last render, row 0 at the top: RGBA (final color, alpha = coverage) and depth (world
  // units along the camera axis, +inf = miss). Synchronous readback.
  FloatImage readColor() const { return target_.readColor(); }
  FloatImage readDepth() const { return target_.readDepth(); }
  float readDepthAt(uint32_t x, uint32_t y) const { return target_.readDepthAt(x, y); }
  // The window depth (shaders/window_depth.glsl) where each ray stopped, over the tiles cast before the
  // schedule's callback (after the fragment entry point: all of them). Synchronous readback.
  FloatImage readStopDepth() const { return target_.readDepthBuffer(); }
  uint32_t colorTexture() const { return target_.colorTexture(); }
  uint32_t depthTexture() const { return target_.depthTexture(); }

  // Whether DVR programs walk the leaves in gathered batches (LLVMPIPE_DVR_LEAF_BATCH in
  // shaders/raycast_common.glsl), the form measured faster on software rasterizers only. On by default
  // exactly there (render/backend_choice.h isSoftwareRenderer); the images are the same either way. Applies
  // to programs compiled afterwards.
  void setDvrLeafBatch(bool on) { dvrLeafBatch_ = on; }
  bool dvrLeafBatch() const { return dvrLeafBatch_; }

 private:
  const ShaderProgram& program(const RenderParams& params, bool feedback);
  // Binds what the ray-cast program reads and, for the fragment entry point, the target and its state.
  void bindForCasting(const RaycastFrame& frame, const ShaderProgram& p);
  void castTile(const RaycastFrame& frame, const ShaderProgram& p, const PixelRect& tile);
  // Compute entry point: the stop depths of `tile` into the depth attachment (shaders/stop_depth.frag).
  void copyStopDepth(const PixelRect& tile);
  // The targets as if every ray missed (TileSchedule::nothingToSample), then the schedule's callback.
  void writeMisses(const RaycastFrame& frame, const TileSchedule& schedule);

  // (backend, mode, stored gradients, leaf batch, feedback) -> program
  std::map<std::tuple<RenderBackend, RenderMode, DvrLighting, bool, bool>, std::unique_ptr<ShaderProgram>>
      programs_;
  bool dvrLeafBatch_ = false;
  RenderTarget target_{"RaycastPass", true};
  RaycastBlockBuffer blockBuffer_;
  uint32_t emptyVertexArray_ = 0;
  uint32_t tfTexture_ = 0;
  std::unique_ptr<IndexTexture> leafMaxima_;  // MIP: RaycastFrame::leafMaxima as float bits
  std::vector<uint32_t> leafMaximaWords_;
  uint64_t lastDrawCalls_ = 0;
  uint64_t lastPixelsCast_ = 0;
  RenderBackend lastBackend_ = RenderBackend::Auto;  // of the last render(); Auto before the first
  uint32_t stopDepthTexture_ = 0;                    // compute entry point: R32F, the size of the target
  uint32_t stopDepthWidth_ = 0, stopDepthHeight_ = 0;
  std::unique_ptr<ShaderProgram> stopDepthProgram_;
  GpuTimer timer_;
  GpuTimer afterFirstTileTimer_;
  bool afterFirstTileTimed_ = false;  // the last render() ran a callback
};

}  // namespace ropecast
