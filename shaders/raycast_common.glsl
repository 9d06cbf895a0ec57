// castRay(pixel): the whole single-pass ray cast of one pixel (docs/RENDERING.md), shared by the fragment
// (shaders/raycast.frag) and compute (shaders/raycast.comp) entry points so both produce the same image.
// Rays are generated as loader/camera.h pixelRay does, clipped to the volume box, walked leaf by leaf with the
// rope traversal (shaders/rope_traversal.glsl), and sampled per leaf at the leaf's level on a step grid
// anchored at the volume entry. No #version line: the entry point has it.
//
// Variants (defines): RAYCAST_MODE_ISO or RAYCAST_MODE_DVR; BRICK_BORDER; ISO_BISECTION_STEPS;
// DVR_SHADE_GRADIENT_THRESHOLD (render/raycast_pass.cpp passes them from the C++ constants).

#include "shaders/rope_traversal.glsl"
#include "shaders/shading.glsl"

// Camera (loader/camera.h): eye, orthonormal frame and the pinhole's extent.
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

struct RayResult {
  vec4 color;   // final color (background composited), alpha = coverage
  float depth;  // world distance along the camera axis; +inf for none
};

// loader/camera.h pixelRay: the ray through the center of pixel (px, py), row 0 at the top.
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

  vec3 color = vec3(0.0);
  float alpha = 0.0;
  float depth = kInfinity;
#ifdef RAYCAST_MODE_ISO
  bool hasPrev = false;
  float tPrev = 0.0;
  float fPrev = 0.0;
  bool hit = false;
  BrickRef hitBrick;
  vec3 hitCellWorld = vec3(0.0);
  float tHitB = 0.0;
#endif

  RopeCursor cursor;
  RopeLeaf leaf;
  bool done = !ropeBegin(cursor, originCube, dirCube, t0, t1);
  bool entryLeaf = true;
  while (!done && ropeNextLeaf(cursor, leaf)) {
    // The first leaf starts where the ray enters the volume (the cube holds the volume, so its tEnter is t0
    // up to rounding in cube coordinates): its first sample is t0 itself, never dropped by that rounding.
    bool firstLeaf = entryLeaf;
    entryLeaf = false;
    if (leaf.kind != kRopeTagDataLeaf) continue;  // empty leaves are skipped without sampling

    uint level = uMaxDepth - leaf.depth;
    float levelScale = ropeBoxScale(level);  // 2^L, exact
    float dt = uStepVoxels * levelScale * uMinSpacing;
    vec3 cellWorld = uSpacing * levelScale;
    BrickRef brick;
    brick.slotOrigin = poolSlotOrigin(leaf.brickSlot);
    brick.boxMin = leaf.boxMin;
    brick.texelsPerCube = uBrickSize * ropeBoxScale(leaf.depth);

    // Samples t = t0 + k dt with tEnter <= t < min(tExit, t1) (k from 0 in the first leaf).
    float tStop = min(leaf.tExit, t1);
    float k = 0.0;
    if (!firstLeaf) {
      k = ceil((leaf.tEnter - t0) / dt);
      if (t0 + k * dt < leaf.tEnter) k += 1.0;
    }
    for (float t = t0 + k * dt; t < tStop; k += 1.0, t = t0 + k * dt) {
#ifdef RAYCAST_MODE_ISO
      vec3 texel = brickTexel(brick, originCube + t * dirCube);
      float v = brickValue(brick, texel);
      float f = v - uIsoValue;
      if (hasPrev && (f >= 0.0) != (fPrev >= 0.0)) {
        // A crossing between the previous and this sample: refined after the walk (below), so that the SIMD
        // lanes of a software rasterizer run the bisection once together rather than once per lane.
        hitBrick = brick;
        hitCellWorld = cellWorld;
        tHitB = t;
        hit = true;
        done = true;
        break;
      }
      hasPrev = true;
      tPrev = t;
      fPrev = f;
#else
      vec3 poolCoord = brickPoolCoord(brick, brickTexel(brick, originCube + t * dirCube));
      float v = poolValue(poolCoord);
      vec4 tf = transferFunction(v);
      float a = 1.0 - pow(1.0 - tf.a, dt / uMinSpacing);
      if (!(a > 0.0)) continue;
      vec3 c = shadeDvr(tf.rgb, poolGradient(poolCoord, cellWorld), dir, uMinSpacing);
      color += (1.0 - alpha) * a * c;
      alpha += (1.0 - alpha) * a;
      depth = t * depthPerT;
      if (alpha >= uErt) {
        done = true;
        break;
      }
#endif
    }
  }

#ifdef RAYCAST_MODE_ISO
  if (hit) {
    // Bisection between the previous sample and the first one across the isovalue, at the level of the leaf
    // holding the latter, in exact interpolation; then the gradient there.
    float ta = tPrev, fa = fPrev, tb = tHitB;
    for (int i = 0; i < ISO_BISECTION_STEPS; ++i) {
      float tm = 0.5 * (ta + tb);
      float fm = brickValueExact(hitBrick, brickTexel(hitBrick, originCube + tm * dirCube)) - uIsoValue;
      if ((fm >= 0.0) == (fa >= 0.0)) {
        ta = tm;
        fa = fm;
      } else {
        tb = tm;
      }
    }
    float tHit = 0.5 * (ta + tb);
    vec3 hitTexel = brickTexel(hitBrick, originCube + tHit * dirCube);
    color = shadeIso(brickGradientExact(hitBrick, hitTexel, hitCellWorld), dir);
    alpha = 1.0;
    depth = tHit * depthPerT;
  }
#endif

  result.color = vec4(color + (1.0 - alpha) * uBackground, alpha);
  result.depth = depth;
  return result;
}
