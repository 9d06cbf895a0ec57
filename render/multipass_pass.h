// MultipassPass: the multi-pass block renderer, the strategy the single-pass rope ray caster replaces
// (Gobbetti et al. 2008, Sect. 2: "separate rendering of blocks and frame buffer composition"), over the same
// working set: the same pool, cut, transfer function and sample grid as RaycastPass, so the two images can be
// compared pixel for pixel (docs/RENDERING.md "Multi-pass"). The data (and solid) leaves of the cut are
// sorted front to back in the octree's visibility order for the eye, and each is drawn as its own pass:
//   block:   the leaf's box (clipped to the volume) is rasterized, its front faces, or one full-screen
//            triangle when the box reaches behind the eye; each fragment clips its camera ray to the box and
//            samples the ray's global grid t0 + k dt there (the first k from the ray's entry into the volume,
//            as shaders/sampling.glsl firstSampleIndex does), continuing the pixel's front-to-back state in
//            float images: premultiplied color and opacity ("under"), the depth, and the isosurface march's
//            last sample and the leaf it lies in, so a crossing between two blocks is found and refined as
//            the single pass finds and refines it;
//   mark:    the same box again, writing depth where the pixel's ray has ended (opacity >= --ert, or an
//            isosurface hit): early ray termination across blocks, the later blocks' fragments fail the
//            depth test before they are shaded.
// A last full-screen pass composites the background and leaves the final color and depth in the target.
// Occlusion queries and ray feedback are the single pass's; this pass has neither.
//
// Owns GL objects: render thread only, with the GlContext current.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <tuple>
#include <vector>

#include <glm/vec3.hpp>

#include "core/float_image.h"
#include "render/gpu_timer.h"
#include "render/raycast_pass.h"
#include "render/raycast_uniforms.h"
#include "render/render_target.h"
#include "store/octree_layout.h"

namespace ropecast {

// A data leaf of the cut to draw: its node and the pool slot of its brick; or, slot kRopeNoBrick, a solid
// leaf (LeafKind::Solid), whose block only caps the rays that enter it through a cut.
struct MultipassLeaf {
  NodeKey key;
  uint32_t slot = 0;
  // MIP and MinIP: the leaf's bound (as RaycastFrame::leafMaxima); its block leaves a pixel whose maximum is
  // at least this alone.
  float maxValue = 1.0f;
};

// Sorts `leaves` (disjoint nodes of one octree) front to back for an eye at `eye` (world units): octree
// visibility order, each node's children visited from the eye's octant outwards, so a leaf comes before
// every leaf it can hide. Any thread.
void sortFrontToBack(std::vector<MultipassLeaf>& leaves, const OctreeLayout& layout, glm::dvec3 spacing,
                     glm::dvec3 eye);

// What one multi-pass frame did.
struct MultipassCounts {
  uint64_t blocks = 0;       // data (and solid) leaves drawn, one pass each
  uint64_t fullScreen = 0;   // of those, drawn as a full-screen triangle (the box reaches behind the eye)
  uint64_t glDrawCalls = 0;  // every draw: the blocks, their marks and the resolve
  // Fragments that passed the depth test in the blocks and marks (GL_SAMPLES_PASSED): each block fragment
  // sets up its ray and reads and writes the pixel's state; the marks add at most one per pixel. The single
  // pass shades one fragment (or invocation) per pixel.
  uint64_t fragments = 0;
};

class MultipassPass {
 public:
  MultipassPass();
  ~MultipassPass();
  MultipassPass(const MultipassPass&) = delete;
  MultipassPass& operator=(const MultipassPass&) = delete;

  // Renders the frame from `leaves` (the data and solid leaves of the cut behind frame.index, in any order;
  // sorted here). frame.params.backend, frame.index and frame.feedback are not used. Throws ropecast::Error
  // on bad inputs, shader or GL errors.
  void render(const RaycastFrame& frame, std::vector<MultipassLeaf> leaves);

  // Wall or GPU time of the last render's passes (GpuTimer), waiting for the result.
  double lastRaycastMs() { return timer_.elapsedMs(); }
  bool raycastTimerUsedWallClock() const { return timer_.usedWallClock(); }
  const MultipassCounts& lastCounts() const { return counts_; }
  // As RaycastPass: RGBA (alpha = coverage) and world depth (+inf = miss), row 0 at the top.
  FloatImage readColor() const { return target_.readColor(); }
  FloatImage readDepth() const { return target_.readDepth(); }
  float readDepthAt(uint32_t x, uint32_t y) const { return target_.readDepthAt(x, y); }

 private:
  enum class Stage { Block, Mark, Resolve };
  const ShaderProgram& program(const RenderParams& params, Stage stage);
  void resize(uint32_t width, uint32_t height);

  // (mode, stored gradients, stage) -> program
  std::map<std::tuple<RenderMode, DvrLighting, Stage>, std::unique_ptr<ShaderProgram>> programs_;
  RenderTarget target_{"MultipassPass", false};  // color = the accumulation, depth = the world depth
  uint32_t marchTexture_ = 0;  // RGBA32F: the isosurface march's state (has previous, t, f, ended)
  uint32_t beforeTexture_ =
      0;                      // RGBA32UI: the leaf of the march's previous sample (box min bits, depth, slot)
  uint32_t depthBuffer_ = 0;  // DEPTH_COMPONENT32F: 0.25 where a ray ended (the mark), else 1
  uint32_t framebuffer_ = 0;  // the depth buffer alone: the blocks write only through images
  uint32_t width_ = 0, height_ = 0;
  RaycastBlockBuffer blockBuffer_;
  uint32_t emptyVertexArray_ = 0;
  uint32_t tfTexture_ = 0;
  uint32_t fragmentQuery_ = 0;  // GL_SAMPLES_PASSED over the blocks and marks
  MultipassCounts counts_;
  GpuTimer timer_;
};

}  // namespace ropecast
