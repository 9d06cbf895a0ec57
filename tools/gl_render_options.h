// The options `ropecast render` and `ropecast view` share (the scene and how it is drawn: the part of
// RenderOptions, tools/render_command.h, that is not about output files or frame sequences), and what both
// make of them before anything draws: the brick source, the render parameters, the transfer function table,
// the camera, the FrameRenderer's configuration. One place, so that a view and a render given the same
// options draw the same image. Main thread.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "core/camera.h"
#include "core/render_params.h"
#include "core/transfer_function.h"
#include "occlusion/visibility_tracker.h"
#include "render/frame_renderer.h"
#include "store/brick_source.h"
#include "store/octree_layout.h"
#include "tools/render_command.h"

namespace ropecast::tools {

// The default orbit (docs/ARCHITECTURE.md): azimuth, elevation (degrees), distance (bounding-sphere radii).
inline constexpr double kDefaultOrbit[3] = {30.0, 20.0, 3.0};
// The default orbit of a patient's volume (VolumeInfo::patientFrame): facing the patient, as radiology
// viewers open a 3D view, turned 30 degrees to the patient's left and raised 20 (LPS: anterior toward -y,
// left toward +x).
inline constexpr double kPatientDefaultOrbit[3] = {-60.0, 20.0, 3.0};

extern const std::vector<std::pair<std::string, RenderMode>> kModeNames;
extern const char* const kModeHelp;  // --mode's help: what each name draws
extern const std::vector<std::pair<std::string, bool>> kOnOffNames;
extern const std::vector<std::pair<std::string, GradientSource>> kGradientNames;
std::vector<std::pair<std::string, RenderBackend>> backendNames();
// The names of `ropecast render --brute-stage`: auto, fragment, compute.
extern const std::vector<std::pair<std::string, RenderBackend>> kBruteStageNames;

// Which command the scene options are for: the viewer has no brute-force backend (render's benchmark
// baseline).
enum class SceneCommand { Render, View };

// Registers the options that describe the scene and how it is drawn (mode, camera, size, budgets, backend,
// ...), not the input.
void addSceneOptions(CLI::App& app, RenderOptions& o, SceneCommand command);

// The scene options that cannot go together or cannot be a camera (--brick with a store, --brute-stage
// without --backend brute, --eye without --target, an eye on its target, an orbit of no distance, a
// visibility threshold above the image's pixels where progressive frames query), before any file is read:
// throws UsageError.
void checkSceneOptions(const RenderOptions& o);

// Says on stderr (as `who`: "render", "view") when the last frame left leaves coarser than --voxels-per-pixel
// asks for want of GPU pool slots: the image is valid but not what the option promises, so a regression
// image or a screenshot should not look finished.
void warnIfPoolLimited(const RenderOptions& o, const FrameStats& last, const char* who);

// The input of --input's kinds, with --io-delay-ms applied by the caller (DelayedBrickSource); `who` names
// the command ("render").
std::unique_ptr<BrickSource> openBrickSource(const RenderOptions& o, const std::string& who,
                                             VolumeInfo* volume = nullptr);
// A store file; procedural:NAME:SIZE, bricked by `brick` (default kDefaultBrickSize); or a volume as convert
// reads it with `read`'s options, converted to a temporary store bricked by `brick` (tools/temporary_store.h;
// `quiet` as there; `volume`, where given, receives what the source read, and is left as it is for a store
// or a procedural input). A store keeps its own brick size and everything it was read with, so `brick` or a
// `read` option with a store is a UsageError, and a `read` option with a procedural input too.
std::unique_ptr<BrickSource> openBrickSource(const std::string& input, std::optional<uint32_t> brick,
                                             const VolumeReadArgs& read, bool quiet, const std::string& who,
                                             VolumeInfo* volume = nullptr);

// --material's KA,KD,KS,SHININESS (materialProblem has checked them) into `lighting`.
void setMaterial(LightingParams& lighting, const std::vector<double>& material);

// --orbit, else the default orbit of `volume` (kPatientDefaultOrbit for a patient's, else kDefaultOrbit).
// Throws UsageError for a distance that is not positive.
glm::dvec3 orbitFor(const RenderOptions& o, const VolumeInfo& volume);

// The camera of --eye/--target/--up/--fov, else of --view, else of orbitFor around the volume box.
// Throws UsageError as checkSceneOptions.
Camera chooseCamera(const RenderOptions& o, const BrickSourceInfo& info);

// The volume's value range in data units: the source's known range, else what its stored type holds.
std::pair<double, double> valueRangeOf(const BrickSourceInfo& info);

// The crop box of --crop's three ranges (RenderOptions::crop) of the volume's file indices (empty ranges: the
// whole volume), in the source's (x the other way where it keeps x reversed: BrickSourceInfo::xReversed).
// Throws UsageError, naming the axis and the volume's extent, when a range does not lie in it.
CropBox cropBoxOf(const std::vector<std::string>& ranges, const BrickSourceInfo& info);

// A crop box in the source's indices as the file counts them, and back (the same map both ways).
CropBox fileCropOf(const CropBox& crop, const BrickSourceInfo& info);

// The clip plane of --clip-plane's six numbers (RenderOptions::clipPlane; empty: none), its normal made unit.
// Throws UsageError when the normal has no direction.
ClipPlane clipPlaneOf(const std::vector<double>& values);

// RenderParams of the options (isovalue default: the middle of the value range; --mode slice's plane
// core/orientation.h defaultSlicePlane). Warns on stderr, as `command`, when an isovalue lies outside the
// value range.
RenderParams renderParamsOf(const RenderOptions& o, const BrickSourceInfo& info, const char* command);

// The transfer function of --tf (a preset or a JSON file; empty: the linear preset), placed for the data.
// --tf's help: the presets, and what it defaults to.
std::string tfOptionHelp(const std::string& defaultText);
// The preset an absent --tf means in `mode` (gray for an intensity projection, else linear).
std::string defaultTfSpec(RenderMode mode);
// --tf-range's two numbers (empty: not given): a UsageError unless LO < HI.
void checkTfRange(const std::vector<double>& tfRange);
// `function` stretched over --tf-range's LO,HI where given (empty: as it is).
TransferFunction windowed(const TransferFunction& function, const std::vector<double>& tfRange);
// `--tf spec` placed for the data; an empty spec is the mode's default; windowed by --tf-range.
TransferFunction transferFunctionOf(const std::string& spec, const BrickSourceInfo& info, RenderMode mode,
                                    const std::vector<double>& tfRange);
TfTable bakeFor(const TransferFunction& function, const BrickSourceInfo& info);

// The FrameRenderer's configuration of the options, for a renderer drawing `params`.
FrameRendererConfig frameRendererConfigOf(const RenderOptions& o, const RenderParams& params);

}  // namespace ropecast::tools
