#version 450 core
// Early ray termination across the blocks of the multi-pass renderer (render/multipass_pass.h): drawn over a
// block's box after it, this pass keeps the fragments whose ray has ended (opacity >= --ert, or an isosurface
// hit), which write their depth, and discards the others; the later blocks' fragments there fail the depth
// test and are never shaded, as multi-pass ray casters terminate rays (Krüger and Westermann 2003).

#include "shaders/raycast_block.h"

#if defined(RAYCAST_MODE_ISO) || defined(RAYCAST_MODE_MIP)
layout(rgba32f, binding = 2) uniform readonly image2D uMarch;
#else
layout(rgba32f, binding = 0) uniform readonly image2D uAccum;
#endif

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
#ifdef RAYCAST_MODE_ISO
  bool ended = imageLoad(uMarch, pixel).w != 0.0;
#elif defined(RAYCAST_MODE_MIP)
  vec4 state = imageLoad(uMarch, pixel);  // a maximum that reaches the cut's largest value is final
  bool ended = state.y != 0.0 && state.x >= raycast.leafMaximaLargest;
#elif defined(RAYCAST_MODE_AIP) || defined(RAYCAST_MODE_SLICE)
  bool ended = false;  // a mean takes every sample; a slice's one sample lies in one block
#else
  bool ended = imageLoad(uAccum, pixel).a >= raycast.ert;
#endif
  if (!ended) discard;
}
