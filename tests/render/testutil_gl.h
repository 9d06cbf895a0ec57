// Helpers of the GL test tier (tests/render/*_gltest.cpp): one headless GL context shared by every test of
// the process (EGL displays are per process, see render/gl_context.h), image comparison, temporary folders.
// Test thread only.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "index/cut.h"
#include "index/rope_index.h"
#include "reference/cpu_raycaster.h"
#include "reference/image_io.h"
#include "render/brick_pool.h"
#include "render/gl_context.h"
#include "render/gl_fence.h"
#include "render/gradient_pool.h"
#include "render/index_texture.h"
#include "render/raycast_pass.h"
#include "store/brick_source.h"
#include "tests/common/temp_dir.h"

namespace ropecast::test {

// The process-wide context, created on first use and current on the calling (test) thread.
GlContext& sharedGlContext();

// Whether the shared context runs on a hardware GPU (not a software rasterizer such as llvmpipe, where the
// tests are tuned and CI runs them). Hardware differs in documented ways the tests allow for where they say:
// texture filtering weights in fixed point (8 fractional bits on NVIDIA), each shader stage compiled on its
// own (multiply-adds fused differently), SNORM rounding.
bool onHardwareGpu();

// Peak signal-to-noise ratio in dB over the first `channels` channels (peak 1.0); +inf for identical images.
double psnrDb(const FloatImage& a, const FloatImage& b, uint32_t channels = 3);
// Largest absolute difference over the first `channels` channels (inf == inf counts as 0).
double maxAbsDifference(const FloatImage& a, const FloatImage& b, uint32_t channels);

// A small volume built directly as bricks for ray caster tests: a function of the world position gives the
// normalized value of every level-L sample (at its center (n + 0.5) s 2^L, sample indices clamped to the
// level's dims as the store's edge replication does), and `refine` chooses the cut: a node inside the data is
// split while refine(node) says so (down to maxDepth); leaves inside the data get bricks, the others are
// Empty.
struct SceneSpec {
  glm::u32vec3 dims{32};
  glm::dvec3 spacing{1.0};
  uint32_t brickSize = 8;
  SampleType storedType = SampleType::UInt16;
  std::function<double(glm::dvec3 world)> value;       // normalized to [0, 1]
  std::function<bool(const NodeKey& node)> refine;     // default: split everything (full resolution)
  std::function<bool(const NodeKey& leaf)> emptyLeaf;  // inside leaves to mark Empty (default: none)
  // Isosurface caps: an inside leaf whose samples (borders included) all lie above this normalized value is
  // Solid, without a brick, as FrameRenderer marks the empty leaves inside a capped isosurface. Unset: none.
  std::optional<double> solidAbove;
};

struct GlScene {
  BrickSourceInfo info;  // layout, dims, spacing, stored type (identity mapping)
  VolumeGeometry geometry;
  Cut cut;
  RopeIndex index;
  std::unordered_map<uint32_t, std::vector<std::byte>>
      bricks;  // by pool slot (reference/cpu_raycaster BricksBySlot)
  std::unique_ptr<BrickPool> pool;
  std::unique_ptr<GradientPool> gradients;  // derived from every uploaded slot, for stored DVR gradients
  std::unique_ptr<IndexTexture> indexTexture;
  size_t dataLeaves = 0;
  size_t solidLeaves = 0;
  uint32_t minLeafDepth = 0, maxLeafDepth = 0;
  // Per leaf of the cut, the largest and the smallest sample of its brick, normalized (-1 and 2 for empty
  // leaves).
  std::vector<float> leafMaxima, leafMinima;
  // RaycastFrame::leafMaxima for `mode`: the maxima (MIP), minus the minima (MinIP); none for the others.
  std::vector<float> leafBounds(RenderMode mode) const;
};

// Builds the bricks, the cut and its index, and uploads pool and index (needs the shared context).
GlScene buildScene(const SceneSpec& spec);

// Renders the scene with the pass; fills frame.pool/gradients/index/volume from the scene.
void renderScene(RaycastPass& pass, const GlScene& scene, RaycastFrame frame,
                 const TileSchedule& schedule = {});

// What the CPU mirror (reference/cpu_raycaster.h renderMirror) is asked for the frame: its camera, size,
// parameters and transfer function.
CpuRenderInput cpuInputOf(const RaycastFrame& frame);

// Says a fence signaled only once *released is true: readbacks held back, as a GPU still busy holds them.
class HeldBackFences final : public FenceProbe {
 public:
  explicit HeldBackFences(const bool* released) : released_(released) {}
  bool signaled(GlSync) override { return *released_; }

 private:
  const bool* released_;
};

}  // namespace ropecast::test
