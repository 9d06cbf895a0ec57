#version 450 core
// Fragment entry point of the ray caster: one ray per fragment of a screen tile (render/raycast_pass.cpp draws
// the tiles one by one, so occlusion queries can be issued between them). Writes color, world depth and, as
// gl_FragDepth, the window depth where the ray stopped (shaders/window_depth.glsl; 1 when it left the volume),
// which the occlusion queries test their boxes against.

#include "shaders/raycast_common.glsl"
#include "shaders/window_depth.glsl"

layout(location = 0) out vec4 outColor;
layout(location = 1) out float outDepth;

void main() {
  RayResult r = castRay(uvec2(gl_FragCoord.xy));
  outColor = r.color;
  outDepth = r.depth;
  gl_FragDepth = windowDepth(r.stopDepth);
}
