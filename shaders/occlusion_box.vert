#version 450 core
// The axis-aligned boxes of an occlusion query (render/occlusion_queries.cpp), one instance each: 36
// vertices from gl_VertexID, 12 triangles wound counter-clockwise seen from outside, projected by
// uViewProjection (the ray caster's camera, depth as shaders/window_depth.glsl maps it).

layout(location = 0) uniform mat4 uViewProjection;
layout(location = 1) uniform vec3 uBoxLo[8];  // locations 1 to 8
layout(location = 9) uniform vec3 uBoxHi[8];  // locations 9 to 16

// Per face (-x, +x, -y, +y, -z, +z) two triangles over the corners, corner bit 0 = x, 1 = y, 2 = z.
const int kCorners[36] = int[36](0, 4, 6, 0, 6, 2,   // -x
                                 1, 3, 7, 1, 7, 5,   // +x
                                 0, 1, 5, 0, 5, 4,   // -y
                                 2, 6, 7, 2, 7, 3,   // +y
                                 0, 2, 3, 0, 3, 1,   // -z
                                 4, 5, 7, 4, 7, 6);  // +z

void main() {
  int c = kCorners[gl_VertexID];
  vec3 corner = mix(uBoxLo[gl_InstanceID], uBoxHi[gl_InstanceID], vec3(c & 1, (c >> 1) & 1, (c >> 2) & 1));
  gl_Position = uViewProjection * vec4(corner, 1.0);
}
