// `ropecast render`: renders a store or a procedural volume headless, one image or a progressive sequence.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>

#include "core/camera_path.h"
#include "core/error.h"
#include "core/temporary_file.h"
#include "core/transfer_function.h"
#include "loader/io_queue.h"
#include "reference/cpu_raycaster.h"
#include "reference/image_io.h"
#include "render/brute_force_pass.h"
#include "render/frame_renderer.h"
#include "render/gl_context.h"
#include "render/step_pacer.h"
#include "store/procedural_bricks.h"
#include "store/store.h"
#include "tools/cli_checks.h"
#include "tools/cli_values.h"
#include "tools/command.h"

namespace ropecast::tools {
namespace {

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
  uint32_t brick = kDefaultBrickSize;  // procedural inputs only
  bool occlusion = true;
  bool feedback = true;
  uint32_t queryBudget = VisibilityConfig{}.tiles.queryBudget;
  uint64_t visibilityThreshold = VisibilityConfig{}.thresholdPixels;
};

std::unique_ptr<BrickSource> openBrickSource(const RenderOptions& o) {
  if (o.input.rfind("procedural:", 0) == 0) return openProceduralBricks(o.input, o.brick);
  if (!std::filesystem::exists(o.input)) throw Error(o.input + ": no such store file");
  return Store::open(o.input);
}

Camera chooseCamera(const RenderOptions& o, const BrickSourceInfo& info) {
  const glm::dvec3 boxMax = glm::dvec3(info.volume.dims) * info.volume.spacing;
  if (!o.eye.empty() || !o.target.empty()) {
    if (o.eye.empty() || o.target.empty()) throw Error("--eye and --target go together");
    Camera c;
    c.eye = toVec3(o.eye);
    c.target = toVec3(o.target);
    c.fovYDeg = o.fov;
    c.up = o.up.empty() ? defaultUp(c.target - c.eye) : toVec3(o.up);
    if (const std::string problem = cameraProblem(c); !problem.empty())
      throw Error("--eye " + formatTriple(o.eye) + " --target " + formatTriple(o.target) +
                  (o.up.empty() ? "" : " --up " + formatTriple(o.up)) + ": " + problem);
    return c;
  }
  const glm::dvec3 orbit = o.orbit.empty() ? glm::dvec3(30.0, 20.0, 3.0) : toVec3(o.orbit);
  if (orbit.z <= 0.0) throw Error("--orbit: the distance must be positive, got " + formatTriple(o.orbit));
  return orbitCamera(orbit.x, orbit.y, orbit.z, glm::dvec3(0.0), boxMax, o.fov);
}

FloatImage toFloatImage(const std::vector<float>& values, uint32_t w, uint32_t h, uint32_t channels) {
  FloatImage image;
  image.width = w;
  image.height = h;
  image.channels = channels;
  image.pixels = values;
  return image;
}

void writeOutputs(const RenderOptions& o, const FloatImage& color, const FloatImage& depth) {
  writePng(o.output, color, false);
  if (!o.exr.empty()) writeExr(o.exr, color);
  if (!o.depth.empty()) writeDepthExr(o.depth, depth);
}

// "out.png", frame 7 -> "out_0007.png".
std::string framePath(const std::string& path, uint64_t frame) {
  std::filesystem::path p(path);
  char suffix[32];
  std::snprintf(suffix, sizeof suffix, "_%04llu", static_cast<unsigned long long>(frame));
  return (p.parent_path() / (p.stem().string() + suffix + p.extension().string())).string();
}

// Writes the stats lines to a temporary file renamed at the end, so a failed or interrupted run leaves no
// partial file (TemporaryFile: removed on destruction and, with removeTemporaryFilesOnSignals, on a signal).
class StatsWriter {
 public:
  explicit StatsWriter(const std::string& path) {
    if (!path.empty()) file_.emplace(path, "--stats");
  }
  void write(const FrameStats& s) {
    if (!file_) return;
    const std::string line = toJsonLine(s) + '\n';
    file_->writeAt(offset_, std::as_bytes(std::span(line)));
    offset_ += line.size();
  }
  void finish() {
    if (file_) file_->commit();
  }

 private:
  std::optional<TemporaryFile> file_;
  uint64_t offset_ = 0;
};

// The image outputs are checked before anything is loaded or rendered.
void checkImageOutputs(const RenderOptions& o) {
  const auto check = [](const char* option, const std::string& path, ImageOutputKind kind) {
    if (path.empty()) return;
    if (const std::string problem = imageOutputProblem(path, kind); !problem.empty())
      throw Error(std::string(option) + " " + path + ": " + problem);
  };
  check("-o", o.output, ImageOutputKind::Color8);
  check("--exr", o.exr, ImageOutputKind::FloatExr);
  check("--depth", o.depth, ImageOutputKind::FloatExr);
}

// What every path shares, read and checked before anything renders: the bricks, the image size, the render
// parameters, the transfer function, the camera of each frame, the --stats file.
class RenderSetup {
  const RenderOptions& o_;
  std::unique_ptr<BrickSource> source_;
  std::unique_ptr<BrickSource> delayed_;  // --io-delay-ms
  std::optional<TfTable> tf_;
  std::optional<CameraPath> path_;

 public:
  explicit RenderSetup(const RenderOptions& o) : o_(o), source_(openBrickSource(o)) {
    if (o.ioDelayMs > 0.0) delayed_ = std::make_unique<DelayedBrickSource>(*source_, o.ioDelayMs);
    const BrickSourceInfo& info = bricks().info();
    width = o.size.at(0);
    height = o.size.at(1);
    params.mode = o.mode;
    const uint32_t storedMax = storedMaxOf(info.storedType);
    const double lo = info.volume.valueMin.value_or(info.mapping.toData(0));
    const double hi = info.volume.valueMax.value_or(info.mapping.toData(storedMax));
    params.isoValue = o.iso.value_or(0.5 * (lo + hi));
    params.stepVoxels = o.step;
    params.ert = o.ert;
    params.background = toVec3(o.background);
    params.backend = o.backend;
    params.gradients = o.gradients;
    if (params.mode == RenderMode::Iso && !(params.isoValue >= lo && params.isoValue <= hi))
      std::fprintf(stderr,
                   "ropecast render: warning: --iso %g lies outside the volume's value range [%g, %g]: the "
                   "isosurface is empty\n",
                   params.isoValue, lo, hi);

    // A --tf that names no preset and no readable file is an error in either mode (a script that switches
    // modes should not learn of a typo only when it reaches DVR); the table is baked for DVR only.
    if (params.mode == RenderMode::Dvr || !o.tf.empty()) {
      const TransferFunction function = TransferFunction::fromSpec(o.tf, tfDataRangeFor(info));
      if (params.mode == RenderMode::Dvr) tf_ = TfTable::bake(function, info.mapping, storedMax);
    }

    if (!o.path.empty()) path_ = loadCameraPath(o.path);
    frames = std::max<uint32_t>(1, o.frames);
    // Every keyframe has a view, but eye and target can meet between two; found before any frame is written.
    for (uint32_t frame = 0; path_ && frame < frames; ++frame) {
      const Camera c = cameraOf(frame);
      if (const std::string problem = viewProblem(c.eye, c.target); !problem.empty())
        throw Error("camera path " + o.path + ", frame " + std::to_string(frame) + " of " +
                    std::to_string(frames) + ": " + problem);
    }
    stats.emplace(o.stats);
  }

  const BrickSource& bricks() const { return delayed_ ? *delayed_ : *source_; }
  const TfTable* tf() const { return tf_ ? &*tf_ : nullptr; }
  Camera cameraOf(uint32_t frame) const {
    const BrickSourceInfo& info = bricks().info();
    const glm::dvec3 boxMax = glm::dvec3(info.volume.dims) * info.volume.spacing;
    return path_ ? sampleCameraPath(*path_, frame, frames, glm::dvec3(0.0), boxMax) : chooseCamera(o_, info);
  }

  uint32_t width = 0, height = 0;
  RenderParams params;
  uint32_t frames = 1;
  std::optional<StatsWriter> stats;  // set once everything above is checked
};

// --reference: the CPU ray marcher over the full-resolution data, the last frame's camera.
void renderReference(const RenderOptions& o, const RenderSetup& s) {
  ReferenceRenderer reference(s.bricks());
  CpuRenderInput input;
  input.camera = s.cameraOf(s.frames - 1);
  input.width = s.width;
  input.height = s.height;
  input.params = s.params;
  input.tf = s.tf();
  const CpuImage image = reference.render(input);
  writeOutputs(o, toFloatImage(image.rgba, image.width, image.height, 4),
               toFloatImage(image.depth, image.width, image.height, 1));
}

// --backend brute: the baseline of bench/render_vs_brute.sh, level 0 in one 3D texture and no index
// (render/brute_force_pass).
void renderBrute(const RenderOptions& o, RenderSetup& s) {
  GlContext gl;
  BruteForcePass brute(s.bricks());
  BruteForceFrame bf;
  bf.params = s.params;
  bf.tf = s.tf();
  bf.width = s.width;
  bf.height = s.height;
  for (uint32_t frame = 0; frame < s.frames; ++frame) {
    const auto start = std::chrono::steady_clock::now();
    bf.camera = s.cameraOf(frame);
    brute.render(bf);
    FrameStats stats;
    stats.frame = frame;
    stats.raycastMs = brute.lastRaycastMs();
    stats.stepVoxels = bf.params.stepVoxels;
    stats.raycastWallClock = brute.raycastTimerUsedWallClock();
    stats.backend = RenderBackend::Brute;
    stats.drawCalls = 1;
    stats.glDrawCalls = 1;
    stats.fragments = uint64_t(bf.width) * bf.height;
    stats.frameMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    stats.converged = true;
    s.stats->write(stats);
  }
  writeOutputs(o, brute.readColor(), brute.readDepth());
}

// The octree ray caster of both remaining paths, its shader compiled (FrameRenderer::prepare) and the request
// of frame 0; the FrameRenderer resolves --backend auto for the context's GL renderer.
struct OctreeRender {
  OctreeRender(const RenderOptions& o, const RenderSetup& s, const GlContext& gl, bool synchronous) {
    FrameRendererConfig config;
    config.gpuBudgetBytes = o.gpuBudget;
    config.cpuCacheBytes = o.cpuCache;
    config.uploadBudgetBytes = o.uploadBudget;
    config.uploadTimeBudgetMs = o.uploadTimeBudgetMs;
    config.storedGradients = usesStoredGradients(s.params);
    config.uploadThroughPbo = o.uploadPbo;
    config.occlusion = o.occlusion;
    config.feedback = o.feedback;
    config.visibility.tiles.queryBudget = o.queryBudget;
    config.visibility.thresholdPixels = o.visibilityThreshold;
    renderer = std::make_unique<FrameRenderer>(gl.info(), s.bricks(), config);
    request.width = s.width;
    request.height = s.height;
    request.params = s.params;
    request.voxelsPerPixel = o.voxelsPerPixel;
    request.tf = s.tf();
    request.synchronous = synchronous;
    request.camera = s.cameraOf(0);
    renderer->prepare(request);  // shader compilation before frame 0, not in its frame_ms
  }
  std::unique_ptr<FrameRenderer> renderer;
  FrameRequest request;
};

// One frame without --frames, --converge or --path: load everything the view needs, then draw.
void renderSingleFrame(const RenderOptions& o, RenderSetup& s) {
  GlContext gl;
  OctreeRender octree(o, s, gl, /*synchronous=*/true);
  s.stats->write(octree.renderer->render(octree.request));
  writeOutputs(o, octree.renderer->readColor(), octree.renderer->readDepth());
}

// --frames, --converge, --path: the asynchronous loader streams bricks while frames render, and no frame
// waits for the disk.
void renderProgressive(const RenderOptions& o, RenderSetup& s) {
  GlContext gl;
  OctreeRender octree(o, s, gl, /*synchronous=*/false);
  FrameRequest& request = octree.request;
  const uint32_t frameCap = o.converge ? std::max(s.frames, o.maxFrames) : s.frames;
  StepPacer stepPacer(o.targetFrameMs);
  for (uint32_t frame = 0;; ++frame) {
    request.camera = s.cameraOf(std::min(frame, s.frames - 1));
    request.params.stepVoxels = s.params.stepVoxels * stepPacer.scale();
    const FrameStats stats = octree.renderer->render(request);
    stepPacer.record(stats.frameMs, stats.raycastMs);
    s.stats->write(stats);
    const bool last = o.converge ? (frame + 1 >= s.frames && stats.converged) || frame + 1 >= frameCap
                                 : frame + 1 >= s.frames;
    // --every writes the frame's PNG only: the EXR and depth outputs are the last frame's, written once.
    if (o.every > 0 && (frame % o.every == 0) && !last)
      writePng(framePath(o.output, frame), octree.renderer->readColor(), false);
    if (last) {
      if (o.converge && !stats.converged)
        std::fprintf(stderr, "ropecast render: not converged after %u frames (--max-frames)\n", frame + 1);
      break;
    }
  }
  writeOutputs(o, octree.renderer->readColor(), octree.renderer->readDepth());
}

const std::vector<std::pair<std::string, RenderMode>> kModeNames{{"iso", RenderMode::Iso},
                                                                 {"dvr", RenderMode::Dvr}};
const std::vector<std::pair<std::string, bool>> kOnOffNames{{"on", true}, {"off", false}};
const std::vector<std::pair<std::string, GradientSource>> kGradientNames{
    {"stored", GradientSource::Stored}, {"computed", GradientSource::Computed}};
std::vector<std::pair<std::string, RenderBackend>> backendNames() {
  std::vector<std::pair<std::string, RenderBackend>> names;
  for (const auto& [name, backend] : kRenderBackendNames) names.emplace_back(name, backend);
  return names;
}

int runRender(const RenderOptions& o) {
  if (o.output.empty()) throw Error("render: -o OUT.png is required");
  checkImageOutputs(o);
  removeTemporaryFilesOnSignals();  // an interrupted render leaves no temporary behind
  RenderSetup setup(o);
  if (o.reference)
    renderReference(o, setup);
  else if (o.backend == RenderBackend::Brute)
    renderBrute(o, setup);
  else if (o.converge || o.frames > 1 || !o.path.empty())
    renderProgressive(o, setup);
  else
    renderSingleFrame(o, setup);
  setup.stats->finish();
  return 0;
}

const CommandRegistration registration("render", 50, [](CLI::App& app) -> std::function<int()> {
  auto o = std::make_shared<RenderOptions>();
  app.description("render a store or procedural:NAME:SIZE headless to PNG (and EXR, depth, per-frame stats)");
  app.add_option("input", o->input, "store file (.rcast) or procedural:NAME:SIZE")->required();
  app.add_option("-o,--output", o->output, "output PNG")->required();
  addEnumOption(app, "--mode", o->mode, kModeNames, "isosurface or direct volume rendering");
  app.add_option("--iso", o->iso, "isovalue in data units (default: middle of the value range)")
      ->check(finiteIn(-HUGE_VAL, HUGE_VAL));
  app.add_option("--tf", o->tf, "transfer function: a preset (ct-bone, ct-soft, mri, linear) or a JSON file");
  addImageSizeOption(app, "--size", o->size, "image size WxH, each in [1, 16384] (default 512x512)");
  addTripleOption(app, "--orbit", o->orbit,
                  "AZ,EL,DIST: degrees, degrees, bounding-sphere radii (default 30,20,3)");
  addTripleOption(app, "--eye", o->eye, "camera position X,Y,Z (world units)");
  addTripleOption(app, "--target", o->target, "point looked at X,Y,Z");
  addTripleOption(app, "--up", o->up, "up vector X,Y,Z (default 0,0,1; 0,1,0 when looking along z)");
  app.add_option("--fov", o->fov, "vertical field of view, degrees")
      ->check(finiteIn(1.0, 179.0))
      ->capture_default_str();
  addTripleOption(app, "--background", o->background, "background R,G,B in [0,1] (default 0,0,0)");
  addEnumOption(
      app, "--backend", o->backend, backendNames(),
      "auto: compute on hardware GPUs, fragment on software rasterizers (llvmpipe); fragment or "
      "compute: the octree ray caster's entry point; brute: level 0 in one 3D texture, no index (a "
      "benchmark baseline); multipass: the same cut drawn one data brick per pass, composited front "
      "to back (no occlusion queries, no feedback). --stats names the one used");
  addEnumOption(
      app, "--gradients", o->gradients, kGradientNames,
      "DVR gradients: stored (derived at upload, one lookup per sample, 8 more bytes per pool texel) "
      "or computed (six more lookups per sample)");
  app.add_option("--exr", o->exr, "also write float RGBA EXR (alpha = coverage)");
  app.add_option("--depth", o->depth, "also write the depth (world units along the view axis) as EXR");
  app.add_option("--stats", o->stats, "write one JSON object per frame, one per line");
  app.add_flag("--reference", o->reference,
               "brute-force CPU ray marching of the full-resolution data instead");
  app.add_option("--step", o->step, "sample distance in voxels of the level crossed")
      ->check(finiteIn(0.01, 8.0))
      ->capture_default_str();
  app.add_option("--ert", o->ert, "early ray termination opacity (DVR)")
      ->check(finiteIn(0.0, 1.0))
      ->capture_default_str();
  app.add_option("--voxels-per-pixel", o->voxelsPerPixel, "refinement target: voxels per pixel")
      ->check(finiteIn(0.01, 64.0))
      ->capture_default_str();
  addByteSizeOption(app, "--gpu-budget", o->gpuBudget,
                    "GPU brick pool bytes (e.g. 512M; default from the driver)");
  addByteSizeOption(app, "--cpu-cache", o->cpuCache, "CPU brick cache bytes")->default_str("1G");
  addByteSizeOption(app, "--upload-budget", o->uploadBudget,
                    "brick upload bytes per frame (default: unlimited)");
  app.add_option(
         "--upload-time-budget", o->uploadTimeBudgetMs,
         "brick upload milliseconds per progressive frame, from the measured throughput (default: none)")
      ->check(finiteIn(0.0, 100000.0));
  app.add_flag("--upload-pbo", o->uploadPbo, "upload bricks through a pixel buffer object");
  app.add_option("--target-frame-ms", o->targetFrameMs,
                 "progressive frames: sample at up to 4x --step while a frame takes longer than this (the "
                 "written images too; default: off)")
      ->check(finiteIn(0.0, 100000.0));
  app.add_option("--frames", o->frames, "frames to render (progressive loading)")
      ->check(CLI::Range(1u, 1000000u));
  app.add_option("--path", o->path, "camera path: JSON list of cameras or keyframes");
  app.add_flag("--converge", o->converge, "render until the working set is complete and nothing is pending");
  app.add_option("--max-frames", o->maxFrames, "frame cap for --converge")->capture_default_str();
  app.add_option("--every", o->every, "also write every K-th frame as OUT_NNNN.png");
  app.add_option("--io-delay-ms", o->ioDelayMs, "added latency per brick read (shows asynchrony)")
      ->check(finiteIn(0.0, 10000.0));
  addEnumOption(app, "--occlusion", o->occlusion, kOnOffNames,
                "progressive frames: occlusion queries between screen tiles keep hidden nodes from refining");
  addEnumOption(
      app, "--feedback", o->feedback, kOnOffNames,
      "progressive frames: the rays report the bricks they used and where they wanted finer data; "
      "requested nodes refine first, nodes no ray sampled do not refine, used bricks stay in the pool");
  app.add_option("--query-budget", o->queryBudget, "occlusion queries per frame")
      ->check(CLI::Range(1u, 1000000u))
      ->capture_default_str();
  app.add_option("--visibility-threshold", o->visibilityThreshold,
                 "visible pixels below which a queried node counts as occluded")
      ->check(CLI::Range(uint64_t(0), uint64_t(1) << 32))
      ->capture_default_str();
  app.add_option("--brick", o->brick, "brick size for procedural inputs")
      ->check(CLI::IsMember({8u, 16u, 32u, 64u}));
  return [o] { return runRender(*o); };
});

}  // namespace
}  // namespace ropecast::tools
