// The part the compute entry points of the ray casters share (shaders/raycast.comp, shaders/brute_force.comp):
// kRaycastWorkgroupSize-square workgroups over a screen tile [uTileOrigin, uTileEnd), one ray per invocation,
// its color and world depth stored into the pass's RenderTarget with imageStore. The C++ side:
// bindComputeTargets, dispatchComputeTile and finishComputeWrites (render/raycast_uniforms.h).
// No #version line; include after shaders/compositing.glsl (RayResult).

layout(local_size_x = kRaycastWorkgroupSize, local_size_y = kRaycastWorkgroupSize) in;
layout(rgba32f, binding = kRaycastColorImageUnit) uniform writeonly image2D uColorImage;
layout(r32f, binding = kRaycastDepthImageUnit) uniform writeonly image2D uDepthImage;
layout(location = kRaycastTileOriginLocation) uniform uvec2 uTileOrigin;
layout(location = kRaycastTileEndLocation) uniform uvec2 uTileEnd;  // one past the tile's last pixel

// The pixel of this invocation; false for the invocations of the last workgroups that lie past the tile or
// the image.
bool tilePixel(out uvec2 pixel) {
  pixel = uTileOrigin + gl_GlobalInvocationID.xy;
  return all(lessThan(pixel, min(uTileEnd, raycast.imageSize)));
}

void storeRayResult(uvec2 pixel, RayResult r) {
  imageStore(uColorImage, ivec2(pixel), r.color);
  imageStore(uDepthImage, ivec2(pixel), vec4(r.depth));
}
