// castRay(pixel): the whole single-pass ray cast of one pixel (docs/RENDERING.md), shared by the fragment
// (shaders/raycast.frag) and compute (shaders/raycast.comp) entry points so both produce the same image.
// Rays are generated as core/camera.h pixelRay does, clipped to the volume box, walked leaf by leaf with the
// rope traversal (shaders/rope_traversal.glsl), and sampled per leaf at the leaf's level on a step grid
// anchored at the volume entry. No #version line: the entry point has it.
//
// Variants (defines): RAYCAST_MODE_ISO or RAYCAST_MODE_DVR; BRICK_BORDER; ISO_BISECTION_STEPS;
// DVR_SHADE_GRADIENT_THRESHOLD (render/raycast_pass.cpp passes them from the C++ constants); DVR_STORED_GRADIENTS
// (DVR samples a GradientPool, render/gradient_pool.h).

#include "shaders/rope_traversal.glsl"
#include "shaders/shading.glsl"

// Camera (core/camera.h): eye, orthonormal frame and the pinhole's extent.
uniform vec3 uEye;
uniform vec3 uForward;
uniform vec3 uRight;
uniform vec3 uUp;
uniform float uTanHalfFov;
uniform float uAspect;
uniform uvec2 uImageSize;

// Volume geometry in world units.
uniform vec3 uVolumeMax;   // n * s
uniform vec3 uCubeWorld;   // C * s: the root cube's extent
uniform vec3 uSpacing;     // s
uniform float uMinSpacing;  // min(s)
uniform float uBrickSize;  // B
uniform uint uMaxDepth;

// RenderParams.
uniform float uStepVoxels;
uniform float uErt;
uniform vec3 uBackground;
uniform float uIsoValue;  // normalized: mapping.toStored(V) / storedMax

const float kInfinity = uintBitsToFloat(0x7F800000u);

// The uniforms that the walks read per leaf or per sample, loaded once per ray (walkUniforms()) and passed down:
// llvmpipe loads a uniform that is read inside a loop anew in every iteration, lane by lane with a bounds check
// (~25 instructions each; reading DVR's once per ray took ML DVR frames 10 % fewer instructions there).
struct WalkUniforms {
  vec3 level0;  // (step min(s), step, min(s)): dt, opacity exponent and spacing of level-0 sampling
  vec3 spacing;
  float brickSize;
  uint maxDepth;
  float isoValue;
  float ert;
  PoolLayout pool;
  DvrUniforms dvr;
};

WalkUniforms walkUniforms() {
  WalkUniforms wu;
  wu.level0 = vec3(uStepVoxels * uMinSpacing, uStepVoxels, uMinSpacing);
  wu.spacing = uSpacing;
  wu.brickSize = uBrickSize;
  wu.maxDepth = uMaxDepth;
  wu.isoValue = uIsoValue;
  wu.ert = uErt;
  wu.pool = poolLayout();
  wu.dvr = dvrUniforms();
  return wu;
}

struct RayResult {
  vec4 color;   // final color (background composited), alpha = coverage
  float depth;  // world distance along the camera axis; +inf for none
};

// core/camera.h pixelRay: the ray through the center of pixel (px, py), row 0 at the top.
vec3 pixelRayDir(uvec2 pixel) {
  vec2 size = vec2(uImageSize);
  float x = (2.0 * (float(pixel.x) + 0.5) / size.x - 1.0) * uTanHalfFov * uAspect;
  float y = (1.0 - 2.0 * (float(pixel.y) + 0.5) / size.y) * uTanHalfFov;
  return normalize(uForward + x * uRight + y * uUp);
}

// Slab test against [0, uVolumeMax]; t0 clamped to 0. False on a miss.
bool clipToVolume(vec3 origin, vec3 dir, out float t0, out float t1) {
  t0 = -kInfinity;
  t1 = kInfinity;
  for (int a = 0; a < 3; ++a) {
    if (dir[a] == 0.0) {
      if (origin[a] < 0.0 || origin[a] > uVolumeMax[a]) return false;
      continue;
    }
    float tn = (0.0 - origin[a]) / dir[a];
    float tf = (uVolumeMax[a] - origin[a]) / dir[a];
    t0 = max(t0, min(tn, tf));
    t1 = min(t1, max(tn, tf));
  }
  t0 = max(t0, 0.0);
  return t0 < t1;
}

// The first sample index k (t = t0 + k dt) of a leaf entered at tEnter: samples t0 + k dt with
// tEnter <= t (k from 0 in the ray's first leaf, whose tEnter is t0 up to rounding in cube coordinates, so that
// its first sample is t0 itself, never dropped by that rounding).
float firstSampleIndex(float t0, float tEnter, float dt, bool firstLeaf) {
  if (firstLeaf) return 0.0;
  float k = ceil((tEnter - t0) / dt);
  if (t0 + k * dt < tEnter) k += 1.0;
  return k;
}

// A data leaf's brick and sampling: step dt = step * 2^L * min(s), one level-L cell in world units.
struct LeafSampling {
  BrickRef brick;
  float levelScale;  // 2^L
  float dt;
  vec3 cellWorld;
};

LeafSampling leafSampling(uint slot, uint depth, vec3 boxMin, WalkUniforms wu) {
  LeafSampling ls;
  ls.levelScale = ropeBoxScale(wu.maxDepth - depth);  // exact
  ls.dt = wu.level0.y * ls.levelScale * wu.level0.z;
  ls.cellWorld = wu.spacing * ls.levelScale;
  ls.brick.slotOrigin = poolSlotOrigin(slot, wu.pool);
  ls.brick.boxMin = boxMin;
  ls.brick.texelsPerCube = wu.brickSize * ropeBoxScale(depth);
  return ls;
}

// Inside a data leaf the pool coordinate of the ray's point at t is affine in t, base + t * slope (the slope
// fixed by the leaf's level): the walks compute it once per sample from these. Samples of the leaf lie at
// texels [BRICK_BORDER, B + BRICK_BORDER] of its slot, so their filter footprints stay inside it unclamped.
struct LeafPoolRay {
  vec3 base;
  vec3 slope;
};

LeafPoolRay leafPoolRay(BrickRef b, vec3 originCube, vec3 dirCube, PoolLayout pool) {
  LeafPoolRay r;
  r.base = (b.slotOrigin + float(BRICK_BORDER) + (originCube - b.boxMin) * b.texelsPerCube) * pool.texelSize;
  r.slope = dirCube * b.texelsPerCube * pool.texelSize;
  return r;
}

#ifdef RAYCAST_MODE_ISO
struct IsoHit {
  bool hit;
  BrickRef brick;  // the leaf holding the first sample across the isovalue
  vec3 cellWorld;
  float tPrev, fPrev;  // the sample before the crossing
  float tHit;          // the first sample across
};

// March leaf by leaf to the first sample pair across the isovalue.
IsoHit walkIso(vec3 originCube, vec3 dirCube, float t0, float t1, WalkUniforms wu) {
  IsoHit h;
  h.hit = false;
  bool hasPrev = false;
  RopeCursor cursor;
  RopeLeaf leaf;
  ropeBegin(cursor, originCube, dirCube, t0, t1);  // a ray that misses the root cube gets an empty cursor
  bool done = false;
  bool entryLeaf = true;
  // Both loops test their exit at the bottom, as walkDvr's do (llvmpipe would otherwise run one more masked
  // leaf per ray and one more masked sample per leaf). An empty cursor gives no leaf.
  do {
    if (!ropeNextLeaf(cursor, leaf)) break;
    bool firstLeaf = entryLeaf;
    entryLeaf = false;
    if (leaf.kind != kRopeTagDataLeaf) continue;  // empty leaves are skipped without sampling
    LeafSampling ls = leafSampling(leaf.brickSlot, leaf.depth, leaf.boxMin, wu);
    float tStop = min(leaf.tExit, t1);
    LeafPoolRay pool = leafPoolRay(ls.brick, originCube, dirCube, wu.pool);
    float k = firstSampleIndex(t0, leaf.tEnter, ls.dt, firstLeaf);
    float t = t0 + k * ls.dt;
    if (!(t < tStop)) continue;
    do {
      float f = poolValue(pool.base + t * pool.slope) - wu.isoValue;
      if (hasPrev && (f >= 0.0) != (h.fPrev >= 0.0)) {
        // A crossing between the previous and this sample: refined after the walk (castRay), so that the SIMD
        // lanes of a software rasterizer run the bisection once together rather than once per lane.
        h.tHit = t;
        done = true;
        break;
      }
      hasPrev = true;
      h.tPrev = t;
      h.fPrev = f;
      k += 1.0;
      t = t0 + k * ls.dt;
    } while (t < tStop);
    // The leaf of the crossing, recorded here rather than in the sample loop: llvmpipe runs an `if` body with
    // every sample whether or not a lane takes it, and these are ten selects against a sample's ~150 instructions.
    if (done) {
      h.hit = true;
      h.brick = ls.brick;
      h.cellWorld = ls.cellWorld;
    }
    // The cursor knows when the ray has no leaf left (no rope out of the last one): stop there rather than in
    // one more ropeNextLeaf, which llvmpipe runs whole for the SIMD group (~0.5 % of a frame).
  } while (!done && cursor.node != kRopeNull);
  return h;
}
#else
// The DVR walk gathers a few data leaves with the rope traversal, then samples all of them in one flat loop,
// and repeats. With one sample loop per leaf, SIMD lanes (a GPU warp, llvmpipe's AVX lanes) that cross leaf
// borders at different samples (an oblique border plane: neighbouring rays reach it several samples apart)
// idle at every leaf until the lane with the longest leaf is done; in the flat loop a lane moves on to its next
// gathered leaf at once. A batch is small because early ray termination usually ends the ray within a few
// leaves, and leaves gathered beyond it are traversal wasted (on llvmpipe 8 beat 4 and 2).
//
// The batch lives in eight named slots, not in an array: llvmpipe keeps a local array in memory and reads or
// writes an element lane by lane even at a constant index, while named variables stay in registers and a slot
// is picked by selects (~2 % of a DVR frame there).
#define DVR_LEAF_BATCH 8u

struct DvrAccum {
  vec3 color;  // premultiplied, front to back
  float alpha;
  float depth;
};

// A gathered leaf as the flat loop samples it. Sample k of the ray lies at t0 + k dt on the grid of the leaf's
// level L (dt = step 2^L min(s)), and at pool coordinate base.xyz + k * poolStep: one sample advances `step`
// texels of its own level, so poolStep is the same at every level and only base (the leaf's pool coordinate
// extrapolated back to t0) changes from leaf to leaf. The leaf's samples are k < base.w.
// level: dt; the opacity correction's exponent step * 2^L; min(s) * 2^-L, against which shadeDvr tests the
// level-0-scaled gradient (the gradient is 2^L times that of the leaf's cells, exactly, so the test and the
// normal are those of docs/RENDERING.md bit for bit).
struct GatheredLeaf {
  vec4 base;
  vec3 level;
};

// One gathered leaf as the gather stores it: base (base.xyz, the first k past the leaf), the leaf's first k and
// its 2^L.
struct GatherSlot {
  vec4 base;
  vec2 first;  // first k, 2^L
};

// level0: GatheredLeaf.level at level 0, (step min(s), step, min(s)): WalkUniforms.level0.
GatheredLeaf gatheredLeaf(GatherSlot slot, vec3 level0) {
  float levelScale = slot.first.y;
  float levelInverse = uintBitsToFloat(0x7F000000u - floatBitsToUint(levelScale));  // 2^-L, exact
  GatheredLeaf g;
  g.base = slot.base;
  g.level = level0 * vec3(levelScale, levelScale, levelInverse);
  return g;
}

// Composites sample k of the current leaf and steps to the next; true when the ray reached early termination at
// uErt. gradientScale: 1 / (2 s), the differences' scale at level 0.
bool dvrStep(inout DvrAccum acc, inout float k, GatheredLeaf g, vec3 poolStep, float t0, vec3 gradientScale,
             vec3 dir, float depthPerT, WalkUniforms wu) {
  vec3 poolCoord = g.base.xyz + k * poolStep;
  PoolSample sampled = poolSample(poolCoord);
  vec4 tf = transferFunction(sampled.value, wu.dvr);
  float a = 1.0 - pow(1.0 - tf.a, g.level.y);
  if (a > 0.0) {
    vec3 gradient = poolSampleDifferences(sampled, poolCoord, wu.pool) * gradientScale;
    vec3 c = shadeDvr(tf.rgb, gradient, dir, g.level.z, wu.dvr);
    acc.color += (1.0 - acc.alpha) * a * c;
    acc.alpha += (1.0 - acc.alpha) * a;
    acc.depth = (t0 + k * g.level.x) * depthPerT;
  }
  k += 1.0;
  return a > 0.0 && acc.alpha >= wu.ert;  // as the CPU mirror: only a composited sample ends the ray
}

// The slot of index i (i in 1..7: slot 0 is taken when the batch begins).
GatherSlot pickSlot(uint i, GatherSlot s1, GatherSlot s2, GatherSlot s3, GatherSlot s4, GatherSlot s5,
                    GatherSlot s6, GatherSlot s7) {
  GatherSlot s = s1;
  if (i == 2u) s = s2;
  if (i == 3u) s = s3;
  if (i == 4u) s = s4;
  if (i == 5u) s = s5;
  if (i == 6u) s = s6;
  if (i == 7u) s = s7;
  return s;
}

// Front-to-back compositing along the ray with early termination at uErt.
DvrAccum walkDvr(vec3 originCube, vec3 dirCube, vec3 dir, float t0, float t1, float depthPerT,
                 WalkUniforms wu) {
  DvrAccum acc;
  acc.color = vec3(0.0);
  acc.alpha = 0.0;
  acc.depth = kInfinity;

  vec3 poolStep = dirCube * (wu.brickSize * ropeBoxScale(wu.maxDepth) * wu.level0.x) * wu.pool.texelSize;
  vec3 gradientScale = 1.0 / (2.0 * wu.spacing);

  RopeCursor cursor;
  RopeLeaf leaf;
  ropeBegin(cursor, originCube, dirCube, t0, t1);  // as in walkIso: a miss leaves the cursor empty
  bool more = true;
  bool entryLeaf = true;
  // Every loop of this walk tests its exit at the bottom. llvmpipe repeats a loop body while any lane is left in
  // it, so a loop tested at the top runs one more whole body, all lanes masked, before it sees that none is:
  // here one more gather and flat-loop block per batch (~2 % of a DVR frame, ~6 % for rays of one leaf).
  do {
    // Gather the next data leaves along the ray (empty leaves are skipped without sampling).
    GatherSlot s0, s1, s2, s3, s4, s5, s6, s7;
    uint count = 0u;
    do {
      if (!ropeNextLeaf(cursor, leaf)) break;
      bool firstLeaf = entryLeaf;
      entryLeaf = false;
      if (leaf.kind != kRopeTagDataLeaf) continue;
      LeafSampling ls = leafSampling(leaf.brickSlot, leaf.depth, leaf.boxMin, wu);
      LeafPoolRay pool = leafPoolRay(ls.brick, originCube, dirCube, wu.pool);
      GatherSlot slot;
      slot.base = vec4(pool.base + t0 * pool.slope, firstSampleIndex(t0, min(leaf.tExit, t1), ls.dt, false));
      slot.first = vec2(firstSampleIndex(t0, leaf.tEnter, ls.dt, firstLeaf), ls.levelScale);
      // The write side of pickSlot's selects (the slots are named variables, see DVR_LEAF_BATCH).
      if (count == 0u) s0 = slot;
      if (count == 1u) s1 = slot;
      if (count == 2u) s2 = slot;
      if (count == 3u) s3 = slot;
      if (count == 4u) s4 = slot;
      if (count == 5u) s5 = slot;
      if (count == 6u) s6 = slot;
      if (count == 7u) s7 = slot;
      ++count;
      // As in walkIso: no further ropeNextLeaf once the cursor has no leaf left.
    } while (count < DVR_LEAF_BATCH && cursor.node != kRopeNull);
    more = cursor.node != kRopeNull;

    // Sample all gathered leaves in one flat loop. Up to three samples of the current leaf per leaf-change check:
    // llvmpipe runs every `if` for the whole SIMD group under a mask whether or not a lane takes it (only loops
    // stop when no lane is left), so the leaf change costs its selects every iteration; straight samples
    // amortize them, and a lane whose leaf ends inside the group idles for the rest of it (instructions per ML
    // DVR frame there with 2, 3, 4, 5 samples: 191.7, 191.2, 193.1, 195.2 M; a counted inner loop cost 10 % more).
    if (count > 0u) {
      GatheredLeaf g = gatheredLeaf(s0, wu.level0);
      float k = s0.first.x;
      uint next = 1u;
      for (;;) {
        // A leaf may hold no sample (a sliver between two sample points): then the leaf change below moves on.
        // One exit per cause (a flag and break, not a return from inside the loops): ~1 % of a frame on llvmpipe.
        bool terminated = k < g.base.w && dvrStep(acc, k, g, poolStep, t0, gradientScale, dir, depthPerT, wu);
        if (!terminated && k < g.base.w)
          terminated = dvrStep(acc, k, g, poolStep, t0, gradientScale, dir, depthPerT, wu);
        if (!terminated && k < g.base.w)
          terminated = dvrStep(acc, k, g, poolStep, t0, gradientScale, dir, depthPerT, wu);
        if (terminated) {
          more = false;
          break;
        }
        // The leaf change, at the bottom so that the loop ends there: an `if`, not a loop (a loop costs its own
        // masked bookkeeping every iteration on llvmpipe, ~1.5 % of a DVR frame; a leaf without samples takes
        // one iteration instead).
        if (!(k < g.base.w)) {
          if (next == count) break;
          GatherSlot slot = pickSlot(next, s1, s2, s3, s4, s5, s6, s7);
          g = gatheredLeaf(slot, wu.level0);
          k = slot.first.x;
          ++next;
        }
      }
    }
  } while (more);
  return acc;
}
#endif

RayResult castRay(uvec2 pixel) {
  RayResult result;
  result.color = vec4(uBackground, 0.0);
  result.depth = kInfinity;

  vec3 dir = pixelRayDir(pixel);
  float t0, t1;
  if (!clipToVolume(uEye, dir, t0, t1)) return result;

  // Root-cube coordinates: u = x / (C s); t stays the world t.
  vec3 originCube = uEye / uCubeWorld;
  vec3 dirCube = dir / uCubeWorld;
  float depthPerT = dot(dir, uForward);
  WalkUniforms wu = walkUniforms();

#ifdef RAYCAST_MODE_ISO
  IsoHit h = walkIso(originCube, dirCube, t0, t1, wu);
  if (!h.hit) return result;
  // Bisection between the previous sample and the first one across the isovalue, at the level of the leaf
  // holding the latter, in exact interpolation; then the gradient there.
  float ta = h.tPrev, fa = h.fPrev, tb = h.tHit;
  for (int i = 0; i < ISO_BISECTION_STEPS; ++i) {
    float tm = 0.5 * (ta + tb);
    vec3 texel = brickTexel(h.brick, originCube + tm * dirCube);
    float fm = brickValueExact(h.brick, texel, wu.pool) - wu.isoValue;
    if ((fm >= 0.0) == (fa >= 0.0)) {
      ta = tm;
      fa = fm;
    } else {
      tb = tm;
    }
  }
  float tHit = 0.5 * (ta + tb);
  vec3 hitTexel = brickTexel(h.brick, originCube + tHit * dirCube);
  result.color = vec4(shadeIso(brickGradientExact(h.brick, hitTexel, h.cellWorld, wu.pool), dir), 1.0);
  result.depth = tHit * depthPerT;
#else
  DvrAccum acc = walkDvr(originCube, dirCube, dir, t0, t1, depthPerT, wu);
  result.color = vec4(acc.color + (1.0 - acc.alpha) * uBackground, acc.alpha);
  result.depth = acc.depth;
#endif
  return result;
}
