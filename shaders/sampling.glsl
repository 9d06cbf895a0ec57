// Rays and their samples as docs/RENDERING.md fixes them ("Rays", "Spaces"), shared by the rope ray caster
// (shaders/raycast_common.glsl) and the brute-force pass (shaders/brute_force_common.glsl): the camera ray and
// its clip to the volume box (cut to --crop), the sample grid t0 + k dt, and the value texture's samples along
// a segment of the ray. The value texture is the brick pool for the ray caster and the whole level-0 volume for brute force. The
// CPU mirror (reference/cpu_raycaster.cpp) computes the same in double. No #version line: the entry point has it.

#include "shaders/raycast_block.h"

layout(binding = kRaycastValueUnit) uniform sampler3D uValues;  // R8/R16 UNORM, LINEAR, CLAMP_TO_EDGE
#ifdef DVR_STORED_GRADIENTS
// render/gradient_pool: RGBA16_SNORM (central differences, value) of uValues, same dimensions.
layout(binding = kRaycastSampleUnit) uniform sampler3D uSamples;
#endif

const float kInfinity = uintBitsToFloat(0x7F800000u);  // +inf

struct Ray {
  vec3 origin;       // the eye, world units
  vec3 dir;          // unit direction
  float t0, t1;      // the part inside the volume box; t is a world distance along dir
  float depthPerT;   // dot(dir, forward): camera-axis depth per unit t
  // Isosurface caps: the normal of the cut the ray enters the drawn part through, pointing into it, where
  // raycast.capBounds caps that cut; zero otherwise (core/camera.h entryBound, boundInwardNormal).
  vec3 capNormal;
};

// core/camera.h pixelRay: the ray through the center of pixel (px, py), row 0 at the top.
vec3 pixelRayDir(uvec2 pixel) {
  vec2 size = vec2(raycast.imageSize);
  float x = (2.0 * (float(pixel.x) + 0.5) / size.x - 1.0) * raycast.tanHalfFov * raycast.aspect;
  float y = (1.0 - 2.0 * (float(pixel.y) + 0.5) / size.y) * raycast.tanHalfFov;
  return normalize(raycast.forward + x * raycast.right + y * raycast.up);
}

// The pixel's ray clipped to the box its samples lie in, [clipMin, clipMax] (the volume box cut to --crop), by
// the slab test, and to the kept side of --clip-plane (a slice: started at the plane); t0 clamped to 0. False
// on a miss. Notes the bound it
// enters through, as core/camera.h entryBound (ties to the box, then to the lower axis).
bool cameraRay(uvec2 pixel, out Ray ray) {
  ray.origin = raycast.eye;
  ray.dir = pixelRayDir(pixel);
  ray.depthPerT = dot(ray.dir, raycast.forward);
  ray.t0 = -kInfinity;
  ray.t1 = kInfinity;
  ray.capNormal = vec3(0.0);
  int bound = -1;
  for (int a = 0; a < 3; ++a) {
    if (ray.dir[a] == 0.0) {
      if (ray.origin[a] < raycast.clipMin[a] || ray.origin[a] > raycast.clipMax[a]) return false;
      continue;
    }
    float tNear = (raycast.clipMin[a] - ray.origin[a]) / ray.dir[a];
    float tFar = (raycast.clipMax[a] - ray.origin[a]) / ray.dir[a];
    if (min(tNear, tFar) > ray.t0) {
      ray.t0 = min(tNear, tFar);
      bound = ray.dir[a] > 0.0 ? a : 3 + a;
    }
    ray.t1 = min(ray.t1, max(tNear, tFar));
  }
  vec3 n = raycast.clipPlaneNormal;
#ifdef RAYCAST_MODE_SLICE
  // --mode slice: the ray starts where it crosses the plane inside the box (core/camera.h startAtPlane), its
  // one sample; t1 stays, the traversal's end.
  ray.t0 = max(ray.t0, 0.0);
  float along = dot(n, ray.dir);
  if (along == 0.0) return false;
  float t = -(dot(n, ray.origin) - raycast.clipPlaneOffset) / along;
  if (!(t >= ray.t0 && t < ray.t1)) return false;
  ray.t0 = t;
  return true;
#endif
  // --clip-plane: the part where dot(n, x) >= offset (core/camera.h clipToHalfSpace).
  if (n != vec3(0.0)) {
    float along = dot(n, ray.dir);
    float above = dot(n, ray.origin) - raycast.clipPlaneOffset;
    if (along == 0.0) {
      if (above < 0.0) return false;
    } else if (along > 0.0) {
      if (-above / along > ray.t0) {
        ray.t0 = -above / along;
        bound = 6;
      }
    } else {
      ray.t1 = min(ray.t1, -above / along);
    }
    // --slab: and where dot(n, x) <= clipPlaneFar, its far face (core/render_params.h clipToPlane).
    if (raycast.clipPlaneFar < kInfinity) {
      float farAbove = raycast.clipPlaneFar - dot(n, ray.origin);
      if (along == 0.0) {
        if (farAbove < 0.0) return false;
      } else if (along < 0.0) {
        if (farAbove / along > ray.t0) {
          ray.t0 = farAbove / along;
          bound = 7;
        }
      } else {
        ray.t1 = min(ray.t1, farAbove / along);
      }
    }
  }
  if (ray.t0 > 0.0 && bound >= 0 && (raycast.capBounds & (1u << uint(bound))) != 0u) {
    if (bound >= 6) {
      ray.capNormal = bound == 6 ? n : -n;
    } else {
      ray.capNormal[bound % 3] = bound < 3 ? 1.0 : -1.0;
    }
  }
  ray.t0 = max(ray.t0, 0.0);
  return ray.t0 < ray.t1;
}

// The first sample index k (t = t0 + k dt) with tBegin <= t. The ray's first leaf starts at k = 0, since its
// tBegin equals t0 only up to rounding in cube coordinates. One formula for a leaf's first k and the first k
// past it, so that neighbouring leaves split the grid exactly.
float firstSampleIndex(float t0, float tBegin, float dt, bool firstLeaf) {
  if (firstLeaf) return 0.0;
  float k = ceil((tBegin - t0) / dt);
  if (t0 + k * dt < tBegin) k += 1.0;
  return k;
}

// A stretch of a ray inside one brick of level L (brute force: the whole volume at level 0), over which the
// value texture's coordinate is affine in t.
struct Segment {
  vec3 coordAtZero;       // texture coordinate of the ray at t = 0 (extrapolated), for filtered lookups
  vec3 coordPerT;         // its change per unit t
  vec3 texelMin;          // the texels the segment may read: the brick's slot, or the whole volume
  vec3 texelCount;
  vec3 texelAtZero;       // texel coordinate relative to texelMin at t = 0, for exact interpolation; apart
  vec3 texelPerT;         // from coordAtZero so that it does not round with the slot's place in the pool
  vec3 gradientScale;     // 1 / (2 h), h = s 2^L: central differences to a gradient
  float dt;               // step 2^L min(s)
  float opacityExponent;  // dt / min(s) = step 2^L
};

vec3 segmentCoord(Segment s, float t) { return s.coordAtZero + t * s.coordPerT; }

// v at a texture coordinate: hardware trilinear filtering.
float sampleValue(vec3 coord) { return textureLod(uValues, coord, 0.0).r; }

// v(x + h) - v(x - h) per axis at a texture coordinate, h one texel. Samples of a leaf lie at texels
// [BRICK_BORDER, B + BRICK_BORDER] of its slot, so for BRICK_BORDER >= 2 the neighbours stay inside it.
vec3 centralDifferences(vec3 coord) {
  vec3 differences;
  for (int a = 0; a < 3; ++a) {
    vec3 h = vec3(0.0);
    h[a] = raycast.valueTexelSize[a];
    differences[a] = sampleValue(coord + h) - sampleValue(coord - h);
  }
  return differences;
}

// A DVR sample: its value, and its central differences, from the sample texture when gradients are stored
// (one lookup gives both) or from six more lookups of the values, taken only where the sample is shaded.
struct DvrSample {
  vec3 coord;
  float value;
  vec3 storedDifferences;
};

DvrSample dvrSample(vec3 coord) {
  DvrSample s;
  s.coord = coord;
#ifdef DVR_STORED_GRADIENTS
  vec4 texel = textureLod(uSamples, coord, 0.0);
  s.value = texel.a;
  s.storedDifferences = texel.rgb;
#else
  s.value = sampleValue(coord);
  s.storedDifferences = vec3(0.0);
#endif
  return s;
}

vec3 dvrSampleDifferences(DvrSample s) {
#ifdef DVR_STORED_GRADIENTS
  return s.storedDifferences;
#else
  return centralDifferences(s.coord);
#endif
}

// v at a texel coordinate relative to texelMin, interpolated in float from eight texelFetch()es and clamped to the outer texel
// centers of the segment's texels (clamp-to-edge of that brick alone). Hardware filtering of 8-bit textures
// uses 8-bit weights (llvmpipe, most GPUs): fine for marching, but the bisected isosurface hit and its normal
// would come out blocky.
float valueExact(Segment s, vec3 texel) {
  vec3 q = clamp(texel, vec3(0.5), s.texelCount - 0.5) - 0.5;
  vec3 base = clamp(floor(q), vec3(0.0), max(s.texelCount - 2.0, vec3(0.0)));
  vec3 f = q - base;
  ivec3 lo = ivec3(s.texelMin + base);
  ivec3 hi = min(lo + 1, ivec3(s.texelMin + s.texelCount) - 1);
  float c[8];
  for (int corner = 0; corner < 8; ++corner) {
    bvec3 upper = bvec3((corner & 1) != 0, (corner & 2) != 0, (corner & 4) != 0);
    c[corner] = texelFetch(uValues, mix(lo, hi, upper), 0).r;
  }
  return mix(mix(mix(c[0], c[1], f.x), mix(c[2], c[3], f.x), f.y),
             mix(mix(c[4], c[5], f.x), mix(c[6], c[7], f.x), f.y), f.z);
}

vec3 segmentTexel(Segment s, float t) { return s.texelAtZero + t * s.texelPerT; }

// The gradient at t by central differences of valueExact, h one texel of the segment's level.
vec3 gradientExact(Segment s, float t) {
  vec3 texel = segmentTexel(s, t);
  vec3 differences;
  for (int a = 0; a < 3; ++a) {
    vec3 h = vec3(0.0);
    h[a] = 1.0;
    differences[a] = valueExact(s, texel + h) - valueExact(s, texel - h);
  }
  return differences * s.gradientScale;
}
