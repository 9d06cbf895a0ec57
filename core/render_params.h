// RenderParams: what a ray caster is asked to compute, independent of the data and the camera
// (docs/RENDERING.md). Plain data, GL-free; shared by the GLSL ray caster (render/raycast_pass), the CPU
// mirror and the reference renderer so that all three read the same settings. Any thread.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string_view>
#include <utility>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#include "core/camera.h"
#include "core/world_box.h"

namespace ropecast {

// The name an enum value has in a table of (name, value) pairs; "?" for none.
template <class Enum, size_t N>
constexpr std::string_view nameIn(const std::array<std::pair<std::string_view, Enum>, N>& names, Enum value) {
  for (const auto& [name, entry] : names)
    if (entry == value) return name;
  return "?";
}

// What a ray computes (docs/RENDERING.md): the first isosurface crossing, shaded; the transfer function's
// colors composited front to back (direct volume rendering); the largest or the smallest value along the
// ray mapped through the transfer function (maximum or minimum intensity projection); or the mean value along
// the ray mapped through it (average intensity projection, a radiograph's look); or the value where the ray
// crosses the clip plane mapped through it (a slice of the volume, oblique or not, in the 3D view).
enum class RenderMode { Iso, Dvr, Mip, MinIp, Aip, Slice };
// The names of `--mode`, of the viewer's script events and of --stats and bench settings.
inline constexpr std::array<std::pair<std::string_view, RenderMode>, 6> kRenderModeNames{
    {{"iso", RenderMode::Iso},
     {"dvr", RenderMode::Dvr},
     {"mip", RenderMode::Mip},
     {"minip", RenderMode::MinIp},
     {"aip", RenderMode::Aip},
     {"slice", RenderMode::Slice}}};
constexpr std::string_view renderModeName(RenderMode mode) {
  return nameIn(kRenderModeNames, mode);
}
// Whether the mode reads the transfer function (all but the isosurface).
constexpr bool usesTransferFunction(RenderMode mode) {
  return mode != RenderMode::Iso;
}
// Whether a ray shows one value, its largest or smallest (MIP or MinIP). The renderers compute both as the
// largest of projectionSign(mode) v: the smallest v is minus the largest -v.
constexpr bool isIntensityProjection(RenderMode mode) {
  return mode == RenderMode::Mip || mode == RenderMode::MinIp;
}
constexpr double projectionSign(RenderMode mode) {
  return mode == RenderMode::MinIp ? -1.0 : 1.0;
}
// Whether a ray shows one value of the transfer function without compositing it: an intensity projection's,
// the average's or the slice's. They have an opaque preset by default (gray; a slice's window), and no
// occlusion queries: no ray stops at an opaque sample (a slice's rays stop at the plane, and nothing behind
// it is drawn or loaded).
constexpr bool showsOneValue(RenderMode mode) {
  return isIntensityProjection(mode) || mode == RenderMode::Aip || mode == RenderMode::Slice;
}
// How the GL renderer draws (the CPU renderers ignore it): the octree ray caster's fragment or compute entry
// point (render/raycast_pass), brute force over level 0 in one 3D texture without an index (the benchmark
// baseline, render/brute_force_pass), the multi-pass block renderer over the same cut (each data leaf drawn
// as its own pass and composited front to back, the strategy the single pass replaces: Gobbetti et al. 2008,
// Sect. 2; render/multipass_pass), or Auto: fragment or compute, whichever suits the GL renderer
// (render/backend_choice.h resolves it).
enum class RenderBackend { Auto, Fragment, Compute, Brute, Multipass };
// The names of `ropecast render --backend` and of the "backend" field of --stats.
inline constexpr std::array<std::pair<std::string_view, RenderBackend>, 5> kRenderBackendNames{
    {{"auto", RenderBackend::Auto},
     {"fragment", RenderBackend::Fragment},
     {"compute", RenderBackend::Compute},
     {"brute", RenderBackend::Brute},
     {"multipass", RenderBackend::Multipass}}};
constexpr std::string_view renderBackendName(RenderBackend backend) {
  return nameIn(kRenderBackendNames, backend);
}
// Where a DVR sample's central-difference gradient comes from on the GPU: a texture of value and differences
// derived at upload (render/gradient_pool.h: one lookup per sample, 8 more bytes per texel of GPU memory) or
// six more lookups of the value texture per sample. The same gradient up to storage precision; the CPU
// renderers ignore it.
enum class GradientSource { Stored, Computed };

// Phong headlight constants of docs/RENDERING.md ("Isosurface", "Direct volume rendering").
struct LightingParams {
  glm::dvec3 isoBaseColor{0.9, 0.85, 0.75};  // --iso-color
  double ambient = 0.15;                     // ka  (--material KA,KD,KS,SHININESS)
  double diffuse = 0.75;                     // kd
  double specular = 0.25;                    // ks
  double shininess = 32.0;
  // --shading (DVR): off keeps the transfer function's colors unlit, as VTK's and ParaView's volume mappers
  // draw by default (dvrLightingOf).
  bool dvrShading = true;

  friend bool operator==(const LightingParams&, const LightingParams&) = default;
};

// Gradient magnitude (times min spacing) below which DVR samples are left unshaded.
inline constexpr double kDvrShadeGradientThreshold = 1e-4;
// A DVR ray's depth is that of the sample at which its accumulated opacity reaches this (where it looks
// half solid: what a probe or a depth-compositing caller wants, not its far end), else of its last sample
// that added opacity.
inline constexpr double kDvrDepthOpacity = 0.5;
// Bisection steps refining an isosurface crossing.
inline constexpr int kIsoBisectionSteps = 8;

// --crop: the part of the volume the rays sample, in level-0 voxel units (voxel i of an axis spans [i, i +
// 1), the volume [0, n)); the whole volume by default. The GL ray casters, the CPU renderers and the refiner
// cut the volume box to it (sampledWorldBox): rays are clipped to it, and nodes wholly outside it are culled,
// neither read nor uploaded. Where the box cuts an isosurface, a cap closes it (RenderParams::isoCaps).
struct CropBox {
  glm::dvec3 lo{0.0};
  glm::dvec3 hi{std::numeric_limits<double>::infinity()};

  friend bool operator==(const CropBox&, const CropBox&) = default;
};

// --clip-plane: a plane through `point` (world units) that cuts away the half-space its normal points away
// from: the rays sample only where dot(normal, x - point) >= 0, and the refiner culls nodes wholly on the
// other side. None while the normal is zero (the default). Like the crop box, it caps an isosurface it cuts.
// With --mode slice it is the slice: each ray takes one sample where it crosses the plane inside the drawn
// box, and the refiner culls every node the plane does not cross. With --slab T it keeps the slab of
// thickness T centered on the plane instead of a half-space (a thick-slab MIP of radiology), whichever way
// the normal points; a slice has no slab.
struct ClipPlane {
  glm::dvec3 point{0.0};
  glm::dvec3 normal{0.0};  // unit length, or zero for none
  double slab = 0.0;       // world units; 0: the half-space

  bool enabled() const { return normal != glm::dvec3(0.0); }
  // dot(normal, x) at the plane: the points kept have at least this (within slab / 2 of it, with a slab).
  double offset() const { return normal.x * point.x + normal.y * point.y + normal.z * point.z; }
  // The least and the largest dot(normal, x) kept: [offset, +inf), or offset -+ slab / 2.
  double keptFrom() const { return offset() - 0.5 * slab; }
  double keptTo() const {
    return slab > 0.0 ? offset() + 0.5 * slab : std::numeric_limits<double>::infinity();
  }
  friend bool operator==(const ClipPlane&, const ClipPlane&) = default;
};

// Narrows [t0, t1] to the part of the ray `plane` keeps (core/camera.h clipToHalfSpace, twice for a slab: its
// near face kEntryPlane, where the normal points in, its far face kEntryPlaneBack); false when nothing is
// left. No plane keeps everything.
inline bool clipToPlane(const Ray& ray, const ClipPlane& plane, double& t0, double& t1,
                        int* entry = nullptr) {
  if (!clipToHalfSpace(ray, plane.normal, plane.keptFrom(), t0, t1, entry)) return false;
  return !(plane.slab > 0.0) ||
         clipToHalfSpace(ray, -plane.normal, -plane.keptTo(), t0, t1, entry, kEntryPlaneBack);
}

struct RenderParams {
  RenderMode mode = RenderMode::Iso;
  double isoValue = 0.0;       // data units (mapped to stored values by the renderer)
  double stepVoxels = 0.5;     // --step: sample distance in voxels of the level being crossed
  double ert = 0.99;           // --ert: early ray termination opacity (DVR)
  glm::dvec3 background{0.0};  // --background, linear RGB in [0, 1]
  RenderBackend backend = RenderBackend::Fragment;
  // --gradients (DVR). Computed works with any pool; `ropecast render` defaults to stored, which needs a
  // GradientPool beside the pool (FrameRendererConfig::storedGradients).
  GradientSource gradients = GradientSource::Computed;
  LightingParams lighting;
  CropBox crop;         // --crop
  ClipPlane clipPlane;  // --clip-plane
  // --caps (isosurface): a ray that enters the drawn part through a cut (capBoundsOf) and whose first sample
  // lies inside the surface (v >= vIso) stops there, shaded with the cut's normal: the surface looks solid
  // where the crop box or the clip plane cuts it (docs/RENDERING.md "Caps"). Off: the ray goes on and meets
  // the surface from within.
  bool isoCaps = true;

  friend bool operator==(const RenderParams&, const RenderParams&) = default;
};

// The world box the rays sample in: the volume box [0, dims * spacing] cut to params.crop.
inline WorldBox sampledWorldBox(const RenderParams& params, glm::u32vec3 dims, glm::dvec3 spacing) {
  const glm::dvec3 n(dims);
  return {glm::clamp(params.crop.lo, glm::dvec3(0.0), n) * spacing,
          glm::clamp(params.crop.hi, glm::dvec3(0.0), n) * spacing};
}

// The bounds of the drawn part that cap an isosurface (core/camera.h entryBound numbers them): bit b for the
// crop box's face b where it lies inside the volume (a face on the volume's own boundary is no cut), bit
// kEntryPlane for the clip plane (and kEntryPlaneBack for a slab's far face). Zero unless an isosurface is
// drawn with caps.
inline uint32_t capBoundsOf(const RenderParams& params, glm::u32vec3 dims) {
  if (params.mode != RenderMode::Iso || !params.isoCaps) return 0;
  uint32_t bits = params.clipPlane.enabled() ? 1u << kEntryPlane : 0u;
  if (params.clipPlane.enabled() && params.clipPlane.slab > 0.0) bits |= 1u << kEntryPlaneBack;
  for (int a = 0; a < 3; ++a) {
    if (params.crop.lo[a] > 0.0) bits |= 1u << a;
    if (params.crop.hi[a] < double(dims[a])) bits |= 1u << (3 + a);
  }
  return bits;
}

// How a DVR sample's color is lit, which picks the ray casters' program: by gradients stored beside the pool
// (--gradients stored), by gradients computed per sample (computed), or not at all (--shading off: no
// gradient is taken). Computed for the other modes, which light no DVR sample.
enum class DvrLighting { Stored, Computed, Unlit };
inline DvrLighting dvrLightingOf(const RenderParams& params) {
  if (params.mode != RenderMode::Dvr) return DvrLighting::Computed;
  if (!params.lighting.dvrShading) return DvrLighting::Unlit;
  return params.gradients == GradientSource::Stored ? DvrLighting::Stored : DvrLighting::Computed;
}

// Whether a GL ray caster samples a GradientPool for these params.
inline bool usesStoredGradients(const RenderParams& params) {
  return dvrLightingOf(params) == DvrLighting::Stored;
}

}  // namespace ropecast
