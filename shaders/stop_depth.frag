#version 450 core
// Copies the compute entry point's stop depths (shaders/raycast.comp uStopDepthImage, world units) of a
// finished tile into the depth buffer, as window depth, so that the occlusion queries issued after that tile
// test against it as they do after the fragment entry point (Gobbetti et al. 2008, Sect. 6). Drawn with
// shaders/raycast.vert over the tile, depth test ALWAYS, no color writes.

#include "shaders/raycast_block.h"
#include "shaders/window_depth.glsl"

layout(binding = 0) uniform sampler2D uStopDepth;

void main() { gl_FragDepth = windowDepth(texelFetch(uStopDepth, ivec2(gl_FragCoord.xy), 0).r); }
