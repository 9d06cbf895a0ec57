// The colors of docs/RENDERING.md: the transfer function lookup with its opacity correction, and the Phong
// headlight of the isosurface and of shaded DVR samples. The CPU mirror (reference/cpu_raycaster.cpp) computes the
// same in double. No #version line. Needs the defines TF_ENTRIES and DVR_SHADE_GRADIENT_THRESHOLD.

#include "shaders/raycast_block.h"

layout(binding = kRaycastTfUnit) uniform sampler1D uTransferFunction;  // RGBA32F, straight color, LINEAR

// The transfer function at normalized value v: linear between its N entries, texcoord (v (N-1) + 0.5) / N.
vec4 transferFunction(float v) {
  const float n = float(TF_ENTRIES);
  return textureLod(uTransferFunction, (clamp(v, 0.0, 1.0) * (n - 1.0) + 0.5) / n, 0.0);
}

// The opacity of a step of opacityExponent level-0 voxels, from the table's opacity of one.
float correctedOpacity(float alpha, float opacityExponent) { return 1.0 - pow(1.0 - alpha, opacityExponent); }

// The Phong headlight (light and viewer at the eye: L = V = -dir, R = reflect(-L, N)).
struct Headlight {
  float nDotL;
  float rDotV;
};

Headlight headlight(vec3 n, vec3 dir) {
  vec3 l = -dir;
  return Headlight(dot(n, l), dot(reflect(-l, n), l));
}

// The isosurface's color from its gradient: normal -g / |g| (-dir where g vanishes), facing the viewer.
vec3 shadeIso(vec3 gradient, vec3 dir) {
  float len = length(gradient);
  vec3 n = len > 0.0 ? -gradient / len : -dir;
  if (dot(n, -dir) < 0.0) n = -n;
  Headlight h = headlight(n, dir);
  return raycast.isoBaseColor * (raycast.ambient + raycast.diffuse * max(h.nDotL, 0.0)) +
         vec3(raycast.specular * pow(max(h.rDotV, 0.0), raycast.shininess));
}

// A DVR sample's color, shaded two-sided where the gradient is large enough to give a normal.
vec3 shadeDvr(vec3 color, vec3 gradient, vec3 dir) {
  float len = length(gradient);
  if (!(len * raycast.minSpacing > DVR_SHADE_GRADIENT_THRESHOLD)) return color;
  Headlight h = headlight(-gradient / len, dir);
  return color * (raycast.ambient + raycast.diffuse * abs(h.nDotL)) +
         vec3(raycast.specular * pow(abs(h.rDotV), raycast.shininess));
}
