#version 450 core
// Fragment entry point of the ray caster: one ray per fragment of a screen tile (render/raycast_pass.cpp draws
// the tiles one by one, so occlusion queries can be issued between them). Writes color, world depth and a
// window-space gl_FragDepth (perspective over [depthNear, depthFar]; 1 for a miss).

#include "shaders/raycast_common.glsl"

layout(location = 0) out vec4 outColor;
layout(location = 1) out float outDepth;

void main() {
  RayResult r = castRay(uvec2(gl_FragCoord.xy));
  outColor = r.color;
  outDepth = r.depth;
  if (isinf(r.depth)) {
    gl_FragDepth = 1.0;
  } else {
    float near = raycast.depthNear, far = raycast.depthFar;
    float d = max(r.depth, near);
    float ndc = (far + near) / (far - near) - 2.0 * far * near / ((far - near) * d);
    gl_FragDepth = clamp(0.5 * ndc + 0.5, 0.0, 1.0);
  }
}
