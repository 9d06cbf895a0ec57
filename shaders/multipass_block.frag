#version 450 core
// One block of the multi-pass renderer (render/multipass_pass.h): the camera ray of each fragment is clipped to
// the leaf's box and sampled there on the ray's global grid, continuing the pixel's front-to-back state held in
// images between the passes. The box's entry and exit are computed as the rope traversal computes a leaf's
// (ropePlaneT in root-cube coordinates, shaders/rope_traversal.glsl), and the first sample index as
// castRay computes it (firstSampleIndex, anchored at the ray's entry into the volume), so two neighbouring
// blocks split the grid exactly as the single pass splits it between two leaves (docs/RENDERING.md "Rays").
// Early fragment tests: the depth test that skips the pixels whose ray has ended (the mark of
// shaders/multipass_mark.frag) runs before the shader, which its image stores would otherwise forbid.

layout(early_fragment_tests) in;

#include "shaders/raycast_common.glsl"

layout(rgba32f, binding = 0) uniform image2D uAccum;  // premultiplied color, opacity (iso: the hit, 1)
layout(r32f, binding = 1) uniform image2D uDepth;     // world depth (+inf: none yet)
#ifdef RAYCAST_MODE_MIP
// The largest value so far and whether there is one (MipMax; shaders/multipass_resolve.frag maps it to a
// color); its depth is in uDepth.
layout(rgba32f, binding = 2) uniform image2D uMarch;
#endif
#ifdef RAYCAST_MODE_AIP
// The sum so far (AipSum.sum), the ray's length in the drawn box, whether a sample was taken (AipSum;
// shaders/multipass_resolve.frag makes the mean a color); the first sample above zero's depth is in uDepth.
layout(rgba32f, binding = 2) uniform image2D uMarch;
#endif
#ifdef RAYCAST_MODE_ISO
layout(rgba32f, binding = 2) uniform image2D uMarch;  // has previous sample, its t, its f, hit
// The leaf of the previous sample, where shadeIsoHit refines a crossing that lies before this block:
// floatBitsToUint(box min), depth | brick slot << 8.
layout(rgba32ui, binding = 3) uniform uimage2D uBefore;
#endif
layout(location = 3) uniform vec3 uLeafBoxMin;  // root-cube coordinates
layout(location = 4) uniform uvec2 uLeaf;       // depth, brick slot (kRopeNoBrick: a solid leaf, which caps)
#ifdef RAYCAST_MODE_MIP
layout(location = 5) uniform float uLeafMax;    // the leaf's largest value (MultipassLeaf::maxValue)
#endif

// Where the ray leaves a box (root-cube coordinates), as the rope traversal clips a leaf: the first exit plane
// of the moving axes.
float boxExitT(vec3 boxMin, float boxSize, vec3 originCube, vec3 invDir) {
  bvec3 moving = notEqual(invDir, vec3(0.0));
  vec3 boxExit = ropePlaneT(boxMin + vec3(greaterThan(invDir, vec3(0.0))) * boxSize, originCube, invDir);
  float tExit = kInfinity;
  for (int a = 0; a < 3; ++a)
    if (moving[a]) tExit = min(tExit, boxExit[a]);
  return tExit;
}

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  Ray ray;
  if (!cameraRay(uvec2(pixel), ray)) return;
  vec3 originCube = ray.origin / raycast.cubeWorld;
  vec3 dirCube = ray.dir / raycast.cubeWorld;

  // As ropeBegin: 1/dir on moving axes, and where the walk of the single pass starts (tStart) and ends.
  vec3 invDir;
  for (int a = 0; a < 3; ++a) {
    float inv = dirCube[a] != 0.0 ? 1.0 / dirCube[a] : 0.0;
    invDir[a] = (isinf(inv) || isnan(inv)) ? 0.0 : inv;
  }
  bvec3 moving = notEqual(invDir, vec3(0.0));
  bvec3 positive = greaterThan(invDir, vec3(0.0));
  vec3 cubeEntry = ropePlaneT(vec3(not(positive)), originCube, invDir);
  vec3 cubeExit = ropePlaneT(vec3(positive), originCube, invDir);
  float boxSize = ropeBoxSize(uLeaf.x);
  vec3 boxEntry = ropePlaneT(uLeafBoxMin + vec3(not(positive)) * boxSize, originCube, invDir);
  float tStart = ray.t0, tEnd = ray.t1;
  float tEnter = -kInfinity;
  for (int a = 0; a < 3; ++a) {
    if (!moving[a]) {
      // The box holds the ray as the rope traversal's descent does: a ray in the face two boxes share
      // belongs to the upper one (half-open boxes), but for the cube's own upper face.
      float boxMax = uLeafBoxMin[a] + boxSize;
      if (originCube[a] < uLeafBoxMin[a] || (originCube[a] >= boxMax && boxMax < 1.0)) return;
      continue;
    }
    tStart = max(tStart, cubeEntry[a]);
    tEnd = min(tEnd, cubeExit[a]);
    tEnter = max(tEnter, boxEntry[a]);
  }
  float tExit = boxExitT(uLeafBoxMin, boxSize, originCube, invDir);
  // The box holding the walk's start is the ray's first leaf: its grid starts at k = 0.
  bool entry = tEnter <= tStart;
  tEnter = max(tEnter, tStart);
  tExit = min(tExit, tEnd);
  if (!(tExit > tEnter)) return;

#ifdef RAYCAST_MODE_ISO
  vec4 state = imageLoad(uMarch, pixel);
  if (state.w != 0.0) return;
  IsoMarch march = IsoMarch(state.x != 0.0, state.y, state.z, false, 0.0, ray.capNormal != vec3(0.0), false);
  if (uLeaf.y == kRopeNoBrick) {
    // A solid leaf, as the single pass's walk takes it: the ray's first sample, if the leaf holds it, is a cap.
    float dt = leafStep(uLeaf.x);
    float t = ray.t0 + firstSampleIndex(ray.t0, tEnter, dt, entry) * dt;
    if (!march.capsFirst || march.hasPrev || !(t < tExit)) return;
    isoMarchCap(march, t);
    RayResult r = shadeIsoCap(march, ray);
    imageStore(uAccum, pixel, r.color);
    imageStore(uDepth, pixel, vec4(r.depth));
    imageStore(uMarch, pixel, vec4(0.0, 0.0, 0.0, 1.0));
    return;
  }
#endif
  RopeLeaf leaf;
  leaf.depth = uLeaf.x;
  leaf.brickSlot = uLeaf.y;
  leaf.boxMin = uLeafBoxMin;
  Segment s = leafSegment(leaf, originCube, dirCube);
  float kBegin = firstSampleIndex(ray.t0, tEnter, s.dt, entry);

#ifdef RAYCAST_MODE_ISO
  bool sampled = marchIso(march, s, ray.t0, kBegin, min(tExit, ray.t1));
  if (march.cap) {
    RayResult r = shadeIsoCap(march, ray);
    imageStore(uAccum, pixel, r.color);
    imageStore(uDepth, pixel, vec4(r.depth));
  } else if (march.hit) {
    uvec4 beforeBits = imageLoad(uBefore, pixel);
    RopeLeaf before;
    before.boxMin = uintBitsToFloat(beforeBits.xyz);
    before.depth = beforeBits.w & 0xFFu;
    before.brickSlot = beforeBits.w >> 8u;
    float beforeExit = min(boxExitT(before.boxMin, ropeBoxSize(before.depth), originCube, invDir), tEnd);
    // The first block's samples start at t0, which its float tEnter may round past.
    RayResult r = shadeIsoHit(march, s, entry ? min(tEnter, ray.t0) : tEnter,
                              leafSegment(before, originCube, dirCube), min(beforeExit, ray.t1), ray);
    // The nearest hit wins by depth; in front-to-back order the first hit is the nearest.
    if (r.depth < imageLoad(uDepth, pixel).r) {
      imageStore(uAccum, pixel, r.color);
      imageStore(uDepth, pixel, vec4(r.depth));
    }
  }
  if (!march.hit && sampled)
    imageStore(uBefore, pixel, uvec4(floatBitsToUint(uLeafBoxMin), uLeaf.x | (uLeaf.y << 8u)));
  imageStore(uMarch, pixel, vec4(march.hasPrev ? 1.0 : 0.0, march.tPrev, march.fPrev, march.hit ? 1.0 : 0.0));
#elif defined(RAYCAST_MODE_MIP)
  // Front to back, a later block's sample replaces the maximum only when larger, as within the single pass.
  vec4 state = imageLoad(uMarch, pixel);
  MipMax m = state.y != 0.0 ? MipMax(state.x, 0.0) : mipBegin();
  if (uLeafMax <= m.value) return;  // as the single pass's leafBelowMaximum
  float before = m.value;
  marchMip(m, s, ray.t0, kBegin, firstSampleIndex(ray.t0, min(tExit, ray.t1), s.dt, false));
  if (m.value > before) {
    imageStore(uMarch, pixel, vec4(m.value, 1.0, 0.0, 0.0));
    imageStore(uDepth, pixel, vec4(m.t * ray.depthPerT));
  }
#elif defined(RAYCAST_MODE_AIP)
  // Sums add up in any order; the nearest first sample above zero wins by depth.
  AipSum a = AipSum(imageLoad(uMarch, pixel).x, kInfinity, false);
  marchAip(a, s, ray.t0, kBegin, firstSampleIndex(ray.t0, min(tExit, ray.t1), s.dt, false),
           entry ? min(tEnter, ray.t0) : tEnter, min(tExit, ray.t1));
  if (!a.sampled) return;
  imageStore(uMarch, pixel, vec4(a.sum, ray.t1 - ray.t0, 1.0, 0.0));
  float firstDepth = a.firstT * ray.depthPerT;
  if (firstDepth < imageLoad(uDepth, pixel).r) imageStore(uDepth, pixel, vec4(firstDepth));
#elif defined(RAYCAST_MODE_SLICE)
  // The block holding the ray's start, its crossing of the plane, takes the one sample; the resolve pass puts
  // the background under it.
  if (!entry) return;
  vec4 tf = transferFunction(sampleValue(segmentCoord(s, ray.t0)));
  if (!(tf.a > 0.0)) return;
  imageStore(uAccum, pixel, vec4(tf.a * tf.rgb, tf.a));
  imageStore(uDepth, pixel, vec4(ray.t0 * ray.depthPerT));
#else
  vec4 accum = imageLoad(uAccum, pixel);
  if (accum.a >= raycast.ert) return;
  // Where early ray termination stops the ray, the mark pass notes (shaders/multipass_mark.frag): not kept here.
  DvrAccum acc = DvrAccum(accum.rgb, accum.a, imageLoad(uDepth, pixel).r, kInfinity);
  compositeDvr(acc, s, ray, kBegin, firstSampleIndex(ray.t0, min(tExit, ray.t1), s.dt, false));
  imageStore(uAccum, pixel, vec4(acc.color, acc.alpha));
  imageStore(uDepth, pixel, vec4(acc.depth));
#endif
}
