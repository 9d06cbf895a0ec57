#version 450 core
// Counts, per query, the samples of its boxes that pass the depth test: a GL_SAMPLES_PASSED query for every
// node at once, in one draw. The depth test runs before this shader (early_fragment_tests), so a fragment
// behind the ray caster's depth never reaches the counter.

#include "shaders/occlusion_layout.h"

layout(early_fragment_tests) in;

layout(std430, binding = kOcclusionCountBinding) buffer OcclusionCounts {
  uint counts[];
};

flat in uint vQuery;

void main() {
  atomicAdd(counts[vQuery], 1u);
}
