#version 450 core
// Fragment entry point of the brute-force ray caster (shaders/brute_force_common.glsl): one ray per fragment of
// one triangle over the viewport (shaders/brute_force.vert).

#include "shaders/brute_force_common.glsl"

layout(location = 0) out vec4 outColor;
layout(location = 1) out float outDepth;

void main() {
  RayResult r = castBrute(uvec2(gl_FragCoord.xy));
  outColor = r.color;
  outDepth = r.depth;
}
