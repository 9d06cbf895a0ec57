// The CPU ray casters: one ray loop written from docs/RENDERING.md, behind two ways of finding the samples.
//   renderMirror: the CPU mirror of the GLSL ray caster. Walks a RopeIndex with the CPU rope traversal
//     (index/rope_traversal.h, float like the GPU) and samples each data leaf's brick at the leaf's level
//     with the trilinear formula in the coordinates the shader uses. GL tests compare their images with it.
//   ReferenceRenderer: the brute-force reference (`--reference`): no octree, the level-0 data of a
//   BrickSource
//     ray marched with the level-0 step and the same shading. Used for quality figures.
// Both render W x H RGBA float + depth with two threads (rows interleaved). Pure CPU, no GL. The functions
// may be called from any thread; a ReferenceRenderer may render from several threads at once (its cache is
// thread-safe).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <unordered_map>
#include <vector>

#include "core/camera.h"
#include "core/render_params.h"
#include "core/transfer_function.h"
#include "index/cut.h"
#include "index/rope_index.h"
#include "store/brick_source.h"

namespace ropecast {

class Level0BrickCache;

// A rendered image: row 0 at the top. rgba: 4 floats per pixel, final color (background composited) and alpha
// = coverage; depth: world distance along the camera axis, +inf where nothing was hit.
struct CpuImage {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<float> rgba;
  std::vector<float> depth;

  glm::vec4 pixel(uint32_t x, uint32_t y) const {
    const size_t i = 4 * (size_t(y) * width + x);
    return {rgba[i], rgba[i + 1], rgba[i + 2], rgba[i + 3]};
  }
};

// What every renderer needs besides the data: the view, the settings and (DVR) the baked transfer function.
struct CpuRenderInput {
  Camera camera;
  uint32_t width = 0;
  uint32_t height = 0;
  RenderParams params;
  const TfTable* tf = nullptr;  // required for DVR and MIP
  unsigned threads = 2;         // rows are split over this many threads
  // MIP and MinIP, the mirror: per leaf of the cut, its bound (render/raycast_pass.h
  // RaycastFrame::leafMaxima); a ray skips the data leaves that cannot raise its maximum. Empty: none is
  // skipped.
  std::span<const float> leafMaxima;
};

// Brick bytes (storedBrickEdge()^3 samples of the stored type, border included) by GPU pool slot.
using BricksBySlot = std::unordered_map<uint32_t, std::vector<std::byte>>;

// One ray of the mirror as the feedback twin (reference/feedback_twin.h) reads it: the data leaves it walked
// in order with the samples it took in each. A traced ray goes on sampling past where it ended (its image
// does not change), so that a test can ask where a ray within rounding of ending would have ended.
struct MirrorSample {
  double t = 0.0;
  double f = 0.0;      // iso: v - vIso
  double alpha = 0.0;  // DVR: the opacity after the sample (accumulation continued past the end)
  bool addsOpacity = false;
  // iso: the sample at the leaf's end, after its grid samples (docs/RENDERING.md "Isosurface"), taken when
  // the ray's previous sample lies more than a texel before the end. Traced from half a texel on, so that
  // the feedback twin can judge decisions within rounding of a texel; leafEndTaken says what the mirror did.
  bool atLeafEnd = false;
  bool leafEndTaken = false;
  double leafEndGapTexels = 0.0;  // the distance from the previous sample, in texels of the leaf's level
};
struct MirrorLeafVisit {
  uint32_t leafIndex = 0;  // in the Cut's leaves
  uint32_t depth = 0;
  double tEnter = 0.0;  // the traversal's [tEnter, tExit), float like the shader's
  double tExit = 0.0;
  bool firstLeaf = false;  // the ray's first leaf: sampled from t0 (docs/RENDERING.md "Rays")
  double dt = 0.0;         // the leaf's step
  double kBegin = 0.0;     // its first sample index on the grid t0 + k dt
  // MIP, MinIP: the leaf's bound less the ray's maximum before it (<= 0: skipped); +inf when not known.
  double maximumMargin = std::numeric_limits<double>::infinity();
  std::vector<MirrorSample> samples;  // the grid samples, then the one at the leaf's end, if traced
  size_t gridSampleCount() const { return samples.size() - (!samples.empty() && samples.back().atLeafEnd); }
};
struct MirrorRayTrace {
  bool entered = false;  // the ray met the volume box
  double t0 = 0.0, t1 = 0.0;
  std::vector<MirrorLeafVisit> leaves;
  // Where the mirror ended the ray (iso hit or early ray termination): leaves[endLeaf].samples[endSample];
  // endLeaf == leaves.size() when it left the volume.
  size_t endLeaf = 0, endSample = 0;
  // Isosurface caps: the ray entered through a capped cut, so a first sample inside the surface ends it. A
  // ray capped in a solid leaf (LeafKind::Solid) is traced no further: its `leaves` end there, none sampled.
  bool capped = false;
};

// Reads the brick of every Data leaf of `cut` from `source`, keyed by the leaf's brickSlot.
BricksBySlot readCutBricks(const Cut& cut, const BrickSource& source);

// The mirror of the GL ray caster. `volume` gives dims, spacing, layout, stored type and mapping; every Data
// leaf's brickSlot must be in `bricks`. Throws ropecast::Error on a missing slot or missing TF in DVR mode.
// With `traces`, also each pixel's ray (traces[y * width + x]).
CpuImage renderMirror(const RopeIndex& index, const BricksBySlot& bricks, const BrickSourceInfo& volume,
                      const CpuRenderInput& input, std::vector<MirrorRayTrace>* traces = nullptr);

// The brute-force reference. Keeps the level-0 bricks it has read for later frames. Its input's camera and
// clip plane are in the world, turned into the volume's axes as FrameRenderer does (store/volume_source.h
// cameraInVolume); the mirror above takes them in the volume's axes, as RaycastPass does.
class ReferenceRenderer {
 public:
  explicit ReferenceRenderer(const BrickSource& source);
  ~ReferenceRenderer();

  CpuImage render(const CpuRenderInput& input) const;
  size_t bricksRead() const;

 private:
  const BrickSource& source_;
  std::unique_ptr<Level0BrickCache> cache_;
};

}  // namespace ropecast
