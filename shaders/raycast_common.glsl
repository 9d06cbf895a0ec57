// castRay(pixel): the single-pass ray cast of one pixel (Gobbetti et al. 2008, Sect. 5.2, Fig. 5;
// docs/RENDERING.md), shared by the fragment (shaders/raycast.frag) and compute (shaders/raycast.comp) entry
// points. The camera ray is clipped to the volume box and walked leaf by leaf with the rope traversal
// (shaders/rope_traversal.glsl); empty leaves are skipped, and each data leaf is one segment sampled at the
// leaf's level on the step grid anchored at the volume entry. No #version line: the entry point has it.
//
// Variants (defines, from render/raycast_uniforms.cpp raycastDefines): RAYCAST_MODE_ISO or RAYCAST_MODE_DVR;
// BRICK_BORDER; ISO_BISECTION_STEPS; TF_ENTRIES; DVR_SHADE_GRADIENT_THRESHOLD; DVR_STORED_GRADIENTS (DVR samples
// a GradientPool, render/gradient_pool.h).

#include "shaders/rope_traversal.glsl"
#include "shaders/brick_pool.glsl"
#include "shaders/compositing.glsl"

// The segment of a data leaf: its brick's texels in the pool and the sampling of its level L = maxDepth - depth.
// Root-cube coordinates u = x / (C s) keep the world t (docs/RENDERING.md "Spaces"); a leaf at depth d holds
// B 2^d level-L samples per cube unit, the first at the leaf's boxMin, behind BRICK_BORDER texels of border.
Segment leafSegment(RopeLeaf leaf, vec3 originCube, vec3 dirCube) {
  float levelScale = ldexp(1.0, int(raycast.maxDepth - leaf.depth));  // 2^L
  float texelsPerCube = raycast.brickSize * ldexp(1.0, int(leaf.depth));
  vec3 slotOrigin = poolSlotOrigin(leaf.brickSlot, raycast.poolSlotGrid, raycast.poolSlotEdge);
  Segment s;
  s.texelAtZero = (originCube - leaf.boxMin) * texelsPerCube + float(BRICK_BORDER);
  s.texelPerT = dirCube * texelsPerCube;
  s.texelMin = slotOrigin;
  s.texelCount = vec3(raycast.poolSlotEdge);
  s.coordAtZero = (slotOrigin + s.texelAtZero) * raycast.valueTexelSize;
  s.coordPerT = s.texelPerT * raycast.valueTexelSize;
  s.gradientScale = 1.0 / (2.0 * raycast.spacing * levelScale);
  s.dt = raycast.stepVoxels * levelScale * raycast.minSpacing;
  s.opacityExponent = raycast.stepVoxels * levelScale;
  return s;
}

RayResult castRay(uvec2 pixel) {
  Ray ray;
  if (!cameraRay(pixel, ray)) return missedRay();
  vec3 originCube = ray.origin / raycast.cubeWorld;
  vec3 dirCube = ray.dir / raycast.cubeWorld;

  RopeCursor cursor;
  RopeLeaf leaf;
  ropeBegin(cursor, originCube, dirCube, ray.t0, ray.t1);  // a ray that misses the root cube gets no leaf
  bool firstLeaf = true;
#ifdef RAYCAST_MODE_ISO
  IsoMarch march = isoMarchBegin();
  Segment hitSegment;
  while (!march.hit && ropeNextLeaf(cursor, leaf)) {
    bool entry = firstLeaf;
    firstLeaf = false;
    if (leaf.kind != kRopeTagDataLeaf) continue;
    Segment s = leafSegment(leaf, originCube, dirCube);
    marchIso(march, s, ray.t0, firstSampleIndex(ray.t0, leaf.tEnter, s.dt, entry), min(leaf.tExit, ray.t1));
    if (march.hit) hitSegment = s;
  }
  return march.hit ? shadeIsoHit(march, hitSegment, ray) : missedRay();
#else
  DvrAccum acc = dvrAccumBegin();
  while (ropeNextLeaf(cursor, leaf)) {
    bool entry = firstLeaf;
    firstLeaf = false;
    if (leaf.kind != kRopeTagDataLeaf) continue;
    Segment s = leafSegment(leaf, originCube, dirCube);
    float kBegin = firstSampleIndex(ray.t0, leaf.tEnter, s.dt, entry);
    float kEnd = firstSampleIndex(ray.t0, min(leaf.tExit, ray.t1), s.dt, false);
    if (compositeDvr(acc, s, ray, kBegin, kEnd)) break;
  }
  return dvrResult(acc);
#endif
}
