// The ray casters' uniforms, one std140 block defined once for C++ (render/raycast_uniforms.cpp fills it and
// uploads it with one buffer update per frame) and GLSL (shaders/sampling.glsl includes this file through the
// shader loader's textual #include), after the nvpro-samples host_device.h pattern; and the binding points of
// the block and of the textures the ray casters sample. Layout only; any thread. Both passes share it:
// RaycastPass (the rope walk, shaders/raycast_common.glsl) and BruteForcePass
// (shaders/brute_force_common.glsl), which leaves the pool and index fields zero.
//
// std140: a vec3 starts at a multiple of 16 bytes and takes 12, so each is followed by one scalar; the C++
// side aliases glm types and checks every offset below (and tests/render/raycast_block_gltest.cpp checks them
// against the GLSL compiler).
#ifndef ROPECAST_SHADERS_RAYCAST_BLOCK_H
#define ROPECAST_SHADERS_RAYCAST_BLOCK_H

#ifdef __cplusplus
#include <cstddef>
#include <cstdint>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace ropecast {
namespace glsl {
using uint = std::uint32_t;
using vec3 = glm::vec3;
using uvec2 = glm::uvec2;
using uvec3 = glm::uvec3;
}  // namespace glsl
#define RAYCAST_CONST inline constexpr int
#define RAYCAST_BLOCK_BEGIN struct alignas(16) RaycastBlock {
#define RAYCAST_BLOCK_END };
#else
#define RAYCAST_CONST const int
#endif

// Binding points: the uniform block, and the texture units (layout(binding = ...) in GLSL).
RAYCAST_CONST kRaycastBlockBinding = 0;
RAYCAST_CONST kRaycastValueUnit = 0;      // values: the brick pool, or brute force's level-0 volume (R8/R16)
RAYCAST_CONST kRaycastTfUnit = 1;         // the transfer function table (RGBA32F, 1D)
RAYCAST_CONST kRaycastRopeIndexUnit = 2;  // the rope index (shaders/rope_traversal.glsl's uRopeIndex)
RAYCAST_CONST kRaycastSampleUnit = 3;     // the DVR sample texture beside the values (render/gradient_pool.h)
RAYCAST_CONST kRaycastLeafMaximaUnit = 4;  // MIP: each leaf's largest value (uLeafMaxima, R32UI float bits)
// The compute entry points' image units (shaders/compute_tile.glsl, shaders/raycast.comp).
RAYCAST_CONST kRaycastColorImageUnit = 0;      // RGBA32F: the pixel's color
RAYCAST_CONST kRaycastDepthImageUnit = 1;      // R32F: the depth output
RAYCAST_CONST kRaycastStopDepthImageUnit = 2;  // R32F: where the ray stopped, for the occlusion queries
// The compute entry points' workgroups (pixels per side) and the uniform locations of their tile.
RAYCAST_CONST kRaycastWorkgroupSize = 8;
RAYCAST_CONST kRaycastTileOriginLocation = 0;  // uvec2 uTileOrigin: the tile's first pixel
RAYCAST_CONST kRaycastTileEndLocation = 1;     // uvec2 uTileEnd: one past the tile's last pixel

#ifndef __cplusplus
#define RAYCAST_BLOCK_BEGIN layout(std140, binding = kRaycastBlockBinding) uniform RaycastBlock {
#define RAYCAST_BLOCK_END } raycast;
#else
namespace glsl {
#endif

RAYCAST_BLOCK_BEGIN
  // Camera (core/camera.h pixelRay): eye, orthonormal frame, the pinhole's extent and the image.
  vec3 eye;                  // offset 0
  float tanHalfFov;          // 12
  vec3 forward;              // 16
  float aspect;              // 28: width / height
  vec3 right;                // 32
  float depthNear;           // 44: the fragment entry point's window depth range (world units)
  vec3 up;                   // 48
  float depthFar;            // 60
  uvec2 imageSize;           // 64: pixels
  float stepVoxels;          // 72: --step, in level-L samples
  float ert;                 // 76: early ray termination opacity
  // Volume geometry in world units (docs/RENDERING.md "Spaces"). The rays are clipped to [clipMin, clipMax]:
  // the volume box [0, n s] cut to --crop (sampledWorldBox, core/render_params.h).
  vec3 clipMax;              // 80
  float minSpacing;          // 92: min(s)
  vec3 spacing;              // 96: s
  float isoValue;            // 108: normalized, mapping.toStored(V) / storedMax
  vec3 cubeWorld;            // 112: C s, the root cube's extent
  float brickSize;           // 124: B
  // The value texture and the brick pool in it.
  vec3 valueTexelSize;       // 128: 1 / the value texture's dimensions
  uint maxDepth;             // 140: depth of the full-resolution leaves
  uvec3 poolSlotGrid;        // 144: slots per axis
  float poolSlotEdge;        // 156: texels per slot per axis, B + 2 BRICK_BORDER
  // Render parameters and lighting (RenderParams, LightingParams).
  vec3 background;           // 160
  float ambient;             // 172: ka
  vec3 isoBaseColor;         // 176
  float diffuse;             // 188: kd
  float specular;            // 192: ks
  float shininess;           // 196
  // Feedback (shaders/feedback.glsl, RAYCAST_FEEDBACK): a leaf of level L > 0 is requested where the ray
  // enters it closer than 2^L feedbackRequestDistance, the distance clamped below at feedbackMinDistance.
  float feedbackRequestDistance;  // 200: voxelsPerPixel maxSpacing imageHeight / (2 tanHalfFov)
  float feedbackMinDistance;      // 204: 0.5 minSpacing
  vec3 clipMin;                   // 208
  // --clip-plane (ClipPlane): the rays sample where dot(clipPlaneNormal, x) >= clipPlaneOffset (a slice: the
  // plane itself) and, with --slab, <= clipPlaneFar (+inf without); a zero normal clips nothing.
  float clipPlaneOffset;          // 220
  vec3 clipPlaneNormal;           // 224
  // MIP: the leaves [0, leafMaximaCount) of the cut have their largest value in uLeafMaxima; 0: none known.
  uint leafMaximaCount;           // 236
  // MIP: the largest of those values (above 1 when none is known): a ray whose maximum reaches it ends.
  float leafMaximaLargest;        // 240
  // Isosurface caps (core/render_params.h capBoundsOf): bit b when a ray entering through bound b of the
  // drawn part (0-2 the crop box's lower faces, 3-5 its upper faces, 6 the clip plane, 7 a slab's far face) is
  // capped; 0: none.
  uint capBounds;                 // 244
  float clipPlaneFar;             // 248
  float unused2;                  // 252: std140 padding
RAYCAST_BLOCK_END

#ifdef __cplusplus
static_assert(sizeof(RaycastBlock) == 256);
static_assert(offsetof(RaycastBlock, eye) == 0 && offsetof(RaycastBlock, tanHalfFov) == 12);
static_assert(offsetof(RaycastBlock, forward) == 16 && offsetof(RaycastBlock, aspect) == 28);
static_assert(offsetof(RaycastBlock, right) == 32 && offsetof(RaycastBlock, depthNear) == 44);
static_assert(offsetof(RaycastBlock, up) == 48 && offsetof(RaycastBlock, depthFar) == 60);
static_assert(offsetof(RaycastBlock, imageSize) == 64 && offsetof(RaycastBlock, stepVoxels) == 72 &&
              offsetof(RaycastBlock, ert) == 76);
static_assert(offsetof(RaycastBlock, clipMax) == 80 && offsetof(RaycastBlock, minSpacing) == 92);
static_assert(offsetof(RaycastBlock, spacing) == 96 && offsetof(RaycastBlock, isoValue) == 108);
static_assert(offsetof(RaycastBlock, cubeWorld) == 112 && offsetof(RaycastBlock, brickSize) == 124);
static_assert(offsetof(RaycastBlock, valueTexelSize) == 128 && offsetof(RaycastBlock, maxDepth) == 140);
static_assert(offsetof(RaycastBlock, poolSlotGrid) == 144 && offsetof(RaycastBlock, poolSlotEdge) == 156);
static_assert(offsetof(RaycastBlock, background) == 160 && offsetof(RaycastBlock, ambient) == 172);
static_assert(offsetof(RaycastBlock, isoBaseColor) == 176 && offsetof(RaycastBlock, diffuse) == 188);
static_assert(offsetof(RaycastBlock, specular) == 192 && offsetof(RaycastBlock, shininess) == 196);
static_assert(offsetof(RaycastBlock, feedbackRequestDistance) == 200 &&
              offsetof(RaycastBlock, feedbackMinDistance) == 204);
static_assert(offsetof(RaycastBlock, clipMin) == 208 && offsetof(RaycastBlock, clipPlaneOffset) == 220);
static_assert(offsetof(RaycastBlock, clipPlaneNormal) == 224 &&
              offsetof(RaycastBlock, leafMaximaCount) == 236);
static_assert(offsetof(RaycastBlock, leafMaximaLargest) == 240 && offsetof(RaycastBlock, capBounds) == 244 &&
              offsetof(RaycastBlock, clipPlaneFar) == 248 && offsetof(RaycastBlock, unused2) == 252);
}  // namespace glsl
using glsl::RaycastBlock;
}  // namespace ropecast
#endif

#undef RAYCAST_CONST
#undef RAYCAST_BLOCK_BEGIN
#undef RAYCAST_BLOCK_END

#endif  // ROPECAST_SHADERS_RAYCAST_BLOCK_H
