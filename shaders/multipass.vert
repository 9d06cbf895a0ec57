#version 450 core
// Vertex stage of the multi-pass block renderer (render/multipass_pass.h). Vertices 0-35 are the twelve
// triangles of a box's six faces (two per face); a face whose outside the eye is not on is a back face and
// collapses to a point outside the view, so the front faces alone are rasterized and a convex box covers each
// pixel of its silhouette once. Vertices 36-38 are one triangle over the whole viewport, for a box that reaches
// behind the eye. Every vertex gets the NDC depth uNdcZ, the pass's value for the depth test that carries early
// ray termination across blocks. Framebuffer row r is image row r (row 0 at the top), as in
// shaders/raycast.vert: the projection is core/camera.h pixelRay's, inverted.

#include "shaders/raycast_block.h"

layout(location = 0) uniform vec3 uBoxMin;  // world units, clipped to the volume
layout(location = 1) uniform vec3 uBoxMax;
layout(location = 2) uniform float uNdcZ;

// A face's corners in its plane's two other axes: the quad (0,0) (1,0) (1,1) (0,1) as two triangles.
const vec2 kFaceCorner[6] = vec2[6](vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(0, 1));

vec4 project(vec3 world) {
  vec3 d = world - raycast.eye;
  float x = dot(d, raycast.right), y = dot(d, raycast.up), z = dot(d, raycast.forward);
  return vec4(x / (raycast.tanHalfFov * raycast.aspect), -y / raycast.tanHalfFov, uNdcZ * z, z);
}

void main() {
  if (gl_VertexID >= 36) {
    int id = gl_VertexID - 36;
    vec2 p = vec2(float((id & 1) << 2), float((id & 2) << 1)) - 1.0;
    gl_Position = vec4(p, uNdcZ, 1.0);
    return;
  }
  int face = gl_VertexID / 6;  // axis face / 2, the box's low (even) or high (odd) side
  int axis = face / 2;
  bool high = (face & 1) != 0;
  bool front = high ? raycast.eye[axis] > uBoxMax[axis] : raycast.eye[axis] < uBoxMin[axis];
  if (!front) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    return;
  }
  vec2 c = kFaceCorner[gl_VertexID % 6];
  vec3 corner;
  corner[axis] = high ? uBoxMax[axis] : uBoxMin[axis];
  corner[(axis + 1) % 3] = mix(uBoxMin[(axis + 1) % 3], uBoxMax[(axis + 1) % 3], c.x);
  corner[(axis + 2) % 3] = mix(uBoxMin[(axis + 2) % 3], uBoxMax[(axis + 2) % 3], c.y);
  gl_Position = project(corner);
}
