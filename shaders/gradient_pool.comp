#version 450 core
// Derives the DVR sample texture (render/gradient_pool.h) of one region of a value texture: per texel
// (v(i+e_x) - v(i-e_x), v(i+e_y) - v(i-e_y), v(i+e_z) - v(i-e_z), v(i)), neighbours clamped to the region.
// Linear filtering of these central differences at a point p equals the difference of the filtered values at
// p +- one texel (filtering is linear and shifts with the texels), so one lookup gives the DVR walk the value
// and the gradient that seven lookups of the value texture gave, as long as p +- one texel stays in the
// region (pool slots: BRICK_BORDER >= 2).

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;

uniform sampler3D uValues;  // R8/R16 UNORM
layout(rgba16_snorm, binding = 0) uniform writeonly image3D uSamples;
uniform ivec3 uOrigin;  // the region in texels
uniform ivec3 uExtent;

float valueAt(ivec3 p) { return texelFetch(uValues, clamp(p, uOrigin, uOrigin + uExtent - 1), 0).r; }

void main() {
  ivec3 i = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(i, uExtent))) return;
  ivec3 p = uOrigin + i;
  vec3 g = vec3(valueAt(p + ivec3(1, 0, 0)) - valueAt(p - ivec3(1, 0, 0)),
                valueAt(p + ivec3(0, 1, 0)) - valueAt(p - ivec3(0, 1, 0)),
                valueAt(p + ivec3(0, 0, 1)) - valueAt(p - ivec3(0, 0, 1)));
  imageStore(uSamples, p, vec4(g, valueAt(p)));
}
