// castBrute(pixel): the brute-force ray cast of one pixel (render/brute_force_pass.h), shared by the fragment
// (shaders/brute_force.frag) and compute (shaders/brute_force.comp) entry points: the whole level-0 volume in
// one 3D texture, every ray sampled from the volume entry t0 to its exit t1 on the grid t0 + k dt,
// dt = step min(s), with no index and no empty-space skipping. The volume is one segment of the shared sampling
// and compositing (shaders/compositing.glsl), so rays, interpolation, bisection, gradients, transfer function,
// shading, maximum, mean, slice and early ray termination are those of the rope ray caster at level 0. No
// #version line: the entry point has it. Variants: the defines of shaders/raycast_common.glsl but
// RAYCAST_FEEDBACK and LLVMPIPE_DVR_LEAF_BATCH.

#include "shaders/compositing.glsl"

// The whole volume as a segment: texture coordinate x / (n s), level 0.
Segment volumeSegment(Ray ray) {
  vec3 dims = vec3(textureSize(uValues, 0));
  vec3 worldToCoord = 1.0 / (raycast.spacing * dims);
  Segment s;
  s.coordAtZero = ray.origin * worldToCoord;
  s.coordPerT = ray.dir * worldToCoord;
  s.texelMin = vec3(0.0);
  s.texelCount = dims;
  s.texelAtZero = ray.origin / raycast.spacing;  // level-0 sample coordinate x / s
  s.texelPerT = ray.dir / raycast.spacing;
  s.gradientScale = 1.0 / (2.0 * raycast.spacing);
  s.dt = raycast.stepVoxels * raycast.minSpacing;
  s.opacityExponent = raycast.stepVoxels;
  return s;
}

RayResult castBrute(uvec2 pixel) {
  Ray ray;
  if (!cameraRay(pixel, ray)) return missedRay();
  Segment s = volumeSegment(ray);
#ifdef RAYCAST_MODE_ISO
  IsoMarch march = isoMarchBegin(ray);
  marchIso(march, s, ray.t0, 0.0, ray.t1);
  if (march.cap) return shadeIsoCap(march, ray);
  // One segment: the previous sample is always in it.
  return march.hit ? shadeIsoHit(march, s, ray.t0, s, ray.t1, ray) : missedRay();
#elif defined(RAYCAST_MODE_MIP)
  MipMax m = mipBegin();
  marchMip(m, s, ray.t0, 0.0, firstSampleIndex(ray.t0, ray.t1, s.dt, false));
  return mipResult(m, ray.depthPerT);
#elif defined(RAYCAST_MODE_SLICE)
  return sliceResult(sampleValue(segmentCoord(s, ray.t0)), ray.t0 * ray.depthPerT);
#elif defined(RAYCAST_MODE_AIP)
  AipSum a = aipBegin();
  marchAip(a, s, ray.t0, 0.0, firstSampleIndex(ray.t0, ray.t1, s.dt, false), ray.t0, ray.t1);
  return aipResult(a, ray.t1 - ray.t0, ray.depthPerT);
#else
  DvrAccum acc = dvrAccumBegin();
  compositeDvr(acc, s, ray, 0.0, firstSampleIndex(ray.t0, ray.t1, s.dt, false));
  return dvrResult(acc);
#endif
}
