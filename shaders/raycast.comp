#version 450 core
// Compute entry point of the ray caster: 8x8 workgroups over the image (or over uTileOrigin + the dispatched
// range), one ray per invocation, results stored with imageStore. Same castRay as the fragment entry point.

#include "shaders/raycast_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba32f, binding = 0) uniform writeonly image2D uColorImage;
layout(r32f, binding = 1) uniform writeonly image2D uDepthImage;
layout(location = 0) uniform uvec2 uTileOrigin;

void main() {
  uvec2 pixel = uTileOrigin + gl_GlobalInvocationID.xy;
  if (any(greaterThanEqual(pixel, raycast.imageSize))) return;
  RayResult r = castRay(pixel);
  imageStore(uColorImage, ivec2(pixel), r.color);
  imageStore(uDepthImage, ivec2(pixel), vec4(r.depth));
}
