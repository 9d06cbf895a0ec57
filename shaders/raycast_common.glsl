// castRay(pixel): the single-pass ray cast of one pixel (Gobbetti et al. 2008, Sect. 5.2, Fig. 5;
// docs/RENDERING.md), shared by the fragment (shaders/raycast.frag) and compute (shaders/raycast.comp) entry
// points. The camera ray is clipped to the volume box and walked leaf by leaf with the rope traversal
// (shaders/rope_traversal.glsl); empty leaves are skipped, and each data leaf is one segment sampled at the
// leaf's level on the step grid anchored at the volume entry. No #version line: the entry point has it.
//
// Variants (defines, from render/raycast_uniforms.cpp raycastDefines): RAYCAST_MODE_ISO, _DVR, _MIP (MIP_SIGN
// 1, or -1 for a minimum intensity projection), _AIP or _SLICE;
// BRICK_BORDER; ISO_BISECTION_STEPS; TF_ENTRIES; DVR_SHADE_GRADIENT_THRESHOLD; DVR_DEPTH_OPACITY;
// DVR_STORED_GRADIENTS (DVR samples a GradientPool, render/gradient_pool.h); RAYCAST_FEEDBACK (rays mark the
// leaves they used and request finer ones, shaders/feedback.glsl).

#include "shaders/rope_traversal.glsl"
#include "shaders/brick_pool.glsl"
#include "shaders/compositing.glsl"
#ifdef RAYCAST_FEEDBACK
#include "shaders/feedback.glsl"
#endif

#ifdef RAYCAST_MODE_MIP
// Each leaf's largest value of MIP_SIGN v (render/raycast_pass.h RaycastFrame::leafMaxima), as float bits.
layout(binding = kRaycastLeafMaximaUnit) uniform usamplerBuffer uLeafMaxima;

// Whether no sample of the leaf can raise the ray's maximum: its largest value is no larger. Such a leaf is
// not sampled, so not used: the maximum found in front hides it, as an opaque surface hides what lies behind
// it (docs/RENDERING.md "Maximum intensity projection").
bool leafBelowMaximum(uint leafIndex, float maximum) {
  return leafIndex < raycast.leafMaximaCount &&
         uintBitsToFloat(texelFetch(uLeafMaxima, int(leafIndex)).r) <= maximum;
}
#endif

// The segment of a data leaf: its brick's texels in the pool and the sampling of its level L = maxDepth - depth.
// Root-cube coordinates u = x / (C s) keep the world t (docs/RENDERING.md "Spaces"); a leaf at depth d holds
// B 2^d level-L samples per cube unit, the first at the leaf's boxMin, behind BRICK_BORDER texels of border.
// The sample step of a leaf at depth `depth`: dt = step 2^L min(s).
float leafStep(uint depth) {
  return raycast.stepVoxels * ldexp(1.0, int(raycast.maxDepth - depth)) * raycast.minSpacing;
}

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
  s.dt = leafStep(leaf.depth);
  s.opacityExponent = raycast.stepVoxels * levelScale;
  return s;
}

#if defined(RAYCAST_MODE_DVR) && defined(LLVMPIPE_DVR_LEAF_BATCH)
// The DVR walk for llvmpipe only (RaycastPass sets LLVMPIPE_DVR_LEAF_BATCH on software rasterizers; the gain is
// in docs/BENCHMARKS.md). llvmpipe runs every branch of a loop body for the whole SIMD group under a mask, and
// a loop while any lane is left in it: with one sample loop per leaf, each lane waits at every leaf border for
// the lane with the most samples left in its leaf. This walk gathers up to eight data leaves, then samples
// them in one flat loop in which a lane goes on to its next leaf at once. Its shape is llvmpipe's: the batch
// is eight named variables (a local array lives in memory there, read lane by lane), a leaf is picked by
// selects, three samples are taken per leaf-change check (the check's selects run every iteration), and the
// loops test their exit at the bottom. The samples, their order and their arithmetic are the plain walk's.

// A gathered leaf: its segment's coordinate at t = 0, its first sample index and the first one past it, 2^L.
// The rest of its Segment follows from 2^L (dvrLeafSegment).
struct GatheredLeaf {
  vec3 coordAtZero;
  float kBegin, kEnd;
  float levelScale;
#ifdef RAYCAST_FEEDBACK
  uint leafIndex;
  bool wantsFiner;
#endif
};

// The Segment of a gathered leaf, from the level-0 segment of the ray (exact: 2^L scales exactly).
Segment dvrLeafSegment(GatheredLeaf g, Segment level0) {
  Segment s = level0;
  s.coordAtZero = g.coordAtZero;
  s.coordPerT = level0.coordPerT / g.levelScale;
  s.gradientScale = level0.gradientScale / g.levelScale;
  s.dt = level0.dt * g.levelScale;
  s.opacityExponent = level0.opacityExponent * g.levelScale;
  return s;
}

GatheredLeaf pickLeaf(uint i, GatheredLeaf g1, GatheredLeaf g2, GatheredLeaf g3, GatheredLeaf g4,
                      GatheredLeaf g5, GatheredLeaf g6, GatheredLeaf g7) {
  GatheredLeaf g = g1;
  if (i == 2u) g = g2;
  if (i == 3u) g = g3;
  if (i == 4u) g = g4;
  if (i == 5u) g = g5;
  if (i == 6u) g = g6;
  if (i == 7u) g = g7;
  return g;
}

DvrAccum walkDvrBatched(inout RopeCursor cursor, Ray ray, vec3 originCube, vec3 dirCube) {
  DvrAccum acc = dvrAccumBegin();
#ifdef RAYCAST_FEEDBACK
  RayFeedback fb = rayFeedbackBegin();
#endif
  RopeLeaf leaf;
  // The Segment of a full-resolution leaf, less its position.
  RopeLeaf finest;
  finest.depth = raycast.maxDepth;
  finest.brickSlot = 0u;
  finest.boxMin = vec3(0.0);
  Segment level0 = leafSegment(finest, originCube, dirCube);
  bool entryLeaf = true;
  bool more = cursor.node != kRopeNull;
  while (more) {
    GatheredLeaf g0, g1, g2, g3, g4, g5, g6, g7;
    uint count = 0u;
    do {
      if (!ropeNextLeaf(cursor, leaf)) break;
      bool entry = entryLeaf;
      entryLeaf = false;
      if (leaf.kind != kRopeTagDataLeaf) continue;
      Segment s = leafSegment(leaf, originCube, dirCube);
      GatheredLeaf g;
      g.coordAtZero = s.coordAtZero;
      g.kBegin = firstSampleIndex(ray.t0, leaf.tEnter, s.dt, entry);
      g.kEnd = firstSampleIndex(ray.t0, min(leaf.tExit, ray.t1), s.dt, false);
      g.levelScale = ldexp(1.0, int(raycast.maxDepth - leaf.depth));
#ifdef RAYCAST_FEEDBACK
      g.leafIndex = leaf.leafIndex;
      g.wantsFiner = feedbackWantsFiner(leaf.depth, leaf.tEnter, ray.t0);
#endif
      if (count == 0u) g0 = g;
      if (count == 1u) g1 = g;
      if (count == 2u) g2 = g;
      if (count == 3u) g3 = g;
      if (count == 4u) g4 = g;
      if (count == 5u) g5 = g;
      if (count == 6u) g6 = g;
      if (count == 7u) g7 = g;
      ++count;
    } while (count < 8u && cursor.node != kRopeNull);
    more = cursor.node != kRopeNull;
    if (count == 0u) continue;

    Segment s = dvrLeafSegment(g0, level0);
    float k = g0.kBegin, kEnd = g0.kEnd;
#ifdef RAYCAST_FEEDBACK
    // A leaf is used when sampling moves on to it with samples to take: the ray has not ended before it.
    if (k < kEnd) feedbackSampled(fb, g0.leafIndex, g0.wantsFiner);
    uint sampledLeaf = g0.leafIndex;
#endif
    uint next = 1u;
    for (;;) {
      bool terminated = false;
      if (k < kEnd) terminated = compositeDvrSample(acc, s, ray, k++);
      if (!terminated && k < kEnd) terminated = compositeDvrSample(acc, s, ray, k++);
      if (!terminated && k < kEnd) terminated = compositeDvrSample(acc, s, ray, k++);
      if (terminated) {
#ifdef RAYCAST_FEEDBACK
        feedbackHit(sampledLeaf);
#endif
        return acc;
      }
      if (!(k < kEnd)) {
        if (next == count) break;
        GatheredLeaf g = pickLeaf(next, g1, g2, g3, g4, g5, g6, g7);
        s = dvrLeafSegment(g, level0);
        k = g.kBegin;
        kEnd = g.kEnd;
#ifdef RAYCAST_FEEDBACK
        if (k < kEnd) feedbackSampled(fb, g.leafIndex, g.wantsFiner);
        sampledLeaf = g.leafIndex;
#endif
        ++next;
      }
    }
  }
  return acc;
}
#endif

RayResult castRay(uvec2 pixel) {
  Ray ray;
  if (!cameraRay(pixel, ray)) return missedRay();
  vec3 originCube = ray.origin / raycast.cubeWorld;
  vec3 dirCube = ray.dir / raycast.cubeWorld;

  RopeCursor cursor;
  RopeLeaf leaf;
  ropeBegin(cursor, originCube, dirCube, ray.t0, ray.t1);  // a ray that misses the root cube gets no leaf
  bool firstLeaf = true;
#ifdef RAYCAST_FEEDBACK
  RayFeedback fb = rayFeedbackBegin();
#endif
#ifdef RAYCAST_MODE_ISO
  IsoMarch march = isoMarchBegin(ray);
  float hitEnter = ray.t0;
  // The data leaf of the march's previous sample (shadeIsoHit refines a crossing before the hit's leaf there).
  RopeLeaf before = RopeLeaf(kRopeTagDataLeaf, 0u, 0u, 0u, vec3(0.0), 1.0, ray.t0, ray.t1);
  while (!march.hit && ropeNextLeaf(cursor, leaf)) {
    bool entry = firstLeaf;
    firstLeaf = false;
    if (leaf.kind == kRopeTagSolidLeaf && march.capsFirst && !march.hasPrev) {
      // Every value of a solid leaf lies above the isovalue: the ray's first sample, if the leaf holds it,
      // is a cap, found without a brick.
      float dt = leafStep(leaf.depth);
      float t = ray.t0 + firstSampleIndex(ray.t0, leaf.tEnter, dt, entry) * dt;
      if (t < min(leaf.tExit, ray.t1)) isoMarchCap(march, t);
      continue;
    }
    if (leaf.kind != kRopeTagDataLeaf) continue;
    Segment s = leafSegment(leaf, originCube, dirCube);
    bool sampled = marchIso(march, s, ray.t0, firstSampleIndex(ray.t0, leaf.tEnter, s.dt, entry),
                            min(leaf.tExit, ray.t1));
#ifdef RAYCAST_FEEDBACK
    // The leaf of the hit took the hit's sample; the ray goes no further.
    if (sampled) feedbackSampled(fb, leaf.leafIndex, feedbackWantsFiner(leaf.depth, leaf.tEnter, ray.t0));
#endif
    if (march.hit) {
      // The first leaf's samples start at t0, which its float tEnter may round past.
      hitEnter = entry ? min(leaf.tEnter, ray.t0) : leaf.tEnter;
    } else if (sampled) {
      before = leaf;
    }
  }
  if (!march.hit) return missedRay();
  if (march.cap) {
#ifdef RAYCAST_FEEDBACK
    if (leaf.kind == kRopeTagDataLeaf) feedbackHit(leaf.leafIndex);
#endif
    return shadeIsoCap(march, ray);
  }
#ifdef RAYCAST_FEEDBACK
  // The ray's stop (RayResult.stopDepth, the sample past the crossing) lies in this leaf, behind its box's
  // front: the pixel an occlusion query of the leaf would count.
  feedbackHit(leaf.leafIndex);
#endif
  // The loop ends on the hit's leaf; its segment is made again rather than kept through the walk (registers).
  return shadeIsoHit(march, leafSegment(leaf, originCube, dirCube), hitEnter,
                     leafSegment(before, originCube, dirCube), min(before.tExit, ray.t1), ray);
#elif defined(RAYCAST_MODE_MIP)
  MipMax m = mipBegin();
  // A maximum that reaches the cut's largest value is final: every leaf left would be skipped.
  while (m.value < raycast.leafMaximaLargest && ropeNextLeaf(cursor, leaf)) {
    bool entry = firstLeaf;
    firstLeaf = false;
    if (leaf.kind != kRopeTagDataLeaf || leafBelowMaximum(leaf.leafIndex, m.value)) continue;
    Segment s = leafSegment(leaf, originCube, dirCube);
    float kBegin = firstSampleIndex(ray.t0, leaf.tEnter, s.dt, entry);
    float kEnd = firstSampleIndex(ray.t0, min(leaf.tExit, ray.t1), s.dt, false);
#ifdef RAYCAST_FEEDBACK
    if (kBegin < kEnd) feedbackSampled(fb, leaf.leafIndex, feedbackWantsFiner(leaf.depth, leaf.tEnter, ray.t0));
#endif
    marchMip(m, s, ray.t0, kBegin, kEnd);
  }
  return mipResult(m, ray.depthPerT);
#elif defined(RAYCAST_MODE_AIP)
  AipSum a = aipBegin();
  while (ropeNextLeaf(cursor, leaf)) {
    bool entry = firstLeaf;
    firstLeaf = false;
    if (leaf.kind != kRopeTagDataLeaf) continue;  // zeros: they add to the length alone
    Segment s = leafSegment(leaf, originCube, dirCube);
    float kBegin = firstSampleIndex(ray.t0, leaf.tEnter, s.dt, entry);
    float kEnd = firstSampleIndex(ray.t0, min(leaf.tExit, ray.t1), s.dt, false);
#ifdef RAYCAST_FEEDBACK
    if (kBegin < kEnd) feedbackSampled(fb, leaf.leafIndex, feedbackWantsFiner(leaf.depth, leaf.tEnter, ray.t0));
#endif
    // The first leaf's samples start at t0, which its float tEnter may round past.
    float tEnter = entry ? min(leaf.tEnter, ray.t0) : leaf.tEnter;
    marchAip(a, s, ray.t0, kBegin, kEnd, tEnter, min(leaf.tExit, ray.t1));
  }
  return aipResult(a, ray.t1 - ray.t0, ray.depthPerT);
#elif defined(RAYCAST_MODE_SLICE)
  // The walk starts where the ray crosses the plane (cameraRay): its first leaf holds the one sample, at its
  // level. An empty leaf's values have no opacity there.
  if (!ropeNextLeaf(cursor, leaf) || leaf.kind != kRopeTagDataLeaf) return missedRay();
#ifdef RAYCAST_FEEDBACK
  feedbackSampled(fb, leaf.leafIndex, feedbackWantsFiner(leaf.depth, leaf.tEnter, ray.t0));
#endif
  return sliceResult(sampleValue(segmentCoord(leafSegment(leaf, originCube, dirCube), ray.t0)),
                     ray.t0 * ray.depthPerT);
#elif defined(LLVMPIPE_DVR_LEAF_BATCH)
  return dvrResult(walkDvrBatched(cursor, ray, originCube, dirCube));
#else
  DvrAccum acc = dvrAccumBegin();
  while (ropeNextLeaf(cursor, leaf)) {
    bool entry = firstLeaf;
    firstLeaf = false;
    if (leaf.kind != kRopeTagDataLeaf) continue;
    Segment s = leafSegment(leaf, originCube, dirCube);
    float kBegin = firstSampleIndex(ray.t0, leaf.tEnter, s.dt, entry);
    float kEnd = firstSampleIndex(ray.t0, min(leaf.tExit, ray.t1), s.dt, false);
#ifdef RAYCAST_FEEDBACK
    if (kBegin < kEnd) feedbackSampled(fb, leaf.leafIndex, feedbackWantsFiner(leaf.depth, leaf.tEnter, ray.t0));
#endif
    if (compositeDvr(acc, s, ray, kBegin, kEnd)) {
#ifdef RAYCAST_FEEDBACK
      feedbackHit(leaf.leafIndex);  // early ray termination stopped the ray in this leaf
#endif
      break;
    }
  }
  return dvrResult(acc);
#endif
}
