// The options of `ropecast render` and the one function that renders them, shared by the render command
// (tools/gl_cmd_render.cpp) and `ropecast regress` (tools/gl_cmd_regress.cpp), so a regression case renders
// exactly what `ropecast render` would with the same options. Main thread (it owns the GL context it makes).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "core/camera.h"
#include "core/float_image.h"
#include "core/orientation.h"
#include "core/render_params.h"
#include "occlusion/visibility_tracker.h"
#include "reference/image_io.h"
#include "store/octree_layout.h"
#include "tools/volume_read_options.h"

namespace ropecast::tools {

// What `ropecast render` is told on its command line (addRenderOptions and the input and -o).
struct RenderOptions {
  std::string input;
  RenderMode mode = RenderMode::Iso;
  std::optional<double> iso;
  std::string tf;
  std::vector<double> tfRange;  // --tf-range: LO,HI in data units; empty: the transfer function as placed
  std::vector<uint32_t> size{512, 512};
  std::vector<double> orbit, eye, target, up;  // up: empty for defaultUp
  std::optional<AnatomicalView> view;          // --view: a named side of the patient, instead of an orbit
  double fov = 40.0;
  std::vector<double> background{0.0, 0.0, 0.0};
  std::vector<std::string> crop;  // --crop: three voxel ranges "A:B" (cli_values.h); empty: the whole volume
  std::vector<double> clipPlane;  // --clip-plane: X,Y,Z,NX,NY,NZ; empty: none
  std::string slice;              // --slice AXIS:INDEX (a slice's plane through voxel centers); "": none
  double slab = 0.0;              // --slab T: the slab of thickness T about the plane (world units); 0: none
  bool caps = true;               // --caps: isosurface caps at the cuts (RenderParams::isoCaps)
  std::vector<double> isoColor;   // --iso-color R,G,B; empty: LightingParams' default
  std::vector<double> material;   // --material KA,KD,KS,SHININESS; empty: LightingParams' defaults
  bool shading = true;            // --shading (DVR): LightingParams::dvrShading
  RenderBackend backend = RenderBackend::Auto;
  // --brute-stage: the entry point of --backend brute, Auto, Fragment or Compute; unset: not given (Auto).
  std::optional<RenderBackend> bruteStage;
  GradientSource gradients = GradientSource::Stored;
  std::string output, exr, depth, stats;
  bool reference = false;
  double step = 0.5;
  double ert = 0.99;
  double voxelsPerPixel = 1.0;
  uint64_t gpuBudget = 0;  // 0: from the driver
  uint64_t cpuCache = uint64_t(1) << 30;
  uint64_t uploadBudget = UINT64_MAX;
  double uploadTimeBudgetMs = 0.0;
  double targetFrameMs = 0.0;
  bool uploadPbo = false;
  uint32_t frames = 1;
  std::string path;
  bool converge = false;
  uint32_t maxFrames = 1000;
  uint32_t every = 0;
  double ioDelayMs = 0.0;
  uint32_t ioThreads = 0;         // 0: FrameRendererConfig's default
  std::optional<uint32_t> brick;  // procedural inputs only (default kDefaultBrickSize)
  VolumeReadArgs read;            // --dims, --type, ..., --spacing: for a volume read from its file
  std::string times;              // render's --times A:B: a time-lapse of time points A to B - 1; "": none
  bool occlusion = true;
  bool feedback = true;
  uint32_t queryBudget = VisibilityConfig{}.tiles.queryBudget;
  uint64_t visibilityThreshold = VisibilityConfig{}.thresholdPixels;
  bool quiet = false;  // no progress line (there is one only when stderr is a terminal)
  bool marks = false;  // --marks: orientation marks drawn into the PNG images (-o, --every's), not the EXRs
  // Not an option: what starts each warning line (regress renders its cases in one process and names the
  // case there, as it does for the lines of a child process).
  std::string messagePrefix;
};

// Adds every option of `ropecast render` but the input and -o to `app`, bound to `o`.
void addRenderOptions(CLI::App& app, RenderOptions& o);

// The last frame of a render: RGBA color (alpha = coverage) and depth (world units, +inf = miss).
struct RenderedFrame {
  FloatImage color, depth;
  Camera camera;             // in the world (the last frame's)
  AxisDirections axes{1.0};  // where the volume's axes point in the world
};

// The color image of a frame as -o writes it: with --marks, the orientation marks drawn into it
// (tools/image_marks.h).
FloatImage colorOutputOf(const RenderOptions& o, const RenderedFrame& frame);

// Renders as `ropecast render` does with these options (one synchronous frame, progressive frames until
// --converge, --reference, --backend brute) and returns the last frame. --stats and --every's frames are
// written under temporary names as it goes; `stageImages`, called with the last frame, writes the caller's
// images under theirs (null: none); only when all are written are they moved onto their names, so that a
// render that fails leaves none of them. Throws ropecast::Error naming the option or file at fault.
using StageImages = std::function<std::vector<StagedImage>(const RenderedFrame&)>;
RenderedFrame renderFrames(const RenderOptions& o, const StageImages& stageImages = {});

}  // namespace ropecast::tools
