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
  std::string mode = "iso";
  std::optional<double> iso;
  std::string tf;
  std::string size = "512x512";
  std::string orbit, eye, target, up;  // up: empty for defaultUp
  double fov = 40.0;
  std::string background = "0,0,0";
  std::string backend = "fragment";
  std::string gradients = "stored";
  std::string output, exr, depth, stats;
  bool reference = false;
  double step = 0.5;
  double ert = 0.99;
  double voxelsPerPixel = 1.0;
  std::string gpuBudget, cpuCache = "1G", uploadBudget;
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
    c.eye = parseTriple(o.eye, "--eye");
    c.target = parseTriple(o.target, "--target");
    c.fovYDeg = o.fov;
    c.up = o.up.empty() ? defaultUp(c.target - c.eye) : parseTriple(o.up, "--up");
    if (const std::string problem = cameraProblem(c); !problem.empty())
      throw Error("--eye " + o.eye + " --target " + o.target + (o.up.empty() ? "" : " --up " + o.up) + ": " +
                  problem);
    return c;
  }
  const glm::dvec3 orbit = o.orbit.empty() ? glm::dvec3(30.0, 20.0, 3.0) : parseTriple(o.orbit, "--orbit");
  if (orbit.z <= 0.0) throw Error("--orbit: the distance must be positive, got " + o.orbit);
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

int runRender(const RenderOptions& o) {
  if (o.output.empty()) throw Error("render: -o OUT.png is required");
  checkImageOutputs(o);
  removeTemporaryFilesOnSignals();  // an interrupted render leaves no temporary behind
  std::unique_ptr<BrickSource> source = openBrickSource(o);
  std::unique_ptr<BrickSource> delayed;
  if (o.ioDelayMs > 0.0) delayed = std::make_unique<DelayedBrickSource>(*source, o.ioDelayMs);
  const BrickSource& bricks = delayed ? *delayed : *source;
  const BrickSourceInfo& info = bricks.info();

  const glm::u32vec2 size = parseImageSize(o.size, "--size");
  RenderParams params;
  params.mode = o.mode == "dvr" ? RenderMode::Dvr : RenderMode::Iso;
  const uint32_t storedMax = info.storedType == SampleType::UInt8 ? 255 : 65535;
  const double lo = info.volume.valueMin.value_or(info.mapping.toData(0));
  const double hi = info.volume.valueMax.value_or(info.mapping.toData(storedMax));
  params.isoValue = o.iso.value_or(0.5 * (lo + hi));
  params.stepVoxels = o.step;
  params.ert = o.ert;
  params.background = parseTriple(o.background, "--background");
  params.backend = o.backend == "compute" ? RenderBackend::Compute : RenderBackend::Fragment;
  params.gradients = o.gradients == "computed" ? GradientSource::Computed : GradientSource::Stored;

  if (params.mode == RenderMode::Iso && !(params.isoValue >= lo && params.isoValue <= hi))
    std::fprintf(stderr,
                 "ropecast render: warning: --iso %g lies outside the volume's value range [%g, %g]: the "
                 "isosurface is empty\n",
                 params.isoValue, lo, hi);

  // A --tf that names no preset and no readable file is an error in either mode (a script that switches modes
  // should not learn of a typo only when it reaches DVR); the table is baked for DVR only.
  std::optional<TfTable> tf;
  if (params.mode == RenderMode::Dvr || !o.tf.empty()) {
    const TransferFunction function = TransferFunction::fromSpec(o.tf, tfDataRangeFor(info));
    if (params.mode == RenderMode::Dvr) tf = TfTable::bake(function, info.mapping, storedMax);
  }

  std::optional<CameraPath> path;
  if (!o.path.empty()) path = loadCameraPath(o.path);
  const glm::dvec3 boxMax = glm::dvec3(info.volume.dims) * info.volume.spacing;
  const uint32_t frames = std::max<uint32_t>(1, o.frames);
  auto cameraOf = [&](uint32_t frame) {
    return path ? sampleCameraPath(*path, frame, frames, glm::dvec3(0.0), boxMax) : chooseCamera(o, info);
  };
  // Every keyframe has a view, but eye and target can meet between two; found before any frame is written.
  for (uint32_t frame = 0; path && frame < frames; ++frame) {
    const Camera c = cameraOf(frame);
    if (const std::string problem = viewProblem(c.eye, c.target); !problem.empty())
      throw Error("camera path " + o.path + ", frame " + std::to_string(frame) + " of " +
                  std::to_string(frames) + ": " + problem);
  }

  StatsWriter stats(o.stats);
  if (o.reference) {
    ReferenceRenderer reference(bricks);
    CpuRenderInput input;
    input.camera = cameraOf(frames - 1);
    input.width = size.x;
    input.height = size.y;
    input.params = params;
    input.tf = tf ? &*tf : nullptr;
    const CpuImage image = reference.render(input);
    writeOutputs(o, toFloatImage(image.rgba, image.width, image.height, 4),
                 toFloatImage(image.depth, image.width, image.height, 1));
    stats.finish();
    return 0;
  }

  if (o.backend == "brute") {
    // The baseline of bench/render_vs_brute.sh: level 0 in one 3D texture, no index
    // (render/brute_force_pass).
    GlContext gl;
    BruteForcePass brute(bricks);
    BruteForceFrame bf;
    bf.params = params;
    bf.tf = tf ? &*tf : nullptr;
    bf.width = size.x;
    bf.height = size.y;
    for (uint32_t frame = 0; frame < frames; ++frame) {
      const auto start = std::chrono::steady_clock::now();
      bf.camera = cameraOf(frame);
      brute.render(bf);
      FrameStats s;
      s.frame = frame;
      s.raycastMs = brute.lastRaycastMs();
      s.stepVoxels = bf.params.stepVoxels;
      s.raycastWallClock = brute.raycastTimerUsedWallClock();
      s.frameMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      s.converged = true;
      stats.write(s);
    }
    writeOutputs(o, brute.readColor(), brute.readDepth());
    stats.finish();
    return 0;
  }

  GlContext gl;
  FrameRendererConfig config;
  if (!o.gpuBudget.empty()) config.gpuBudgetBytes = parseBytes(o.gpuBudget, "--gpu-budget");
  config.cpuCacheBytes = parseBytes(o.cpuCache, "--cpu-cache");
  if (!o.uploadBudget.empty()) config.uploadBudgetBytes = parseBytes(o.uploadBudget, "--upload-budget");
  config.uploadTimeBudgetMs = o.uploadTimeBudgetMs;
  config.storedGradients = usesStoredGradients(params);
  config.uploadThroughPbo = o.uploadPbo;
  FrameRenderer renderer(gl.info(), bricks, config);

  FrameRequest request;
  request.width = size.x;
  request.height = size.y;
  request.params = params;
  request.voxelsPerPixel = o.voxelsPerPixel;
  request.tf = tf ? &*tf : nullptr;
  // A single frame without --converge is issue 3's synchronous render: load what the view needs, then draw.
  const bool progressive = o.converge || frames > 1 || path;
  request.synchronous = !progressive;

  const uint32_t frameCap = o.converge ? std::max(frames, o.maxFrames) : frames;
  request.camera = cameraOf(0);
  renderer.prepare(request);  // shader compilation before frame 0, not in its frame_ms
  StepPacer stepPacer(o.targetFrameMs);
  uint32_t frame = 0;
  for (;; ++frame) {
    request.camera = cameraOf(std::min(frame, frames - 1));
    request.params.stepVoxels = params.stepVoxels * stepPacer.scale();
    const FrameStats s = renderer.render(request);
    stepPacer.record(s.frameMs, s.raycastMs);
    stats.write(s);
    const bool last =
        o.converge ? (frame + 1 >= frames && s.converged) || frame + 1 >= frameCap : frame + 1 >= frames;
    // --every writes the frame's PNG only: the EXR and depth outputs are the last frame's, written once.
    if (o.every > 0 && (frame % o.every == 0) && !last)
      writePng(framePath(o.output, frame), renderer.readColor(), false);
    if (last) {
      if (o.converge && !s.converged)
        std::fprintf(stderr, "ropecast render: not converged after %u frames (--max-frames)\n", frame + 1);
      break;
    }
  }
  writeOutputs(o, renderer.readColor(), renderer.readDepth());
  stats.finish();
  return 0;
}

const CommandRegistration registration("render", 50, [](CLI::App& app) -> std::function<int()> {
  auto o = std::make_shared<RenderOptions>();
  app.description("Render a store or procedural:NAME:SIZE headless to PNG (and EXR, depth, per-frame stats)");
  app.add_option("input", o->input, "store file (.rcast) or procedural:NAME:SIZE")->required();
  app.add_option("-o,--output", o->output, "output PNG")->required();
  app.add_option("--mode", o->mode, "iso or dvr")
      ->check(CLI::IsMember({"iso", "dvr"}))
      ->capture_default_str();
  app.add_option("--iso", o->iso, "isovalue in data units (default: middle of the value range)")
      ->check(finiteIn(-HUGE_VAL, HUGE_VAL));
  app.add_option("--tf", o->tf, "transfer function: a preset (ct-bone, ct-soft, mri, linear) or a JSON file");
  app.add_option("--size", o->size, "image size WxH")->capture_default_str();
  app.add_option("--orbit", o->orbit,
                 "AZ,EL,DIST: degrees, degrees, bounding-sphere radii (default 30,20,3)");
  app.add_option("--eye", o->eye, "camera position X,Y,Z (world units)");
  app.add_option("--target", o->target, "point looked at X,Y,Z");
  app.add_option("--up", o->up, "up vector X,Y,Z (default 0,0,1; 0,1,0 when looking along z)");
  app.add_option("--fov", o->fov, "vertical field of view, degrees")
      ->check(finiteIn(1.0, 179.0))
      ->capture_default_str();
  app.add_option("--background", o->background, "background R,G,B in [0,1]")->capture_default_str();
  app.add_option("--backend", o->backend,
                 "fragment or compute; brute: level 0 in one 3D texture, no index (a benchmark baseline)")
      ->check(CLI::IsMember({"fragment", "compute", "brute"}))
      ->capture_default_str();
  app.add_option(
         "--gradients", o->gradients,
         "DVR gradients: stored (derived at upload, one lookup per sample, 8 more bytes per pool texel) "
         "or computed (six more lookups per sample)")
      ->check(CLI::IsMember({"stored", "computed"}))
      ->capture_default_str();
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
  app.add_option("--gpu-budget", o->gpuBudget, "GPU brick pool bytes (e.g. 512M; default from the driver)");
  app.add_option("--cpu-cache", o->cpuCache, "CPU brick cache bytes")->capture_default_str();
  app.add_option("--upload-budget", o->uploadBudget, "brick upload bytes per frame (default: unlimited)");
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
  app.add_option("--brick", o->brick, "brick size for procedural inputs")
      ->check(CLI::IsMember({8u, 16u, 32u, 64u}));
  return [o] { return runRender(*o); };
});

}  // namespace
}  // namespace ropecast::tools
