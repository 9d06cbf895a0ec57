#include "reference/cpu_raycaster.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <optional>
#include <string>
#include <thread>
#include <type_traits>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "core/error.h"
#include "index/rope_traversal.h"
#include "reference/volume_sampler.h"

namespace ropecast {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Traced rays record the sample at a leaf's end from this distance (texels) on, taken or not.
constexpr double kLeafEndTracedFromTexels = 0.5;

// Per-frame constants of the ray loop (docs/RENDERING.md).
struct FrameConstants {
  RenderParams params;
  const TfTable* tf = nullptr;
  double isoNormalized = 0.0;  // vIso = mapping.toStored(iso) / storedMax
  double sign = 1.0;           // intensity projections: projectionSign(mode)
  glm::dvec3 spacing{1.0};
  double minSpacing = 1.0;
  WorldBox sampled;        // the volume box [0, n s] cut to --crop: the rays' clip
  uint32_t capBounds = 0;  // capBoundsOf: the cuts that cap an isosurface
  glm::dvec3 eye{0.0};
  glm::dvec3 forward{0.0};

  FrameConstants(const BrickSourceInfo& volume, const CpuRenderInput& input)
      : params(input.params), tf(input.tf) {
    if (usesTransferFunction(params.mode) && tf == nullptr)
      throw Error("CPU ray caster: " + std::string(renderModeName(params.mode)) +
                  " mode needs a baked transfer function (CpuRenderInput::tf)");
    if (!(params.stepVoxels > 0.0)) throw Error("CPU ray caster: --step must be positive");
    if (input.width == 0 || input.height == 0) throw Error("CPU ray caster: image size must be positive");
    const double storedMax = storedMaxOf(volume.storedType);
    isoNormalized = volume.mapping.toStored(params.isoValue) / storedMax;
    sign = projectionSign(params.mode);
    spacing = volume.volume.spacing;
    minSpacing = std::min({spacing.x, spacing.y, spacing.z});
    sampled = sampledWorldBox(params, volume.volume.dims, spacing);
    capBounds = capBoundsOf(params, volume.volume.dims);
    eye = input.camera.eye;
    forward = cameraFrame(input.camera).forward;
  }
};

// The ray's part inside the crop box and on the kept side of the clip plane, or in its slab
// (docs/RENDERING.md "Rays"); a slice's from the plane on. `entry`: the bound it enters through
// (core/camera.h entryBound).
bool clipToSampled(const FrameConstants& fc, const Ray& ray, double& t0, double& t1, int& entry) {
  // A slice's ray starts where it crosses the plane inside the box, its one sample.
  if (fc.params.mode == RenderMode::Slice)
    return clipToBox(ray, fc.sampled, t0, t1) &&
           startAtPlane(ray, fc.params.clipPlane.normal, fc.params.clipPlane.offset(), t0, t1);
  return clipToBox(ray, fc.sampled, t0, t1, &entry) && clipToPlane(ray, fc.params.clipPlane, t0, t1, &entry);
}

// Central differences with h_i = s_i * 2^L (docs/RENDERING.md "Isosurface").
template <class Sampler>
glm::dvec3 gradientAt(const Sampler& s, glm::dvec3 x, glm::dvec3 cell) {
  glm::dvec3 g;
  for (int a = 0; a < 3; ++a) {
    glm::dvec3 h(0.0);
    h[a] = cell[a];
    g[a] = (s.value(x + h) - s.value(x - h)) / (2.0 * cell[a]);
  }
  return g;
}

// The front-to-back ray loop shared by the mirror and the reference: fed the ray's data segments in order.
class RayIntegrator {
 public:
  // `entry`: the bound the ray entered the drawn part through (clipToSampled).
  RayIntegrator(const FrameConstants& fc, const Ray& ray, double t0, double t1, int entry)
      : fc_(fc), ray_(ray), t0_(t0), t1_(t1) {
    if (entry != kEntryNone && (fc.capBounds & (1u << entry)) != 0)
      capNormal_ = boundInwardNormal(entry, fc.params.clipPlane.normal);
  }

  // Isosurface caps: whether the ray entered through a capped cut, and has taken no sample yet.
  bool capsNextSample() const { return capNormal_ != glm::dvec3(0.0) && !hasPrev_ && !ended_; }
  bool capped() const { return capNormal_ != glm::dvec3(0.0); }

  // A solid leaf (LeafKind::Solid) of level `level` over [tEnter, tExit): its first sample on the ray's grid,
  // if it holds one, is the ray's first and caps it, as shaders/raycast_common.glsl castRay. False once the
  // ray is finished.
  bool solidLeaf(double tEnter, double tExit, uint32_t level, bool fromEntry) {
    if (!capsNextSample()) return !ended_;
    const double dt = levelStep(level);
    const double t = t0_ + firstSampleIndex(tEnter, dt, fromEntry) * dt;
    if (t < std::min(tExit, t1_)) shadeCap(t);
    return !ended_;
  }

  // Samples [tEnter, tExit) at level `level` with `sampler`; false once the ray is finished (iso hit, ERT).
  // `fromEntry`: the segment is the first the traversal reports, so it starts at t0 and its first sample is
  // t0 itself even where the float traversal rounded tEnter just above t0 (as the shader does). With `visit`,
  // records the samples, and goes on sampling (without changing the image) after the ray has finished.
  template <class Sampler>
  bool march(double tEnter, double tExit, uint32_t level, const Sampler& sampler, bool fromEntry,
             MirrorLeafVisit* visit = nullptr) {
    const double levelScale = std::ldexp(1.0, int(level));
    const double dt = levelStep(level);
    const glm::dvec3 cell = fc_.spacing * levelScale;
    const double tStop = std::min(tExit, t1_);
    double k = firstSampleIndex(tEnter, dt, fromEntry);
    if (visit) {
      visit->dt = dt;
      visit->kBegin = k;
    }
    // Where the leaf's samples begin: the first leaf's at t0, which its float tEnter may round past.
    const double tBegin = fromEntry ? std::min(tEnter, t0_) : tEnter;
    const double firstT = t0_ + k * dt;
    bool sampled = false;
    for (double t = t0_ + k * dt; t < tStop; k += 1.0, t = t0_ + k * dt) {
      tLastSample_ = t;
      anySample_ = true;
      const glm::dvec3 x = ray_.origin + t * ray_.dir;
      const double v = sampler.value(x);
      if (visit) {
        if (ended_) {
          traceAfterEnd(*visit, t, v, dt);
          continue;
        }
        MirrorSample m{t, v - fc_.isoNormalized, 0.0, false};
        if (fc_.params.mode == RenderMode::Dvr) {
          const double a = opacity(v, dt);
          m.addsOpacity = a > 0.0;
          m.alpha = m.addsOpacity ? alpha_ + (1.0 - alpha_) * a : alpha_;
        }
        visit->samples.push_back(m);
      }
      if (fc_.params.mode == RenderMode::Iso) {
        if (takeIsoSample(sampler, tBegin, t, v - fc_.isoNormalized, cell, visit)) {
          if (!visit) return false;
          continue;
        }
        sampled = true;
      } else if (isIntensityProjection(fc_.params.mode)) {
        // As shaders/compositing.glsl marchMip: the first sample of the largest signed value.
        if (fc_.sign * v > mipValue_) {
          mipValue_ = fc_.sign * v;
          mipT_ = t;
        }
      } else if (fc_.params.mode == RenderMode::Aip) {
        // As shaders/compositing.glsl marchAip: each sample's value times the stretch of the leaf it stands
        // for.
        const double next = t0_ + (k + 1.0) * dt;
        aipSum_ += v * ((next < tStop ? t + 0.5 * dt : tStop) - (t == firstT ? tBegin : t - 0.5 * dt));
        aipSampled_ = true;
        if (v > 0.0 && mipT_ == kInf) mipT_ = t;
      } else if (compositeDvr(sampler, x, v, dt, cell)) {
        ended_ = true;
        if (visit) endSample_ = visit->samples.size() - 1;
        if (!visit) return false;
      }
    }
    // As shaders/compositing.glsl marchAip: a leaf crossed between two grid points takes a sample at the
    // middle of the crossing (not traced: the shader's feedback counts the grid's samples).
    if (fc_.params.mode == RenderMode::Aip && !(firstT < tStop) && tStop > tBegin) {
      const double t = 0.5 * (tBegin + tStop);
      const double v = sampler.value(ray_.origin + t * ray_.dir);
      aipSum_ += v * (tStop - tBegin);
      aipSampled_ = true;
      if (v > 0.0 && mipT_ == kInf) mipT_ = t;
    }
    // As shaders/compositing.glsl marchIso: one more sample at the leaf's end when the ray's last sample lies
    // more than a texel of this leaf's level before it (traced rays: the last sample, as if the ray had gone
    // on). The shader measures that distance in float; the trace keeps the sample from half a texel on, so
    // that the feedback twin can judge the decisions within rounding of a texel.
    if (fc_.params.mode == RenderMode::Iso && anySample_) {
      const glm::dvec3 gap = glm::abs(ray_.dir * (tStop - tLastSample_) / cell);
      const double texels = std::max({gap.x, gap.y, gap.z});
      const bool taken = texels > 1.0;
      if (taken || (visit && texels > kLeafEndTracedFromTexels)) {
        const double f = sampler.value(ray_.origin + tStop * ray_.dir) - fc_.isoNormalized;
        if (visit)
          visit->samples.push_back(
              {.t = tStop, .f = f, .atLeafEnd = true, .leafEndTaken = taken, .leafEndGapTexels = texels});
        if (taken) {
          tLastSample_ = tStop;
          if (!ended_) {
            if (takeIsoSample(sampler, tBegin, tStop, f, cell, visit)) return false;
            sampled = true;
          }
        }
      }
    }
    // The leaf of the previous sample, for a crossing found in a later leaf (only the mirror has more than
    // one).
    if (sampled && !ended_) {
      if constexpr (std::is_same_v<Sampler, BrickSampler>) before_ = Before{sampler, tStop, cell};
    }
    return !ended_;
  }

  // --mode slice: the ray's one sample, at t0 where it crosses the plane, at level `level` with `sampler`, as
  // shaders/raycast_common.glsl castRay. With `visit`, records it.
  template <class Sampler>
  void sliceSample(uint32_t level, const Sampler& sampler, MirrorLeafVisit* visit = nullptr) {
    const double v = sampler.value(ray_.origin + t0_ * ray_.dir);
    mipValue_ = v;
    mipT_ = t0_;
    if (visit) {
      visit->dt = levelStep(level);
      visit->kBegin = 0.0;
      visit->samples.push_back({t0_, v - fc_.isoNormalized, 0.0, false});
    }
  }

  // The sample step at level L: dt = step 2^L min(s).
  double levelStep(uint32_t level) const {
    return fc_.params.stepVoxels * std::ldexp(1.0, int(level)) * fc_.minSpacing;
  }

  // The first k of a leaf entered at tEnter with t = t0 + k dt >= tEnter: the grid is anchored at the volume
  // entry (shaders/sampling.glsl firstSampleIndex). The ray's first leaf starts at k = 0.
  double firstSampleIndex(double tEnter, double dt, bool fromEntry) const {
    if (fromEntry) return 0.0;
    double k = std::ceil((tEnter - t0_) / dt);
    if (t0_ + k * dt < tEnter) k += 1.0;
    return k;
  }

  // Traced rays: the sample of its leaf's visit at which the ray ended.
  size_t endSample() const { return endSample_; }
  // Intensity projections: the largest signed value so far (-2 before the first sample).
  double mipMaximum() const { return mipValue_; }

  // Final color = C + (1 - A) * background; alpha = A; depth along the camera axis. A maximum intensity
  // projection's C and A are the transfer function's at the largest value, as shaders/compositing.glsl
  // mipResult.
  void finish(float* rgba, float* depth) const {
    glm::dvec3 color = color_;
    double alpha = alpha_, rayDepth = depth_;
    // An average intensity projection's are the function's at the mean over the ray's part in the drawn box
    // (aipResult), its depth the first sample above zero's.
    const bool oneValue = ((isIntensityProjection(fc_.params.mode) || fc_.params.mode == RenderMode::Slice) &&
                           mipValue_ >= -1.0) ||
                          (fc_.params.mode == RenderMode::Aip && aipSampled_ && t1_ > t0_);
    if (oneValue) {
      const double value = fc_.params.mode == RenderMode::Aip ? std::clamp(aipSum_ / (t1_ - t0_), 0.0, 1.0)
                                                              : fc_.sign * mipValue_;
      const glm::dvec4 tf = fc_.tf->lookup(value);
      if (tf.a > 0.0) {
        color = tf.a * glm::dvec3(tf);
        alpha = tf.a;
        rayDepth = mipT_ * glm::dot(ray_.dir, fc_.forward);
      }
    }
    const glm::dvec3 c = color + (1.0 - alpha) * fc_.params.background;
    rgba[0] = float(c.r);
    rgba[1] = float(c.g);
    rgba[2] = float(c.b);
    rgba[3] = float(alpha);
    *depth = float(rayDepth);
  }

 private:
  // Phong headlight terms: (N.L, R.V) with L = V = -dir and R = reflect(-L, N).
  glm::dvec2 headlight(glm::dvec3 n) const {
    const glm::dvec3 l = -ray_.dir;
    const glm::dvec3 r = glm::reflect(-l, n);
    return {glm::dot(n, l), glm::dot(r, l)};
  }

  // Takes the iso sample (t, f): at a crossing, refines and shades the hit and ends the ray (true); else it
  // becomes the previous sample.
  template <class Sampler>
  bool takeIsoSample(const Sampler& sampler, double tBegin, double t, double f, glm::dvec3 cell,
                     const MirrorLeafVisit* visit) {
    if (capsNextSample() && f >= 0.0) {
      shadeCap(t);
      if (visit) endSample_ = visit->samples.size() - 1;
      return true;
    }
    if (hasPrev_ && (f >= 0.0) != (fPrev_ >= 0.0)) {
      hitIso(sampler, tBegin, t, cell);
      ended_ = true;
      if (visit) endSample_ = visit->samples.size() - 1;
      return true;
    }
    hasPrev_ = true;
    tPrev_ = t;
    fPrev_ = f;
    return false;
  }

  // The crossing between the previous sample and the sample at tb of the leaf `sampler` entered at tBegin,
  // refined and shaded in one brick, as shaders/compositing.glsl shadeIsoHit: split at the entry when the
  // previous sample lies in an earlier leaf, farther out of this brick than a central difference may reach.
  template <class Sampler>
  void hitIso(const Sampler& sampler, double tBegin, double tb, glm::dvec3 cell) {
    double ta = tPrev_, fa = fPrev_;
    if constexpr (std::is_same_v<Sampler, BrickSampler>) {
      const glm::dvec3 texelPrev = sampler.texel(ray_.origin + ta * ray_.dir);
      const double reach = double(sampler.edge()) - 1.5;
      const bool outside = glm::any(glm::lessThan(texelPrev, glm::dvec3(1.5))) ||
                           glm::any(glm::greaterThan(texelPrev, glm::dvec3(reach)));
      if (ta < tBegin && outside) {
        const double fEnter = sampler.value(ray_.origin + tBegin * ray_.dir) - fc_.isoNormalized;
        if ((fEnter >= 0.0) == (fa >= 0.0)) {
          ta = tBegin;
          fa = fEnter;
        } else if (before_) {
          return shadeIsoHit(before_->sampler, ta, fa, std::min(before_->exit, tBegin), before_->cell);
        }
      }
    }
    shadeIsoHit(sampler, ta, fa, tb, cell);
  }

  template <class Sampler>
  void shadeIsoHit(const Sampler& sampler, double ta, double fa, double tb, glm::dvec3 cell) {
    for (int i = 0; i < kIsoBisectionSteps; ++i) {
      const double tm = 0.5 * (ta + tb);
      const double fm = sampler.value(ray_.origin + tm * ray_.dir) - fc_.isoNormalized;
      if ((fm >= 0.0) == (fa >= 0.0)) {
        ta = tm;
        fa = fm;
      } else {
        tb = tm;
      }
    }
    const double tHit = 0.5 * (ta + tb);
    const glm::dvec3 x = ray_.origin + tHit * ray_.dir;
    shadeIso(x, gradientAt(sampler, x, cell));
  }

  // A cap at the ray's first sample t: the cut's normal for the gradient (docs/RENDERING.md "Caps").
  void shadeCap(double t) {
    shadeIso(ray_.origin + t * ray_.dir, capNormal_);
    ended_ = true;
  }

  // The surface at x with gradient g: normal -g / |g| (-dir where g vanishes), facing the viewer.
  void shadeIso(glm::dvec3 x, glm::dvec3 g) {
    const double len = glm::length(g);
    glm::dvec3 n = len > 0.0 ? -g / len : -ray_.dir;
    if (glm::dot(n, -ray_.dir) < 0.0) n = -n;
    const LightingParams& lp = fc_.params.lighting;
    const glm::dvec2 terms = headlight(n);
    color_ = lp.isoBaseColor * (lp.ambient + lp.diffuse * std::max(terms.x, 0.0)) +
             glm::dvec3(lp.specular * std::pow(std::max(terms.y, 0.0), lp.shininess));
    alpha_ = 1.0;
    depth_ = glm::dot(x - fc_.eye, fc_.forward);
  }

  // The opacity of a DVR sample of value v over a step dt.
  double opacity(double v, double dt) const {
    return 1.0 - std::pow(1.0 - fc_.tf->lookup(v).a, dt / fc_.minSpacing);
  }

  // A traced sample after the ray ended: its f, and the opacity accumulated on as if the ray went on.
  void traceAfterEnd(MirrorLeafVisit& visit, double t, double v, double dt) {
    MirrorSample m{t, v - fc_.isoNormalized, 0.0, false};
    if (fc_.params.mode == RenderMode::Dvr) {
      const double a = opacity(v, dt);
      m.addsOpacity = a > 0.0;
      if (m.addsOpacity) traceAlpha_ += (1.0 - traceAlpha_) * a;
      m.alpha = traceAlpha_;
    }
    visit.samples.push_back(m);
  }

  // One DVR sample; true when early ray termination ends the ray.
  template <class Sampler>
  bool compositeDvr(const Sampler& sampler, glm::dvec3 x, double v, double dt, glm::dvec3 cell) {
    const glm::dvec4 tf = fc_.tf->lookup(v);
    const double a = 1.0 - std::pow(1.0 - tf.a, dt / fc_.minSpacing);
    if (!(a > 0.0)) return false;
    glm::dvec3 c(tf);
    // --shading off: the color as it is, no gradient taken.
    const glm::dvec3 g = fc_.params.lighting.dvrShading ? gradientAt(sampler, x, cell) : glm::dvec3(0.0);
    const double len = glm::length(g);
    if (len * fc_.minSpacing > kDvrShadeGradientThreshold) {
      const LightingParams& lp = fc_.params.lighting;
      const glm::dvec2 terms = headlight(-g / len);
      c = c * (lp.ambient + lp.diffuse * std::abs(terms.x)) +
          glm::dvec3(lp.specular * std::pow(std::abs(terms.y), lp.shininess));
    }
    if (alpha_ < kDvrDepthOpacity) depth_ = glm::dot(x - fc_.eye, fc_.forward);
    color_ += (1.0 - alpha_) * a * c;
    alpha_ += (1.0 - alpha_) * a;
    traceAlpha_ = alpha_;
    return alpha_ >= fc_.params.ert;
  }

  const FrameConstants& fc_;
  const Ray& ray_;
  double t0_, t1_;
  glm::dvec3 capNormal_{0.0};  // the capped cut the ray entered through, pointing in; zero: none
  bool ended_ = false;         // by an iso hit or early ray termination
  size_t endSample_ = 0;
  double traceAlpha_ = 0.0;  // traced rays: the opacity accumulated on past the end
  bool hasPrev_ = false;
  double tPrev_ = 0.0, fPrev_ = 0.0;
  // The ray's last sample (iso), which traced rays follow on past the end: tPrev_ until the ray ends.
  bool anySample_ = false;
  double tLastSample_ = 0.0;
  // The mirror's leaf of the previous sample: its brick, where the ray left it, its cell.
  struct Before {
    BrickSampler sampler;
    double exit;
    glm::dvec3 cell;
  };
  std::optional<Before> before_;
  glm::dvec3 color_{0.0};
  double alpha_ = 0.0;
  double depth_ = kInf;
  // Intensity projections: the largest signed value (sign v, in [-1, 1]) so far, -2 before the first sample,
  // and its t; the average intensity projection's t of its first sample above zero; a slice's sample.
  double mipValue_ = -2.0;
  double mipT_ = kInf;
  // The average intensity projection: the sum of v dt, and whether a sample was taken.
  double aipSum_ = 0.0;
  bool aipSampled_ = false;
};

// Runs pixel(x, y, rgba, depth) for every pixel, rows interleaved over the threads.
template <class PixelFn>
CpuImage renderRows(const CpuRenderInput& input, const PixelFn& pixel) {
  CpuImage img;
  img.width = input.width;
  img.height = input.height;
  img.rgba.assign(size_t(4) * input.width * input.height, 0.0f);
  img.depth.assign(size_t(input.width) * input.height, float(kInf));
  const unsigned threadCount = std::clamp(input.threads, 1u, input.height);
  std::vector<std::exception_ptr> errors(threadCount);
  const auto rows = [&](unsigned first) {
    try {
      for (uint32_t y = first; y < input.height; y += threadCount)
        for (uint32_t x = 0; x < input.width; ++x) {
          const size_t i = size_t(y) * input.width + x;
          pixel(x, y, &img.rgba[4 * i], &img.depth[i]);
        }
    } catch (...) {
      errors[first] = std::current_exception();
    }
  };
  std::vector<std::thread> workers;
  for (unsigned t = 1; t < threadCount; ++t) workers.emplace_back(rows, t);
  rows(0);
  for (std::thread& w : workers) w.join();
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
  return img;
}

void writeMiss(const FrameConstants& fc, float* rgba, float* depth) {
  rgba[0] = float(fc.params.background.r);
  rgba[1] = float(fc.params.background.g);
  rgba[2] = float(fc.params.background.b);
  rgba[3] = 0.0f;
  *depth = float(kInf);
}

}  // namespace

BricksBySlot readCutBricks(const Cut& cut, const BrickSource& source) {
  BricksBySlot bricks;
  for (const CutLeaf& leaf : cut.leaves) {
    if (leaf.kind != LeafKind::Data) continue;
    std::vector<std::byte>& b = bricks[leaf.brickSlot];
    b.resize(source.brickBytes());
    source.readBrick({leaf.depth, leaf.coord}, b);
  }
  return bricks;
}

CpuImage renderMirror(const RopeIndex& index, const BricksBySlot& bricks, const BrickSourceInfo& volume,
                      const CpuRenderInput& input, std::vector<MirrorRayTrace>* traces) {
  const FrameConstants fc(volume, input);
  const OctreeLayout& layout = volume.layout;
  const size_t brickBytes = size_t(layout.storedBrickSamples()) * bytesPerSample(volume.storedType);
  for (const auto& [slot, b] : bricks)
    if (b.size() != brickBytes)
      throw Error("renderMirror: brick of slot " + std::to_string(slot) + " has " + std::to_string(b.size()) +
                  " bytes, expected " + std::to_string(brickBytes));
  // Root cube coordinates: u = x / (C s) per axis; the traversal's t stays the world t.
  const glm::dvec3 cubeWorld = double(layout.cubeSamples()) * fc.spacing;
  if (traces) traces->assign(size_t(input.width) * input.height, MirrorRayTrace{});

  return renderRows(input, [&](uint32_t px, uint32_t py, float* rgba, float* depth) {
    const Ray ray = pixelRay(input.camera, input.width, input.height, px, py);
    double t0, t1;
    int entry = kEntryNone;
    if (!clipToSampled(fc, ray, t0, t1, entry)) return writeMiss(fc, rgba, depth);
    // The GPU clips in float: anchor the sample grid where the shader does.
    t0 = double(float(t0));
    t1 = double(float(t1));
    MirrorRayTrace* trace = traces ? &(*traces)[size_t(py) * input.width + px] : nullptr;
    if (trace) {
      trace->entered = true;
      trace->t0 = t0;
      trace->t1 = t1;
    }
    RayIntegrator rayLoop(fc, ray, t0, t1, entry);
    if (trace) trace->capped = rayLoop.capped();
    size_t endLeaf = 0, endSample = 0;
    bool ended = false;
    RopeCursor cursor;
    RopeLeaf leaf;
    if (ropeBegin(cursor, index, glm::vec3(ray.origin / cubeWorld), glm::vec3(ray.dir / cubeWorld), float(t0),
                  float(t1))) {
      bool entryLeaf = true;
      while (ropeNextLeaf(cursor, index, leaf)) {
        const bool firstLeaf = entryLeaf;
        entryLeaf = false;
        if (leaf.kind == kRopeTagSolidLeaf && rayLoop.capsNextSample()) {
          if (!rayLoop.solidLeaf(leaf.tEnter, leaf.tExit, layout.levelOfDepth(leaf.depth), firstLeaf)) break;
          continue;
        }
        if (leaf.kind != kRopeTagDataLeaf && fc.params.mode == RenderMode::Slice) break;
        if (leaf.kind != kRopeTagDataLeaf) continue;  // empty leaves are skipped without sampling
        if (leaf.depth > layout.maxDepth)
          throw Error("renderMirror: a leaf at depth " + std::to_string(leaf.depth) +
                      " is deeper than the volume's octree (" + std::to_string(layout.maxDepth) + ")");
        const auto it = bricks.find(leaf.brickSlot);
        if (it == bricks.end())
          throw Error("renderMirror: no brick for slot " + std::to_string(leaf.brickSlot));
        const NodeKey node{
            leaf.depth, glm::u32vec3(glm::round(glm::dvec3(leaf.boxMin) * double(ropeBoxScale(leaf.depth))))};
        const BrickSampler sampler(it->second.data(), volume.storedType, layout, node, fc.spacing);
        MirrorLeafVisit* visit = nullptr;
        if (trace) {
          visit = &trace->leaves.emplace_back();
          visit->leafIndex = leaf.leafIndex;
          visit->depth = leaf.depth;
          visit->tEnter = leaf.tEnter;
          visit->tExit = leaf.tExit;
          visit->firstLeaf = firstLeaf;
        }
        // A slice's first leaf holds its one sample (an empty one, none); the ray goes no further.
        if (fc.params.mode == RenderMode::Slice) {
          rayLoop.sliceSample(layout.levelOfDepth(leaf.depth), sampler, visit);
          break;
        }
        // As shaders/raycast_common.glsl leafBelowMaximum, in float: a leaf that cannot raise the maximum is
        // not sampled (a traced ray's visit has no sample).
        if (isIntensityProjection(fc.params.mode) && leaf.leafIndex < input.leafMaxima.size()) {
          const float largest = input.leafMaxima[leaf.leafIndex], maximum = float(rayLoop.mipMaximum());
          if (visit) visit->maximumMargin = double(largest) - double(maximum);
          if (largest <= maximum) continue;
        }
        if (!rayLoop.march(leaf.tEnter, leaf.tExit, layout.levelOfDepth(leaf.depth), sampler, firstLeaf,
                           visit)) {
          if (!trace) break;
          if (!ended) {
            ended = true;
            endLeaf = trace->leaves.size() - 1;
            endSample = rayLoop.endSample();
          }
        }
      }
    }
    if (trace) {
      trace->endLeaf = ended ? endLeaf : trace->leaves.size();
      trace->endSample = ended ? endSample : 0;
    }
    rayLoop.finish(rgba, depth);
  });
}

ReferenceRenderer::ReferenceRenderer(const BrickSource& source)
    : source_(source), cache_(std::make_unique<Level0BrickCache>(source)) {}

ReferenceRenderer::~ReferenceRenderer() = default;

size_t ReferenceRenderer::bricksRead() const {
  return cache_->bricksRead();
}

CpuImage ReferenceRenderer::render(const CpuRenderInput& worldInput) const {
  CpuRenderInput input = worldInput;  // as the volume's own axes see it (store/volume_source.h)
  input.camera = cameraInVolume(worldInput.camera, source_.info().volume);
  input.params.clipPlane = clipPlaneInVolume(worldInput.params.clipPlane, source_.info().volume);
  const FrameConstants fc(source_.info(), input);
  const Level0Sampler sampler(*cache_);
  return renderRows(input, [&](uint32_t px, uint32_t py, float* rgba, float* depth) {
    const Ray ray = pixelRay(input.camera, input.width, input.height, px, py);
    double t0, t1;
    int entry = kEntryNone;
    if (!clipToSampled(fc, ray, t0, t1, entry)) return writeMiss(fc, rgba, depth);
    RayIntegrator rayLoop(fc, ray, t0, t1, entry);
    if (fc.params.mode == RenderMode::Slice)
      rayLoop.sliceSample(0, sampler);
    else
      rayLoop.march(t0, t1, 0, sampler, true);
    rayLoop.finish(rgba, depth);
  });
}

}  // namespace ropecast
