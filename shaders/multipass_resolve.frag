#version 450 core
// The last pass of the multi-pass renderer (render/multipass_pass.h), over the whole viewport: the background
// under the accumulated color, C + (1 - A) background (docs/RENDERING.md "Output"), in place; for a maximum
// intensity projection, the largest value through the transfer function (mipResult), for an average one the
// mean (aipResult).

// The shader loader's #include is textual and once per file, whatever the #if around it: both variants
// include the same.
#include "shaders/compositing.glsl"

#ifdef RAYCAST_MODE_MIP
layout(rgba32f, binding = 0) uniform writeonly image2D uAccum;
layout(r32f, binding = 1) uniform image2D uDepth;
layout(rgba32f, binding = 2) uniform readonly image2D uMarch;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 state = imageLoad(uMarch, pixel);
  float depth = imageLoad(uDepth, pixel).r;
  // The depth of the maximum is stored, not its t: one unit along the camera axis per unit "t".
  RayResult r = mipResult(MipMax(state.y != 0.0 ? state.x : mipBegin().value, depth), 1.0);
  imageStore(uAccum, pixel, r.color);
  imageStore(uDepth, pixel, vec4(r.depth));
}
#elif defined(RAYCAST_MODE_AIP)
layout(rgba32f, binding = 0) uniform writeonly image2D uAccum;
layout(r32f, binding = 1) uniform image2D uDepth;
layout(rgba32f, binding = 2) uniform readonly image2D uMarch;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 state = imageLoad(uMarch, pixel);
  // The first sample's depth is stored, not its t: one unit along the camera axis per unit "t".
  RayResult r = aipResult(AipSum(state.x, imageLoad(uDepth, pixel).r, state.z != 0.0), state.y, 1.0);
  imageStore(uAccum, pixel, r.color);
  imageStore(uDepth, pixel, vec4(r.depth));
}
#else
layout(rgba32f, binding = 0) uniform image2D uAccum;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 accum = imageLoad(uAccum, pixel);
  imageStore(uAccum, pixel, vec4(accum.rgb + (1.0 - accum.a) * raycast.background, accum.a));
}
#endif
