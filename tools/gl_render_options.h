// The options `ropecast render` and `ropecast view` share, and what both make of them before anything draws:
// the brick source, the render parameters, the transfer function table, the camera, the FrameRenderer's
// configuration. One place, so that a view and a render given the same options draw the same image.
// Main thread.
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

namespace ropecast::tools {

struct RenderOptions {
  std::string input;
  RenderMode mode = RenderMode::Iso;
  std::optional<double> iso;
  std::string tf;
  std::vector<uint32_t> size{512, 512};
  std::vector<double> orbit, eye, target, up;  // up: empty for defaultUp
  double fov = 40.0;
  std::vector<double> background{0.0, 0.0, 0.0};
  RenderBackend backend = RenderBackend::Auto;
  GradientSource gradients = GradientSource::Stored;
  double step = 0.5;
  double ert = 0.99;
  double voxelsPerPixel = 1.0;
  uint64_t gpuBudget = 0;  // 0: from the driver
  uint64_t cpuCache = uint64_t(1) << 30;
  uint64_t uploadBudget = UINT64_MAX;
  double uploadTimeBudgetMs = 0.0;
  double targetFrameMs = 0.0;
  bool uploadPbo = false;
  double ioDelayMs = 0.0;
  uint32_t brick = kDefaultBrickSize;  // procedural inputs only
  bool occlusion = true;
  bool feedback = true;
  uint32_t queryBudget = VisibilityConfig{}.tiles.queryBudget;
  uint64_t visibilityThreshold = VisibilityConfig{}.thresholdPixels;
};

// The default orbit (docs/ARCHITECTURE.md): azimuth, elevation (degrees), distance (bounding-sphere radii).
inline constexpr double kDefaultOrbit[3] = {30.0, 20.0, 3.0};

extern const std::vector<std::pair<std::string, RenderMode>> kModeNames;
extern const std::vector<std::pair<std::string, bool>> kOnOffNames;
extern const std::vector<std::pair<std::string, GradientSource>> kGradientNames;
std::vector<std::pair<std::string, RenderBackend>> backendNames();

// Registers the options that describe the scene and how it is drawn (input, mode, camera, size, budgets,
// backend, ...).
void addSceneOptions(CLI::App& app, RenderOptions& o);

// The store file or procedural:NAME:SIZE, with --io-delay-ms applied by the caller (DelayedBrickSource).
std::unique_ptr<BrickSource> openBrickSource(const RenderOptions& o);

// The camera of --eye/--target/--up/--fov, else of --orbit (default kDefaultOrbit) around the volume box.
Camera chooseCamera(const RenderOptions& o, const BrickSourceInfo& info);

// The volume's value range in data units: the source's known range, else what its stored type holds.
std::pair<double, double> valueRangeOf(const BrickSourceInfo& info);

// RenderParams of the options (isovalue default: the middle of the value range). Warns on stderr, as
// `command`, when an isovalue lies outside the value range.
RenderParams renderParamsOf(const RenderOptions& o, const BrickSourceInfo& info, const char* command);

// The transfer function of --tf (a preset or a JSON file; empty: the linear preset), placed for the data.
TransferFunction transferFunctionOf(const std::string& spec, const BrickSourceInfo& info);
TfTable bakeFor(const TransferFunction& function, const BrickSourceInfo& info);

// The FrameRenderer's configuration of the options, for a renderer drawing `params`.
FrameRendererConfig frameRendererConfigOf(const RenderOptions& o, const RenderParams& params);

}  // namespace ropecast::tools
