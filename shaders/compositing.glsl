// What a ray does with the samples of a segment (docs/RENDERING.md "Isosurface", "Direct volume rendering",
// "Maximum intensity projection"): the isosurface march to the first sign change and its bisection,
// front-to-back DVR compositing with early ray termination, and the largest value along the ray. Shared by
// the rope ray caster, which calls them once per data leaf (Gobbetti et al. 2008, Sect. 5.2), and the
// brute-force pass, which calls them once for the whole volume. No #version line. Needs the defines
// ISO_BISECTION_STEPS, DVR_DEPTH_OPACITY and those of shaders/shading.glsl.

#include "shaders/sampling.glsl"
#include "shaders/shading.glsl"

struct RayResult {
  vec4 color;   // final color (background composited), alpha = coverage
  float depth;  // world distance along the camera axis; +inf for none
  // Where the ray stopped, as depth: its last sample (the first past the isosurface, or the one at which early
  // ray termination ended it); +inf when it left the volume. What hides the boxes of the occlusion queries
  // (Gobbetti et al. 2008, Sect. 6).
  float stopDepth;
};

RayResult missedRay() { return RayResult(vec4(raycast.background, 0.0), kInfinity, kInfinity); }

// The isosurface march along the ray: f = v - vIso at each sample, remembered across segments.
struct IsoMarch {
  bool hasPrev;        // a sample before this one (the ray's first sample has none)
  float tPrev, fPrev;  // the last sample
  bool hit;
  float tHit;          // the first sample whose sign of f differs from tPrev's (f >= 0 counts as positive)
  bool capsFirst;      // the ray entered through a capped cut (Ray.capNormal): a first sample with f >= 0 hits
  bool cap;            // the hit is such a first sample
};

IsoMarch isoMarchBegin(Ray ray) {
  return IsoMarch(false, 0.0, 0.0, false, 0.0, ray.capNormal != vec3(0.0), false);
}

// The cap at the ray's first sample, at t (docs/RENDERING.md "Caps").
void isoMarchCap(inout IsoMarch m, float t) {
  m.hit = true;
  m.tHit = t;
  m.cap = true;
}

// Takes the sample at t: a crossing when its sign of f differs from the previous sample's (or a cap, when it
// is the first and inside the surface), else the new previous sample.
void isoMarchSample(inout IsoMarch m, Segment s, float t) {
  float f = sampleValue(segmentCoord(s, t)) - raycast.isoValue;
  if (!m.hasPrev && m.capsFirst && f >= 0.0) {
    isoMarchCap(m, t);
  } else if (m.hasPrev && (f >= 0.0) != (m.fPrev >= 0.0)) {
    m.hit = true;
    m.tHit = t;
  } else {
    m.hasPrev = true;
    m.tPrev = t;
    m.fPrev = f;
  }
}

// The samples t0 + k dt of a segment, from k = kBegin while t < tEnd, up to the first crossing. When the
// march's last sample then lies more than a texel of this brick before tEnd (a step above a voxel, or a
// corner of a leaf crossed between two samples), one more is taken at tEnd: no later sample of this brick sees
// a crossing between them, and the next leaf's may not either, for an empty leaf takes none. Within a texel
// of the face no crossing can hide: an empty neighbour's value range covers its border, two texels deep
// (docs/RENDERING.md "Isosurface"). True when it took a sample.
bool marchIso(inout IsoMarch m, Segment s, float t0, float kBegin, float tEnd) {
  bool sampled = false;
  for (float k = kBegin; !m.hit; k += 1.0) {
    float t = t0 + k * s.dt;
    if (!(t < tEnd)) break;
    sampled = true;
    isoMarchSample(m, s, t);
  }
  if (m.hasPrev && !m.hit && any(greaterThan(abs(s.texelPerT * (tEnd - m.tPrev)), vec3(1.0)))) {
    sampled = true;
    isoMarchSample(m, s, tEnd);
  }
  return sampled;
}

// The hit of a march, refined by bisection between the samples around the crossing and shaded there, both
// within one brick: a brick holds its neighbours' samples only BRICK_BORDER texels deep and valueExact clamps
// to its slot, so a bracket or a central difference reaching further reads clamped texels (wrong hits and
// normals at brick borders once the step exceeds about a voxel). `s` is the segment of the hit's sample, which
// the ray entered at tEnter; `before` is that of the previous sample, which it left at beforeExit. When the
// previous sample lies before tEnter and farther out than a central difference around it may reach (1.5
// texels inside the slot), the bracket is split at the entry: the crossing is refined in `s` from its entry
// when f there still has the previous sample's sign, else in `before` up to its exit. Either part lies inside
// its leaf's box, so the bisection and the gradient (one texel either side) stay in the brick; a bracket that
// needs no split is the brute-force pass's.
RayResult shadeIsoHit(IsoMarch m, Segment s, float tEnter, Segment before, float beforeExit, Ray ray) {
  float ta = m.tPrev, fa = m.fPrev, tb = m.tHit;
  vec3 texelPrev = segmentTexel(s, ta);
  if (ta < tEnter && (any(lessThan(texelPrev, vec3(1.5))) || any(greaterThan(texelPrev, s.texelCount - 1.5)))) {
    float fEnter = valueExact(s, segmentTexel(s, tEnter)) - raycast.isoValue;
    if ((fEnter >= 0.0) == (fa >= 0.0)) {
      ta = tEnter;
      fa = fEnter;
    } else {
      s = before;
      tb = min(beforeExit, tEnter);
    }
  }
  for (int i = 0; i < ISO_BISECTION_STEPS; ++i) {
    float tm = 0.5 * (ta + tb);
    float fm = valueExact(s, segmentTexel(s, tm)) - raycast.isoValue;
    if ((fm >= 0.0) == (fa >= 0.0)) {
      ta = tm;
      fa = fm;
    } else {
      tb = tm;
    }
  }
  float tHit = 0.5 * (ta + tb);
  // The ray stops at the last sample it visited, past the crossing: a leaf whose front face holds the surface
  // exactly is seen.
  return RayResult(vec4(shadeIso(gradientExact(s, tHit), ray.dir), 1.0), tHit * ray.depthPerT,
                   m.tHit * ray.depthPerT);
}

// A cap (IsoMarch.cap): the headlight on the cut's plane at the first sample, where the ray stops.
RayResult shadeIsoCap(IsoMarch m, Ray ray) {
  float depth = m.tHit * ray.depthPerT;
  return RayResult(vec4(shadeIso(ray.capNormal, ray.dir), 1.0), depth, depth);
}

// Front-to-back DVR compositing, premultiplied.
struct DvrAccum {
  vec3 color;
  float alpha;
  float depth;      // of the sample at which alpha reached DVR_DEPTH_OPACITY, else of the last that added opacity
  float lastDepth;  // of the last sample that added opacity: where early ray termination stopped the ray
};

DvrAccum dvrAccumBegin() { return DvrAccum(vec3(0.0), 0.0, kInfinity, kInfinity); }

// Composites sample k of a segment; true when early ray termination ends the ray (as the CPU mirror: only a
// sample that adds opacity ends it).
bool compositeDvrSample(inout DvrAccum acc, Segment s, Ray ray, float k) {
  float t = ray.t0 + k * s.dt;
  DvrSample voxel = dvrSample(segmentCoord(s, t));
  vec4 tf = transferFunction(voxel.value);
  float alpha = correctedOpacity(tf.a, s.opacityExponent);
  if (!(alpha > 0.0)) return false;
#ifdef DVR_UNLIT
  vec3 color = tf.rgb;  // --shading off: no gradient is taken
#else
  vec3 color = shadeDvr(tf.rgb, dvrSampleDifferences(voxel) * s.gradientScale, ray.dir);
#endif
  acc.lastDepth = t * ray.depthPerT;
  if (acc.alpha < DVR_DEPTH_OPACITY) acc.depth = acc.lastDepth;
  acc.color += (1.0 - acc.alpha) * alpha * color;
  acc.alpha += (1.0 - acc.alpha) * alpha;
  return acc.alpha >= raycast.ert;
}

// Composites samples k in [kBegin, kEnd) of a segment; true when early ray termination ends the ray.
bool compositeDvr(inout DvrAccum acc, Segment s, Ray ray, float kBegin, float kEnd) {
  for (float k = kBegin; k < kEnd; k += 1.0)
    if (compositeDvrSample(acc, s, ray, k)) return true;
  return false;
}

RayResult dvrResult(DvrAccum acc) {
  float stopDepth = acc.alpha >= raycast.ert ? acc.lastDepth : kInfinity;
  return RayResult(vec4(acc.color + (1.0 - acc.alpha) * raycast.background, acc.alpha), acc.depth, stopDepth);
}

// Maximum intensity projection (MIP_SIGN 1) and minimum intensity projection (MIP_SIGN -1, the largest of
// -v): the largest signed value MIP_SIGN v along the ray and the first sample that reached it (front to back,
// so a plateau's nearest sample gives the depth). A later sample may be larger: the walk ends a ray only when
// its maximum can grow no more (shaders/raycast_common.glsl).
struct MipMax {
  float value;  // of MIP_SIGN v, in [-1, 1]; -2 before the first sample
  float t;
};

MipMax mipBegin() { return MipMax(-2.0, kInfinity); }

// Takes samples k in [kBegin, kEnd) of a segment.
void marchMip(inout MipMax m, Segment s, float t0, float kBegin, float kEnd) {
  for (float k = kBegin; k < kEnd; k += 1.0) {
    float t = t0 + k * s.dt;
    float v = MIP_SIGN * sampleValue(segmentCoord(s, t));
    if (v > m.value) {
      m.value = v;
      m.t = t;
    }
  }
}

// The projected value through the transfer function, over the background by its opacity (not corrected for
// a step: it is one value, not a stretch of the ray). A ray whose value the function leaves transparent shows
// the background and has no depth. Its stop depth is infinite: nothing opaque stopped it, so it hides no
// occlusion query's box.
RayResult mipResult(MipMax m, float depthPerT) {
  vec4 tf = m.value >= -1.0 ? transferFunction(MIP_SIGN * m.value) : vec4(0.0);
  if (!(tf.a > 0.0)) return missedRay();
  return RayResult(vec4(tf.a * tf.rgb + (1.0 - tf.a) * raycast.background, tf.a), m.t * depthPerT, kInfinity);
}

// Average intensity projection: the mean value over the ray's part in the drawn box. Each sample stands for
// the stretch of its leaf within half a step of it, the leaf's first also for the stretch before it and its
// last for the one after it up to the leaf's end, so that the samples of a leaf cover its part of the ray
// once whatever its level's step (a midpoint rule: a ramp's mean is exact); a leaf the ray crosses between
// two grid points of its step takes one sample at the middle of the crossing (else a coarse leaf's corner
// would count as zeros, a dark seam). The sum is divided by the part's length, so that empty leaves, which
// are skipped, count as the zeros they hold. The ray's depth is that of its first sample above zero.
struct AipSum {
  float sum;     // of v times the stretch each sample stands for
  float firstT;  // of the first sample above zero; kInfinity before
  bool sampled;  // a sample was taken: a ray through empty leaves alone shows the background
};

AipSum aipBegin() { return AipSum(0.0, kInfinity, false); }

// Takes samples k in [kBegin, kEnd) of a segment whose leaf the ray crosses over [tEnter, tExit).
void marchAip(inout AipSum a, Segment s, float t0, float kBegin, float kEnd, float tEnter, float tExit) {
  if (!(kBegin < kEnd) && tExit > tEnter) {
    float t = 0.5 * (tEnter + tExit);
    float v = sampleValue(segmentCoord(s, t));
    a.sum += v * (tExit - tEnter);
    a.sampled = true;
    if (v > 0.0 && a.firstT == kInfinity) a.firstT = t;
    return;
  }
  for (float k = kBegin; k < kEnd; k += 1.0) {
    float t = t0 + k * s.dt;
    float v = sampleValue(segmentCoord(s, t));
    a.sum += v * ((k + 1.0 < kEnd ? t + 0.5 * s.dt : tExit) - (k == kBegin ? tEnter : t - 0.5 * s.dt));
    a.sampled = true;
    if (v > 0.0 && a.firstT == kInfinity) a.firstT = t;
  }
}

// The mean of a ray whose part in the drawn box is `length` long, through the transfer function, over the
// background by its opacity (as mipResult). Its stop depth is infinite: nothing stopped it.
RayResult aipResult(AipSum a, float length, float depthPerT) {
  vec4 tf = a.sampled && length > 0.0 ? transferFunction(clamp(a.sum / length, 0.0, 1.0)) : vec4(0.0);
  if (!(tf.a > 0.0)) return missedRay();
  return RayResult(vec4(tf.a * tf.rgb + (1.0 - tf.a) * raycast.background, tf.a), a.firstT * depthPerT,
                   kInfinity);
}

// --mode slice: the value v at the ray's one sample, where it crosses the plane, through the transfer
// function, over the background by its opacity (as mipResult); depth there. Nothing stops behind it.
RayResult sliceResult(float v, float depth) {
  vec4 tf = transferFunction(v);
  if (!(tf.a > 0.0)) return missedRay();
  return RayResult(vec4(tf.a * tf.rgb + (1.0 - tf.a) * raycast.background, tf.a), depth, kInfinity);
}
