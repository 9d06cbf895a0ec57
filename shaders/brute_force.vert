#version 450 core
// Vertex stage of the brute-force ray caster (render/brute_force_pass): one triangle covering the viewport.

void main() {
  vec2 p = vec2(float((gl_VertexID & 1) << 2), float((gl_VertexID & 2) << 1)) - 1.0;
  gl_Position = vec4(p, 0.0, 1.0);
}
