#version 450 core
// Compute entry point of the ray caster: 8x8 workgroups over a screen tile [uTileOrigin, uTileEnd), one ray per invocation, results stored with imageStore. Same castRay as the fragment entry point.
// Where each ray stopped goes to uStopDepthImage, which shaders/stop_depth.frag copies into the depth buffer
// of the occlusion queries.

#include "shaders/raycast_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba32f, binding = kRaycastColorImageUnit) uniform writeonly image2D uColorImage;
layout(r32f, binding = kRaycastDepthImageUnit) uniform writeonly image2D uDepthImage;
layout(r32f, binding = kRaycastStopDepthImageUnit) uniform writeonly image2D uStopDepthImage;
layout(location = 0) uniform uvec2 uTileOrigin;
layout(location = 1) uniform uvec2 uTileEnd;  // one past the tile's last pixel

void main() {
  uvec2 pixel = uTileOrigin + gl_GlobalInvocationID.xy;
  if (any(greaterThanEqual(pixel, min(uTileEnd, raycast.imageSize)))) return;
  RayResult r = castRay(pixel);
  imageStore(uColorImage, ivec2(pixel), r.color);
  imageStore(uDepthImage, ivec2(pixel), vec4(r.depth));
  imageStore(uStopDepthImage, ivec2(pixel), vec4(r.stopDepth));
}
