// Where a brick lies in the pool texture: the GLSL twin of BrickPoolGeometry::slotOrigin (render/brick_pool.h),
// slots numbered x fastest over a grid of slotGrid slots of slotEdge texels per axis. No #version line.

// Texel origin of a pool slot. In float, since integer vector division is slow on some implementations; exact
// while slot < kMaxPoolSlots = 2^21: the quotients lie at least 0.5 / (slots per layer) from an integer, far
// more than their rounding error (tests/render/brick_pool_gltest.cpp checks every slot).
vec3 poolSlotOrigin(uint slot, uvec3 slotGrid, float slotEdge) {
  float perRow = float(slotGrid.x);
  float perLayer = float(slotGrid.x * slotGrid.y);
  float s = float(slot);
  float z = floor((s + 0.5) / perLayer);
  float inLayer = s - z * perLayer;
  float y = floor((inLayer + 0.5) / perRow);
  return vec3(inLayer - y * perRow, y, z) * slotEdge;
}
