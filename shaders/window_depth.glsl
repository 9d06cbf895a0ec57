// Window depth of a world depth along the camera axis: the perspective mapping over [depthNear, depthFar] of
// shaders/raycast_block.h, the one render/occlusion_queries.cpp projects its boxes with, so the boxes' depth
// test compares like with like. +inf (the ray left the volume) maps to 1, the far plane. No #version line.

float windowDepth(float worldDepth) {
  if (isinf(worldDepth)) return 1.0;
  float near = raycast.depthNear, far = raycast.depthFar;
  float d = max(worldDepth, near);
  float ndc = (far + near) / (far - near) - 2.0 * far * near / ((far - near) * d);
  return clamp(0.5 * ndc + 0.5, 0.0, 1.0);
}
