#version 450 core
// Test shader of tests/index/rope_traversal_gltest.cpp: walks one ray per invocation with
// shaders/rope_traversal.glsl and records every leaf it reports, to compare with the CPU reference.
#include "shaders/rope_traversal.glsl"

layout(local_size_x = 64) in;

// Two vec4 per ray: (origin, tStart), (dir, tEnd).
layout(std430, binding = 0) readonly buffer Rays { vec4 rays[]; };
// uMaxHits slots per ray: (leafIndex, bits of tEnter, bits of tExit, depth << 8 | kind).
layout(std430, binding = 1) writeonly buffer Hits { uvec4 hits[]; };
layout(std430, binding = 2) writeonly buffer Counts { uint counts[]; };

uniform uint uRayCount;
uniform uint uMaxHits;

void main() {
  uint ray = gl_GlobalInvocationID.x;
  if (ray >= uRayCount) return;
  vec4 a = rays[2u * ray];
  vec4 b = rays[2u * ray + 1u];
  uint count = 0u;
  RopeCursor cursor;
  if (ropeBegin(cursor, a.xyz, b.xyz, a.w, b.w)) {
    RopeLeaf leaf;
    while (ropeNextLeaf(cursor, leaf)) {
      if (count < uMaxHits)
        hits[ray * uMaxHits + count] =
            uvec4(leaf.leafIndex, floatBitsToUint(leaf.tEnter), floatBitsToUint(leaf.tExit),
                  (leaf.depth << 8u) | leaf.kind);
      ++count;
    }
  }
  counts[ray] = count;
}
