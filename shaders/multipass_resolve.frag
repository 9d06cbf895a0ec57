#version 450 core
// The last pass of the multi-pass renderer (render/multipass_pass.h), over the whole viewport: the background
// under the accumulated color, C + (1 - A) background (docs/RENDERING.md "Output"), in place.

#include "shaders/raycast_block.h"

layout(rgba32f, binding = 0) uniform image2D uAccum;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 accum = imageLoad(uAccum, pixel);
  imageStore(uAccum, pixel, vec4(accum.rgb + (1.0 - accum.a) * raycast.background, accum.a));
}
