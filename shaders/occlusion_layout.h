// The occlusion queries' two shader storage buffers, laid out once for C++ (render/occlusion_queries.cpp
// fills and reads them back) and GLSL (shaders/occlusion_box.vert and .frag draw and count, through the
// shader loader's textual #include). Layout only; any thread.
//   boxes   kOcclusionBoxBinding, read by the vertex shader: one OcclusionBoxRecord per box drawn (an
//           instance), the index of the query it counts for beside its corners;
//   counts  kOcclusionCountBinding: one word per query, the samples of its boxes that passed the depth test.
#ifndef ROPECAST_SHADERS_OCCLUSION_LAYOUT_H
#define ROPECAST_SHADERS_OCCLUSION_LAYOUT_H

#ifdef __cplusplus
#include <cstdint>

namespace ropecast {
#define OCCLUSION_CONST inline constexpr std::uint32_t
#else
#define OCCLUSION_CONST const uint
#endif

// Shader storage binding points (the ray cast's feedback buffer holds kFeedbackBinding = 1 meanwhile).
OCCLUSION_CONST kOcclusionBoxBinding = 2u;
OCCLUSION_CONST kOcclusionCountBinding = 3u;

#ifdef __cplusplus
// std430: a vec3 is aligned to 16 bytes, so a uint fits after each.
struct OcclusionBoxRecord {
  float lo[3];
  std::uint32_t query;  // index into the counts
  float hi[3];
  std::uint32_t unused;
};
static_assert(sizeof(OcclusionBoxRecord) == 32, "std430 layout of OcclusionBoxRecord");
}  // namespace ropecast
#else
struct OcclusionBoxRecord {
  vec3 lo;
  uint query;
  vec3 hi;
  uint unused;
};
#endif

#undef OCCLUSION_CONST

#endif  // ROPECAST_SHADERS_OCCLUSION_LAYOUT_H
