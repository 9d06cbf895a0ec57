// BruteForcePass: the baseline ray caster of bench/render_vs_brute.sh. It holds the whole level-0 volume in
// one 3D texture and marches every ray from the volume entry to its exit at a fixed half-voxel step, with no
// index, no levels and no empty-space skipping; everything else is the rendering contract of
// docs/RENDERING.md at level 0 (same rays, same sample grid t0 + k dt, same interpolation, bisection,
// gradients, transfer function, shading and early ray termination), so on a cut of level-0 leaves its image
// equals RaycastPass's up to rounding (tests/render/brute_force_gltest.cpp). Two entry points over the one
// shared include shaders/brute_force_common.glsl, as the ray caster has, so that a benchmark can compare the
// two methods in the same shader stage:
//   fragment: shaders/brute_force.frag, one triangle over the viewport;
//   compute:  shaders/brute_force.comp, one dispatch over the image in the ray caster's compute workgroups
//             (shaders/compute_tile.glsl).
//
// Owns GL objects: render thread only, with the GlContext current.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <tuple>

#include "core/camera.h"
#include "core/float_image.h"
#include "core/render_params.h"
#include "render/gpu_timer.h"
#include "render/raycast_uniforms.h"
#include "render/render_target.h"
#include "store/brick_source.h"

namespace ropecast {

class GradientPool;
class ShaderProgram;
class TfTable;

struct BruteForceFrame {
  Camera camera;                // in the world: turned into the volume's axes as FrameRenderer does
  RenderParams params;          // params.backend picks the entry point: Fragment or Compute
  const TfTable* tf = nullptr;  // required in DVR mode
  uint32_t width = 0, height = 0;
};

class BruteForcePass {
 public:
  // Reads every level-0 brick of `source` and uploads the interiors into one R8/R16 3D texture (and, for DVR
  // with stored gradients, derives a GradientPool of it at the first such render, as the ray caster's pool
  // has one; render/gradient_pool.h). Throws
  // ropecast::Error when the volume exceeds GL_MAX_3D_TEXTURE_SIZE or on a read error.
  explicit BruteForcePass(const BrickSource& source);
  ~BruteForcePass();
  BruteForcePass(const BruteForcePass&) = delete;
  BruteForcePass& operator=(const BruteForcePass&) = delete;

  // Renders the frame into the targets (resized to width x height as needed). Programs compile on first use
  // of an (entry point, mode) variant. Throws ropecast::Error on bad inputs (naming the field), shader errors
  // or GL errors.
  void render(const BruteForceFrame& frame);
  double lastRaycastMs() { return timer_.elapsedMs(); }
  bool raycastTimerUsedWallClock() const { return timer_.usedWallClock(); }
  // As RaycastPass: RGBA (alpha = coverage) and world depth (+inf = miss), row 0 at the top.
  FloatImage readColor() const { return target_.readColor(); }
  FloatImage readDepth() const { return target_.readDepth(); }
  uint64_t volumeBytes() const { return volumeBytes_; }

 private:
  const ShaderProgram& program(const RenderParams& params);

  BrickSourceInfo info_;
  // (entry point, mode, stored gradients) -> program
  std::map<std::tuple<RenderBackend, RenderMode, DvrLighting>, std::unique_ptr<ShaderProgram>> programs_;
  std::unique_ptr<GradientPool> gradients_;  // derived from the volume at the first use
  uint32_t volumeTexture_ = 0, tfTexture_ = 0;
  uint64_t volumeBytes_ = 0;
  RenderTarget target_{"BruteForcePass", false};
  RaycastBlockBuffer blockBuffer_;
  uint32_t emptyVertexArray_ = 0;
  GpuTimer timer_;
};

}  // namespace ropecast
