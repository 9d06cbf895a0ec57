#version 450 core
// Brute-force ray caster (render/brute_force_pass.h): the whole level-0 volume in one 3D texture, every ray
// marched from the volume entry t0 to its exit t1 on the grid t0 + k dt, dt = step * min(s), with no index and no
// empty-space skipping. Rays, sampling, bisection, gradients, transfer function, shading and early ray
// termination are docs/RENDERING.md's at level 0, written as castRay in shaders/raycast_common.glsl does, whose
// uniforms, ray setup and shading functions this file reuses (its rope traversal is left unused).

#include "shaders/raycast_common.glsl"

uniform sampler3D uVolume;  // level 0: R8/R16 UNORM, LINEAR, CLAMP_TO_EDGE
uniform ivec3 uVolumeDims;  // n
#ifdef DVR_STORED_GRADIENTS
uniform sampler3D uVolumeSamples;  // render/gradient_pool of uVolume: RGBA16_SNORM (differences, value)
#endif

layout(location = 0) out vec4 outColor;
layout(location = 1) out float outDepth;

// Level-0 sample coordinate (sample i centered at i + 0.5) of a world point; spacing: s.
vec3 volumeCoord(vec3 x, vec3 spacing) { return x / spacing; }

// As brickValueExact: trilinear in float from eight texelFetch()es, clamped to the outer sample centers.
// dims: uVolumeDims, read once per ray (WalkUniforms in shaders/raycast_common.glsl says why).
float volumeValueExact(vec3 q, ivec3 dims) {
  vec3 n = vec3(dims);
  vec3 c = clamp(q, vec3(0.5), n - 0.5) - 0.5;
  vec3 base = min(floor(c), max(n - 2.0, vec3(0.0)));
  vec3 f = c - base;
  ivec3 i = ivec3(base);
  ivec3 hi = min(i + 1, dims - 1);
  float c000 = texelFetch(uVolume, i, 0).r;
  float c100 = texelFetch(uVolume, ivec3(hi.x, i.y, i.z), 0).r;
  float c010 = texelFetch(uVolume, ivec3(i.x, hi.y, i.z), 0).r;
  float c110 = texelFetch(uVolume, ivec3(hi.x, hi.y, i.z), 0).r;
  float c001 = texelFetch(uVolume, ivec3(i.x, i.y, hi.z), 0).r;
  float c101 = texelFetch(uVolume, ivec3(hi.x, i.y, hi.z), 0).r;
  float c011 = texelFetch(uVolume, ivec3(i.x, hi.y, hi.z), 0).r;
  float c111 = texelFetch(uVolume, hi, 0).r;
  float c00 = mix(c000, c100, f.x), c10 = mix(c010, c110, f.x);
  float c01 = mix(c001, c101, f.x), c11 = mix(c011, c111, f.x);
  return mix(mix(c00, c10, f.y), mix(c01, c11, f.y), f.z);
}

vec3 volumeGradientExact(vec3 q, ivec3 dims, vec3 spacing) {
  const vec3 dx = vec3(1.0, 0.0, 0.0), dy = vec3(0.0, 1.0, 0.0), dz = vec3(0.0, 0.0, 1.0);
  vec3 g;
  g.x = volumeValueExact(q + dx, dims) - volumeValueExact(q - dx, dims);
  g.y = volumeValueExact(q + dy, dims) - volumeValueExact(q - dy, dims);
  g.z = volumeValueExact(q + dz, dims) - volumeValueExact(q - dz, dims);
  return g / (2.0 * spacing);
}

// Level-0 texture coordinates along a ray are affine in t, base + t * slope, as a leaf's pool coordinates are in
// castRay (LeafPoolRay): the march computes them once per sample without dividing. texel: one texel in texture
// coordinates, for computed gradients.
struct VolumeRay {
  vec3 base;
  vec3 slope;
  vec3 texel;
};

// eye, dims, spacing: the per-ray copies of uEye, uVolumeDims, uSpacing.
VolumeRay volumeRay(vec3 dir, vec3 eye, ivec3 dims, vec3 spacing) {
  vec3 worldToTexture = 1.0 / (spacing * vec3(dims));
  return VolumeRay(eye * worldToTexture, dir * worldToTexture, 1.0 / vec3(dims));
}

float volumeTexValue(vec3 p) { return textureLod(uVolume, p, 0.0).r; }

#ifndef RAYCAST_MODE_ISO
// One DVR sample at t, composited front to back, then the step to the next; true when early ray termination
// ends the ray (walkDvr's dvrStep at level 0, with the same factors per ray: scale.xyz = 1 / (2 s), scale.w =
// the opacity correction's exponent).
bool bruteDvrStep(inout DvrAccum acc, inout float k, inout float t, float t0, float dt, VolumeRay ray, vec4 scale,
                  vec3 dir, float depthPerT, WalkUniforms wu) {
  vec3 p = ray.base + t * ray.slope;
#ifdef DVR_STORED_GRADIENTS
  vec4 stored = textureLod(uVolumeSamples, p, 0.0);
  float v = stored.a;
#else
  float v = volumeTexValue(p);
#endif
  vec4 tf = transferFunction(v, wu.dvr);
  float a = 1.0 - pow(1.0 - tf.a, scale.w);
  if (a > 0.0) {
#ifdef DVR_STORED_GRADIENTS
    vec3 gradient = stored.rgb * scale.xyz;
#else
    vec3 gradient = centralDifferences(uVolume, p, ray.texel) * scale.xyz;
#endif
    vec3 c = shadeDvr(tf.rgb, gradient, dir, wu.level0.z, wu.dvr);
    acc.color += (1.0 - acc.alpha) * a * c;
    acc.alpha += (1.0 - acc.alpha) * a;
    acc.depth = t * depthPerT;
  }
  k += 1.0;
  t = t0 + k * dt;
  return a > 0.0 && acc.alpha >= wu.ert;
}
#endif

RayResult castBrute(uvec2 pixel) {
  RayResult result;
  result.color = vec4(uBackground, 0.0);
  result.depth = kInfinity;
  vec3 dir = pixelRayDir(pixel);
  float t0, t1;
  if (!clipToVolume(uEye, dir, t0, t1)) return result;

  float depthPerT = dot(dir, uForward);
  // The uniforms read in the loops, loaded once per ray as castRay does.
  WalkUniforms wu = walkUniforms();
  ivec3 dims = uVolumeDims;
  vec3 eye = uEye;
  float dt = wu.level0.x;
  VolumeRay ray = volumeRay(dir, eye, dims, wu.spacing);
#ifdef RAYCAST_MODE_ISO
  bool hasPrev = false;
  float tPrev = 0.0, fPrev = 0.0, tHitB = 0.0;
  bool hit = false;
  float k = 0.0, t = t0;
  // Loops test their exit at the bottom, as castRay's walks do (t0 < t1 here).
  do {
    float f = volumeTexValue(ray.base + t * ray.slope) - wu.isoValue;
    if (hasPrev && (f >= 0.0) != (fPrev >= 0.0)) {
      // Refined after the march, as castRay does (once per SIMD group of rays on a software rasterizer).
      tHitB = t;
      hit = true;
      break;
    }
    hasPrev = true;
    tPrev = t;
    fPrev = f;
    k += 1.0;
    t = t0 + k * dt;
  } while (t < t1);
  if (!hit) return result;
  float ta = tPrev, fa = fPrev, tb = tHitB;
  for (int i = 0; i < ISO_BISECTION_STEPS; ++i) {
    float tm = 0.5 * (ta + tb);
    float fm = volumeValueExact(volumeCoord(eye + tm * dir, wu.spacing), dims) - wu.isoValue;
    if ((fm >= 0.0) == (fa >= 0.0)) {
      ta = tm;
      fa = fm;
    } else {
      tb = tm;
    }
  }
  float tHit = 0.5 * (ta + tb);
  vec3 hitCoord = volumeCoord(eye + tHit * dir, wu.spacing);
  result.color = vec4(shadeIso(volumeGradientExact(hitCoord, dims, wu.spacing), dir), 1.0);
  result.depth = tHit * depthPerT;
#else
  // Up to four samples per loop test: on llvmpipe that amortizes the loop's own masked bookkeeping (~10 %), as
  // walkDvr's straight samples per leaf-change check do. Three cost brute force the same (172.3 vs 172.4 M
  // instructions per ML DVR frame); walkDvr takes three, since its lanes also idle at leaf ends.
  DvrAccum acc;
  acc.color = vec3(0.0);
  acc.alpha = 0.0;
  acc.depth = kInfinity;
  vec4 scale = vec4(1.0 / (2.0 * wu.spacing), wu.level0.y);
  float k = 0.0, t = t0;
  do {
    bool terminated = bruteDvrStep(acc, k, t, t0, dt, ray, scale, dir, depthPerT, wu);
    if (!terminated && t < t1) terminated = bruteDvrStep(acc, k, t, t0, dt, ray, scale, dir, depthPerT, wu);
    if (!terminated && t < t1) terminated = bruteDvrStep(acc, k, t, t0, dt, ray, scale, dir, depthPerT, wu);
    if (!terminated && t < t1) terminated = bruteDvrStep(acc, k, t, t0, dt, ray, scale, dir, depthPerT, wu);
    if (terminated) break;
  } while (t < t1);
  result.color = vec4(acc.color + (1.0 - acc.alpha) * uBackground, acc.alpha);
  result.depth = acc.depth;
#endif
  return result;
}

void main() {
  RayResult r = castBrute(uvec2(gl_FragCoord.xy));
  outColor = r.color;
  outDepth = r.depth;
}
