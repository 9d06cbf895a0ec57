#version 450 core
// The axis-aligned boxes of the occlusion queries (render/occlusion_queries.cpp), one instance each, read
// from the boxes buffer: 36 vertices from gl_VertexID, 12 triangles wound counter-clockwise seen from
// outside, projected by uViewProjection (the ray caster's camera, depth as shaders/window_depth.glsl maps it).

#include "shaders/occlusion_layout.h"

layout(location = 0) uniform mat4 uViewProjection;

layout(std430, binding = kOcclusionBoxBinding) readonly buffer OcclusionBoxes {
  OcclusionBoxRecord boxes[];
};

flat out uint vQuery;

// Per face (-x, +x, -y, +y, -z, +z) two triangles over the corners, corner bit 0 = x, 1 = y, 2 = z.
const int kCorners[36] = int[36](0, 4, 6, 0, 6, 2,   // -x
                                 1, 3, 7, 1, 7, 5,   // +x
                                 0, 1, 5, 0, 5, 4,   // -y
                                 2, 6, 7, 2, 7, 3,   // +y
                                 0, 2, 3, 0, 3, 1,   // -z
                                 4, 5, 7, 4, 7, 6);  // +z

void main() {
  const OcclusionBoxRecord box = boxes[gl_InstanceID];
  const int c = kCorners[gl_VertexID];
  const vec3 corner = mix(box.lo, box.hi, vec3(c & 1, (c >> 1) & 1, (c >> 2) & 1));
  vQuery = box.query;
  gl_Position = uViewProjection * vec4(corner, 1.0);
}
