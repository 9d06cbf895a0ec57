#version 450 core
// Compute entry point of the ray caster: one ray per invocation over a screen tile (shaders/compute_tile.glsl),
// the same castRay as the fragment entry point. Where each ray stopped goes to uStopDepthImage, which
// shaders/stop_depth.frag copies into the depth buffer of the occlusion queries.

#include "shaders/raycast_common.glsl"
#include "shaders/compute_tile.glsl"

layout(r32f, binding = kRaycastStopDepthImageUnit) uniform writeonly image2D uStopDepthImage;

void main() {
  uvec2 pixel;
  if (!tilePixel(pixel)) return;
  RayResult r = castRay(pixel);
  storeRayResult(pixel, r);
  imageStore(uStopDepthImage, ivec2(pixel), vec4(r.stopDepth));
}
