// What the ray casters over docs/RENDERING.md share on the GL side: the uniform block of
// shaders/raycast_block.h (camera, volume geometry, RenderParams and lighting; the pass adds its own fields)
// and the buffer it is uploaded to once per frame; the shader defines of a variant; the checks of a request;
// the transfer-function texture; and the C++ side of the compute entry points (shaders/compute_tile.glsl).
// Used by RaycastPass and BruteForcePass. Render thread only, with the GlContext current (raycastBlock and
// the defines: any thread).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/camera.h"
#include "core/render_params.h"
#include "core/sample_type.h"
#include "shaders/raycast_block.h"

namespace ropecast {

class RenderTarget;
class ShaderProgram;
class TfTable;

// "NAME value" with enough digits that the float round-trips.
std::string floatDefine(const char* name, double value);

// The defines of a ray-cast program: docs/RENDERING.md's constants (BRICK_BORDER, ISO_BISECTION_STEPS,
// DVR_SHADE_GRADIENT_THRESHOLD, TF_ENTRIES) and the variant of `params` (RAYCAST_MODE_ISO, _DVR, _MIP with
// MIP_SIGN 1 or -1 for MinIP, or _AIP; DVR_STORED_GRADIENTS or DVR_UNLIT, dvrLightingOf).
std::vector<std::string> raycastDefines(const RenderParams& params);

// Throws ropecast::Error, prefixed by `where`, for a non-positive step, DVR or MIP without a baked transfer
// function, or a table of other than TfTable::kDefaultEntries entries.
void checkRaycastInputs(const RenderParams& params, const TfTable* tf, const char* where);

// The transfer-function texture of shaders/shading.glsl: 1D RGBA32F of TfTable::kDefaultEntries texels,
// LINEAR, CLAMP_TO_EDGE. The caller owns (deletes) it.
uint32_t createTfTexture();
void uploadTf(uint32_t texture, const TfTable& tf);

// The block's fields both passes share: camera and image, volume box and spacing, RenderParams (the isovalue
// normalized to storedMax) and lighting. The rest stays zero for the pass to fill. Throws ropecast::Error for
// a camera or spacing that would give rays that never end.
RaycastBlock raycastBlock(const Camera& camera, uint32_t width, uint32_t height, glm::u32vec3 dims,
                          glm::dvec3 spacing, const ValueMapping& mapping, double storedMax,
                          const RenderParams& params);

// The window depth mapping of the ray-cast passes (RaycastBlock depthNear, depthFar;
// shaders/window_depth.glsl): perspective over [nearDepth, farDepth], world units along the camera axis,
// enclosing the volume box.
struct DepthRange {
  double nearDepth = 0.0, farDepth = 1.0;
};
DepthRange windowDepthRange(const Camera& camera, glm::dvec3 volumeMax);

// A pixel rectangle of the image (row 0 at the top).
struct PixelRect {
  uint32_t x = 0, y = 0, width = 0, height = 0;
};

// The compute entry points (shaders/compute_tile.glsl). Binds the target's color and world-depth textures to
// the image units the rays store into (kRaycastColorImageUnit, kRaycastDepthImageUnit), write only.
void bindComputeTargets(const RenderTarget& target);
// Casts the rays of `tile` with `program`, which must be in use: its tile uniforms, then one dispatch of
// kRaycastWorkgroupSize-square workgroups covering the tile. Nothing for an empty tile.
void dispatchComputeTile(const ShaderProgram& program, const PixelRect& tile);
// After a frame's last dispatch: makes the image stores visible to what reads the targets next (texture
// fetches, readbacks, framebuffer use).
void finishComputeWrites();

// The GL buffer of a RaycastBlock, bound to kRaycastBlockBinding.
class RaycastBlockBuffer {
 public:
  RaycastBlockBuffer();
  ~RaycastBlockBuffer();
  RaycastBlockBuffer(const RaycastBlockBuffer&) = delete;
  RaycastBlockBuffer& operator=(const RaycastBlockBuffer&) = delete;

  // One buffer update, then binds the buffer to kRaycastBlockBinding.
  void upload(const RaycastBlock& block);
  // Binds the buffer to kRaycastBlockBinding again (after another pass used the binding point).
  void bind() const;

 private:
  uint32_t buffer_ = 0;
};

}  // namespace ropecast
