#version 450 core
// Compute entry point of the brute-force ray caster (shaders/brute_force_common.glsl): one ray per invocation
// over a screen tile (shaders/compute_tile.glsl), the same castBrute as the fragment entry point.

#include "shaders/brute_force_common.glsl"
#include "shaders/compute_tile.glsl"

void main() {
  uvec2 pixel;
  if (!tilePixel(pixel)) return;
  storeRayResult(pixel, castBrute(pixel));
}
