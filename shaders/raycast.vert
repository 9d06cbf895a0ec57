#version 450 core
// Vertex stage of the fragment entry point: one triangle of 3 vertices from gl_VertexID, (0,0), (2,0), (0,2) in
// units of the screen tile uTileRect (pixels: x, y, width, height), so that it covers the tile; the scissor cuts
// it to the tile. Pixel rows of the targets are image rows (row 0 = top), so no flip: framebuffer row r holds
// image row r.

#include "shaders/raycast_block.h"

layout(location = 0) uniform uvec4 uTileRect;

void main() {
  vec2 corner = vec2(float((gl_VertexID & 1) << 1), float(gl_VertexID & 2));
  vec2 pixel = vec2(uTileRect.xy) + corner * vec2(uTileRect.zw);
  gl_Position = vec4(pixel / vec2(raycast.imageSize) * 2.0 - 1.0, 0.0, 1.0);
}
