// `ropecast render`: renders a store or a procedural volume headless, one image or a progressive sequence,
// or each time point of a series (--times).
// renderFrames and the options (tools/render_command.h) are shared with `ropecast regress`.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <initializer_list>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/camera_path.h"
#include "core/elapsed.h"
#include "core/error.h"
#include "core/temporary_file.h"
#include "core/transfer_function.h"
#include "loader/io_queue.h"
#include "reference/cpu_raycaster.h"
#include "reference/image_io.h"
#include "render/backend_choice.h"
#include "render/brute_force_pass.h"
#include "render/frame_renderer.h"
#include "render/gl_context.h"
#include "render/step_pacer.h"
#include "store/procedural.h"
#include "store/store.h"
#include "store/volume_source.h"
#include "tools/cli_checks.h"
#include "tools/cli_values.h"
#include "tools/command.h"
#include "tools/frame_series.h"
#include "tools/gl_render_options.h"
#include "tools/image_marks.h"
#include "tools/output_guard.h"
#include "tools/progress_bar.h"
#include "tools/render_command.h"
#include "tools/stats_writer.h"
#include "tools/volume_read_options.h"

namespace ropecast::tools {
namespace {

FloatImage toFloatImage(const std::vector<float>& values, uint32_t w, uint32_t h, uint32_t channels) {
  FloatImage image;
  image.width = w;
  image.height = h;
  image.channels = channels;
  image.pixels = values;
  return image;
}

// A frame's images; renderFrames sets where it was seen from.
RenderedFrame renderedFrame(FloatImage color, FloatImage depth) {
  RenderedFrame frame;
  frame.color = std::move(color);
  frame.depth = std::move(depth);
  return frame;
}

// -o, --exr and --depth under their temporary names (renderFrames renames them with the other outputs).
std::vector<StagedImage> stageOutputs(const RenderOptions& o, const RenderedFrame& frame) {
  std::vector<StagedImage> staged;
  staged.push_back(stagePng(o.output, colorOutputOf(o, frame), false));
  if (!o.exr.empty()) staged.push_back(stageExr(o.exr, frame.color));
  if (!o.depth.empty()) staged.push_back(stageDepthExr(o.depth, frame.depth));
  return staged;
}

// The image outputs are checked before anything is loaded or rendered: a writer for each, and a folder that
// takes a new file (a temporary made and removed).
void checkImageOutputs(const RenderOptions& o) {
  const auto check = [](const char* option, const std::string& path, ImageOutputKind kind) {
    if (path.empty()) return;
    if (const std::string problem = imageOutputProblem(path, kind); !problem.empty())
      throw Error(std::string(option) + " " + path + ": " + problem);
    TemporaryFile probe(path, std::string("render: ") + option);
  };
  check("-o", o.output, ImageOutputKind::Color8);
  check("--exr", o.exr, ImageOutputKind::FloatExr);
  check("--depth", o.depth, ImageOutputKind::FloatExr);
}

// --times A:B: time points A to B - 1 of the input, from 0.
struct TimeRange {
  uint32_t begin = 0, end = 0;
};

// The time points --times names, checked against the input's (its header read, nothing converted).
TimeRange timeRangeOf(const RenderOptions& o) {
  const std::optional<VoxelRange> range = parseVoxelRange(o.times);
  if (!range)
    throw UsageError("render: --times " + o.times +
                     ": expected A:B, A:, :B or : (time points A to B - 1, from 0, as Python's slices)");
  if (isProceduralSpec(o.input) || isStoreInput(o.input))
    throw UsageError("render: --times: the input " + o.input + " holds one time point (" +
                     (isProceduralSpec(o.input) ? "it is generated" : "a store keeps one volume") + ")");
  const uint64_t held = openVolumeSource(o.input, sourceOptionsOf(o.read, "render"))->info().timePoints;
  if (held <= 1) throw UsageError("render: --times: the input " + o.input + " holds one time point");
  const uint64_t begin = range->begin.value_or(0), end = range->end.value_or(held);
  if (begin >= end || end > held)
    throw UsageError("render: --times " + o.times + ": the input " + o.input + " holds " +
                     std::to_string(held) + " time points (0 to " + std::to_string(held - 1) + ")");
  return {uint32_t(begin), uint32_t(end)};
}

// The options that render time point `t` of --times as `render --time T` would, to numbered outputs
// (OUT_TTTT.png, as --every numbers frames).
RenderOptions timePointOptions(const RenderOptions& o, uint32_t t, bool first) {
  RenderOptions at = o;
  at.times.clear();
  at.read.timePoint = t;
  // The file's note on its channels is said once, by the first time point's conversion; the time-lapse has
  // its own progress line.
  if (!first) at.read.channel = o.read.channel.value_or(0);
  at.quiet = true;
  at.output = framePath(o.output, t);
  if (!o.exr.empty()) at.exr = framePath(o.exr, t);
  if (!o.depth.empty()) at.depth = framePath(o.depth, t);
  at.messagePrefix = o.messagePrefix + "time point " + std::to_string(t) + ": ";
  return at;
}

// No output may be an input (the store, --tf, --path) or another output; checked before anything is written.
// With --times, the outputs are each time point's.
void checkOutputsAreNew(const RenderOptions& o, const std::optional<TimeRange>& times) {
  OutputGuard guard("render");
  guard.addVolumeInput("the input", o.input);
  if (std::filesystem::is_regular_file(o.tf)) guard.addInput("--tf", o.tf);
  guard.addInput("--path", o.path);
  for (uint32_t t = times ? times->begin : 0; t < (times ? times->end : 1); ++t) {
    const RenderOptions at = times ? timePointOptions(o, t, true) : o;
    guard.addOutput("-o", at.output);
    guard.addOutput("--exr", at.exr);
    guard.addOutput("--depth", at.depth);
  }
  guard.addOutput("--stats", o.stats);
  if (o.every > 0) {
    const std::filesystem::path out(o.output);
    const std::string stem = out.stem().string() + "_", ext = out.extension().string();
    guard.addOutputSeries(
        "--every", out.parent_path().string(), stem + "NNNN" + ext, [stem, ext](const std::string& name) {
          if (!name.starts_with(stem) || !name.ends_with(ext)) return false;
          const std::string digits = name.substr(stem.size(), name.size() - stem.size() - ext.size());
          return digits.size() >= 4 && digits.find_first_not_of("0123456789") == std::string::npos;
        });
  }
  guard.check();
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
  // `sharedStats`: a time-lapse's --stats, each line with `statsFields` (its time point); null: the setup
  // writes -o's own --stats.
  explicit RenderSetup(const RenderOptions& o, StatsWriter* sharedStats = nullptr,
                       std::string statsFields = {})
      : o_(o), source_(openBrickSource(o, "render")), statsFields_(std::move(statsFields)) {
    if (o.ioDelayMs > 0.0) delayed_ = std::make_unique<DelayedBrickSource>(*source_, o.ioDelayMs);
    const BrickSourceInfo& info = bricks().info();
    width = o.size.at(0);
    height = o.size.at(1);
    params = renderParamsOf(o, info, "render");
    // A --tf that names no preset and no readable file is an error in either mode (a script that switches
    // modes should not learn of a typo only when it reaches DVR); the table is baked for DVR and MIP only.
    if (usesTransferFunction(params.mode) || !o.tf.empty()) {
      const TransferFunction function = transferFunctionOf(o.tf, info, params.mode, o.tfRange);
      if (usesTransferFunction(params.mode)) tf_ = bakeFor(function, info);
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
    if (!sharedStats) ownStats_.emplace(o.stats, "--stats");
    stats_ = sharedStats ? sharedStats : &*ownStats_;
    series.emplace(o.output, o.every > 0);
  }

  void writeStats(const FrameStats& frame) { stats_->write(frame, statsFields_); }
  // Moves the setup's own --stats into place (a shared one is its owner's to finish).
  void finishStats() {
    if (ownStats_) ownStats_->finish();
  }

  const BrickSource& bricks() const { return delayed_ ? *delayed_ : *source_; }
  const TfTable* tf() const { return tf_ ? &*tf_ : nullptr; }
  Camera cameraOf(uint32_t frame) const {
    const BrickSourceInfo& info = bricks().info();
    const glm::dvec3 boxMax = info.volume.worldMax();
    return path_ ? sampleCameraPath(*path_, frame, frames, glm::dvec3(0.0), boxMax) : chooseCamera(o_, info);
  }

  // Frame `frame`'s color as --every writes it: marked with --marks, as -o's (frames past the path's end, of
  // --converge, keep its last camera).
  FloatImage seriesImage(uint32_t frame, FloatImage color) const {
    if (o_.marks)
      drawOrientationMarks(color, cameraOf(std::min(frame, frames - 1)), bricks().info().volume.axes);
    return color;
  }

  uint32_t width = 0, height = 0;
  RenderParams params;
  uint32_t frames = 1;
  std::optional<FrameSeries> series;  // --every's frames, set once everything above is checked

 private:
  std::optional<StatsWriter> ownStats_;  // likewise
  StatsWriter* stats_ = nullptr;
  std::string statsFields_;
};

// --reference: the CPU ray marcher over the full-resolution data, the last frame's camera.
RenderedFrame renderReference(const RenderSetup& s) {
  ReferenceRenderer reference(s.bricks());
  CpuRenderInput input;
  input.camera = s.cameraOf(s.frames - 1);
  input.width = s.width;
  input.height = s.height;
  input.params = s.params;
  input.tf = s.tf();
  const CpuImage image = reference.render(input);
  return renderedFrame(toFloatImage(image.rgba, image.width, image.height, 4),
                       toFloatImage(image.depth, image.width, image.height, 1));
}

// --backend brute: the baseline of bench/render_vs_brute.sh, level 0 in one 3D texture and no index
// (render/brute_force_pass), in the shader stage of --brute-stage; auto resolves as --backend auto does, so
// that by default it runs in the stage the octree ray caster would.
RenderedFrame renderBrute(const RenderOptions& o, RenderSetup& s) {
  GlContext gl;
  BruteForcePass brute(s.bricks());
  BruteForceFrame bf;
  bf.params = s.params;
  bf.params.backend = resolveBackend(o.bruteStage.value_or(RenderBackend::Auto), gl.info().renderer);
  bf.tf = s.tf();
  bf.width = s.width;
  bf.height = s.height;
  for (uint32_t frame = 0; frame < s.frames; ++frame) {
    const auto start = SteadyClock::now();
    bf.camera = s.cameraOf(frame);
    brute.render(bf);
    FrameStats stats;
    stats.frame = frame;
    stats.raycastMs = brute.lastRaycastMs();
    stats.stepVoxels = bf.params.stepVoxels;
    stats.raycastWallClock = brute.raycastTimerUsedWallClock();
    stats.backend = RenderBackend::Brute;
    stats.stage = bf.params.backend;
    stats.drawCalls = 1;
    stats.glDrawCalls = 1;
    stats.fragments = uint64_t(bf.width) * bf.height;
    stats.frameMs = millisecondsSince(start);
    stats.converged = true;
    s.writeStats(stats);
    if (o.every > 0 && (frame % o.every == 0 || frame + 1 == s.frames))
      s.series->write(frame, s.seriesImage(frame, brute.readColor()));
  }
  return renderedFrame(brute.readColor(), brute.readDepth());
}

// The octree ray caster of both remaining paths, its shader compiled (FrameRenderer::prepare) and the request
// of frame 0; the FrameRenderer resolves --backend auto for the context's GL renderer.
struct OctreeRender {
  OctreeRender(const RenderOptions& o, const RenderSetup& s, const GlContext& gl, bool synchronous) {
    request.width = s.width;
    request.height = s.height;
    request.params = s.params;
    request.voxelsPerPixel = o.voxelsPerPixel;
    request.tf = s.tf();
    request.synchronous = synchronous;
    // --converge stops at the first converged frame: one that would only draw the converged image again
    // keeps it.
    request.keepConvergedImage = o.converge;
    // --converge waits for the reads after a frame that uploaded nothing on a still camera; the frame itself
    // would show nothing new.
    request.keepImageWhileReading = o.converge;
    // --converge writes only the converged image: a frame whose cut changed in places casts those places.
    request.recastChangesOnly = o.converge;
    request.camera = s.cameraOf(0);
    // A synchronous frame's reads begin while the GPU pool is made.
    renderer =
        std::make_unique<FrameRenderer>(gl.info(), s.bricks(), frameRendererConfigOf(o, s.params), &request);
    renderer->prepare(request);  // shader compilation before frame 0, not in its frame_ms
  }
  std::unique_ptr<FrameRenderer> renderer;
  FrameRequest request;
};

// Options given that the chosen mode or renderer does not read. A warning, not a usage error: scripts pass
// one set of options to both modes and to every renderer they compare.
void warnUnusedOptions(const CLI::App& app, const RenderOptions& o) {
  const auto warn = [&app, &o](std::initializer_list<const char*> names, const std::string& context) {
    std::string given;
    for (const char* name : names)
      if (app.count(name) > 0) given += (given.empty() ? "" : ", ") + std::string(name);
    if (!given.empty())
      std::fprintf(stderr, "%sropecast render: warning: %s: no effect %s\n", o.messagePrefix.c_str(),
                   given.c_str(), context.c_str());
  };
  if (o.mode == RenderMode::Dvr)
    warn({"--iso", "--caps", "--iso-color"}, "with --mode dvr (the transfer function decides)");
  if (o.mode == RenderMode::Iso)
    warn({"--tf", "--tf-range", "--ert", "--gradients", "--shading"}, "with --mode iso");
  if (o.mode == RenderMode::Dvr && !o.shading)
    warn({"--gradients"}, "with --shading off (no gradient is taken)");
  if (o.mode == RenderMode::Slice)
    warn({"--step", "--target-frame-ms"},
         "with --mode slice (one sample per ray, where it crosses the plane)");
  if (showsOneValue(o.mode)) {
    const std::string mode = "with --mode " + std::string(renderModeName(o.mode));
    warn({"--iso", "--ert", "--gradients", "--caps", "--iso-color", "--shading", "--material"},
         mode + " (one value per ray through the transfer function)");
    warn({"--occlusion", "--query-budget", "--visibility-threshold"},
         mode + (o.mode == RenderMode::Slice ? " (nothing behind the plane is drawn: no occlusion queries)"
                                             : " (nothing opaque stops its rays: no occlusion queries)"));
  }
  if (o.reference || o.backend == RenderBackend::Brute)
    warn({"--voxels-per-pixel", "--gpu-budget", "--cpu-cache", "--upload-budget", "--upload-time-budget",
          "--upload-pbo", "--io-delay-ms", "--occlusion", "--feedback", "--query-budget",
          "--visibility-threshold"},
         o.reference ? "with --reference (full-resolution data on the CPU, no octree)"
                     : "with --backend brute (level 0 in one 3D texture, no octree)");
  // With --path, --frames says which camera is the last frame's, the one --reference renders.
  if (o.reference && o.path.empty()) warn({"--frames"}, "with --reference without --path (one image)");
}

// One frame (no --converge, --frames 1; with --path, its first camera): load everything the view needs, then
// draw.
RenderedFrame renderSingleFrame(const RenderOptions& o, RenderSetup& s) {
  GlContext gl;
  OctreeRender octree(o, s, gl, /*synchronous=*/true);
  ProgressBar progress("render", "", o.quiet);
  LoadProgressFn showLoad;
  if (progress.enabled()) {
    showLoad = [&progress](const LoadProgress& p) {
      char text[128];
      std::snprintf(text, sizeof text, "loading, %llu bricks read, %llu pending, %.1f MiB",
                    static_cast<unsigned long long>(p.bricksRead),
                    static_cast<unsigned long long>(p.readsPending), mebibytes(p.bytesRead));
      progress.status(text, p.readsPending == 0);
    };
  }
  const FrameStats stats = octree.renderer->render(octree.request, showLoad);
  s.writeStats(stats);
  warnIfPoolLimited(o, stats, "render");
  return renderedFrame(octree.renderer->readColor(), octree.renderer->readDepth());
}

// --frames N > 1 (along --path, if given), --converge: the asynchronous loader streams bricks while frames
// render, and no frame waits for the disk.
RenderedFrame renderProgressive(const RenderOptions& o, RenderSetup& s) {
  GlContext gl;
  OctreeRender octree(o, s, gl, /*synchronous=*/false);
  FrameRequest& request = octree.request;
  const uint32_t frameCap = o.converge ? std::max(s.frames, o.maxFrames) : s.frames;
  StepPacer stepPacer(o.targetFrameMs);
  ProgressBar progress("render", "", o.quiet);
  uint64_t bytesRead = 0;
  for (uint32_t frame = 0;; ++frame) {
    request.camera = s.cameraOf(std::min(frame, s.frames - 1));
    request.params.stepVoxels = s.params.stepVoxels * stepPacer.scale();
    const FrameStats stats = octree.renderer->render(request);
    // A converged view holds its step: its frames cost less (no queries, no feedback), and a step they made
    // smaller would be a new view whose queries answer differently, undoing the convergence.
    if (stats.drawn && !stats.converged) stepPacer.record(stats.frameMs, stats.raycastMs);
    s.writeStats(stats);
    const bool last = o.converge ? (frame + 1 >= s.frames && stats.converged) || frame + 1 >= frameCap
                                 : frame + 1 >= s.frames;
    bytesRead += stats.bytesRead;
    if (progress.enabled()) {
      char text[160];
      const std::string of = o.converge && s.frames <= 1 ? "" : "/" + std::to_string(s.frames);
      std::snprintf(text, sizeof text,
                    "frame %u%s, working set %llu bricks, %llu reads pending, %.1f MiB read", frame + 1,
                    of.c_str(), static_cast<unsigned long long>(stats.workingSetBricks),
                    static_cast<unsigned long long>(stats.requestsPending), mebibytes(bytesRead));
      progress.status(text, last);
    }
    // --every writes the frame's PNG only: the EXR and depth outputs are the last frame's, written once.
    // The last frame too, so that a numbered sequence (a movie) ends on the final image.
    if (o.every > 0 && (frame % o.every == 0 || last))
      s.series->write(frame, s.seriesImage(frame, octree.renderer->readColor()));
    if (last) {
      progress.finish();  // the line ends before any message
      if (o.converge && !stats.converged)
        std::fprintf(stderr, "%sropecast render: not converged after %u frames (--max-frames)\n",
                     o.messagePrefix.c_str(), frame + 1);
      warnIfPoolLimited(o, stats, "render");
      break;
    }
    // A still camera, nothing uploaded and reads pending: the next frame would draw the same cut. Waiting
    // for the reads (a slow disk), at most a tenth of a second, keeps the frames, and --max-frames, for
    // frames that show progress.
    const bool stillCamera = o.path.empty() || frame + 1 >= s.frames;
    if (o.converge && stillCamera && stats.bricksUploaded == 0 && stats.requestsPending > 0)
      octree.renderer->waitForReads(std::chrono::milliseconds(100));
  }
  return renderedFrame(octree.renderer->readColor(), octree.renderer->readDepth());
}

}  // namespace

namespace {

// The last frame of the render `setup` was made for, by the path its options choose.
RenderedFrame renderWith(const RenderOptions& o, RenderSetup& setup) {
  RenderedFrame frame;
  if (o.reference)
    frame = renderReference(setup);
  else if (o.backend == RenderBackend::Brute)
    frame = renderBrute(o, setup);
  else if (o.converge || o.frames > 1)
    frame = renderProgressive(o, setup);
  else
    frame = renderSingleFrame(o, setup);
  frame.camera = setup.cameraOf(setup.frames - 1);
  frame.axes = setup.bricks().info().volume.axes;
  return frame;
}

}  // namespace

RenderedFrame renderFrames(const RenderOptions& o, const StageImages& stageImages) {
  RenderSetup setup(o);
  const RenderedFrame frame = renderWith(o, setup);
  // Every output is written before any is renamed; the renames that can fail for a reason found on disk (a
  // folder where a frame goes) are checked first.
  std::vector<StagedImage> staged;
  if (stageImages) staged = stageImages(frame);
  setup.series->checkTargets();
  for (StagedImage& image : staged) image->commit();
  setup.finishStats();
  setup.series->commit();
  return frame;
}

FloatImage colorOutputOf(const RenderOptions& o, const RenderedFrame& frame) {
  FloatImage color = frame.color;
  if (o.marks) drawOrientationMarks(color, frame.camera, frame.axes);
  return color;
}

namespace {

// --times: each time point rendered as `render --time T` would, one after another (a compressed file's later
// time points start from the access points its first took, store/deflate_index.h), every image staged until
// the last is rendered; one --stats file, each line with its time_point.
void renderTimeLapse(const RenderOptions& o, TimeRange times) {
  StatsWriter stats(o.stats, "--stats");
  std::vector<StagedImage> staged;
  if (!o.quiet)
    std::fprintf(stderr,
                 "%sropecast render: time points %u to %u of %s, each converted to a temporary store\n",
                 o.messagePrefix.c_str(), times.begin, times.end - 1, o.input.c_str());
  ProgressBar progress("render", "", o.quiet);
  for (uint32_t t = times.begin; t < times.end; ++t) {
    if (progress.enabled()) {
      char text[96];
      std::snprintf(text, sizeof text, "time point %u (%u of %u)", t, t - times.begin + 1,
                    times.end - times.begin);
      progress.status(text, false);
    }
    const RenderOptions at = timePointOptions(o, t, t == times.begin);
    RenderSetup setup(at, &stats, "\"time_point\":" + std::to_string(t));
    const RenderedFrame frame = renderWith(at, setup);
    for (StagedImage& image : stageOutputs(at, frame)) staged.push_back(std::move(image));
  }
  progress.finish();
  for (StagedImage& image : staged) image->commit();
  stats.finish();
}

int runRender(const CLI::App& app, const RenderOptions& o) {
  if (o.output.empty()) throw UsageError("render: -o OUT.png is required");
  if (o.reference && !o.stats.empty())
    throw UsageError(
        "render: --stats has nothing to record with --reference (one CPU render of the full-resolution "
        "data, without the loader or the GPU); leave one of them out");
  if (o.reference && (o.converge || o.every > 0))
    throw UsageError(
        std::string("render: ") + (o.converge ? "--converge" : "--every") +
        " has nothing to do with --reference (one CPU render of the full-resolution data, of the "
        "camera of --path's last frame); leave one of them out");
  if (o.every > 0 && !(o.converge || o.frames > 1))
    throw UsageError("render: --every " + std::to_string(o.every) +
                     " writes frames of a progressive render: add --frames N or --converge");
  if (!o.times.empty() && o.every > 0)
    throw UsageError(
        "render: --every numbers a progressive render's frames OUT_NNNN.png, as --times numbers its time "
        "points; leave one of them out");
  checkSceneOptions(o);
  warnUnusedOptions(app, o);
  checkImageOutputs(o);
  std::optional<TimeRange> times;
  if (!o.times.empty()) times = timeRangeOf(o);
  checkOutputsAreNew(o, times);
  removeTemporaryFilesOnSignals();  // an interrupted render leaves no temporary behind
  if (times)
    renderTimeLapse(o, *times);
  else
    renderFrames(o, [&o](const RenderedFrame& frame) { return stageOutputs(o, frame); });
  return 0;
}

}  // namespace

void addRenderOptions(CLI::App& app, RenderOptions& o) {
  addSceneOptions(app, o, SceneCommand::Render);
  app.add_option("--exr", o.exr, "also write float RGBA EXR (alpha = coverage)")
      ->check(nonEmptyPath("a file"));
  app.add_option("--depth", o.depth, "also write the depth (world units along the view axis) as EXR")
      ->check(nonEmptyPath("a file"));
  app.add_option("--stats", o.stats, "write one JSON object per frame, one per line")
      ->check(nonEmptyPath("a file"));
  app.add_flag("--reference", o.reference, "brute-force CPU ray marching of the full-resolution data instead")
      ->excludes(app.get_option("--backend"));
  app.add_option("--frames", o.frames,
                 "frames to render (more than 1: progressive loading; with --converge, at least this many)")
      ->transform(integerRange(1, 1000000));
  CLI::Option* path = app.add_option("--path", o.path, "camera path: JSON list of cameras or keyframes")
                          ->check(notEmpty("a camera path file"));
  for (const char* camera : {"--orbit", "--view", "--eye", "--target", "--up", "--fov"})
    path->excludes(app.get_option(camera));
  CLI::Option* converge = app.add_flag("--converge", o.converge,
                                       "render until the working set is complete and nothing is pending");
  app.add_option("--max-frames", o.maxFrames, "frame cap for --converge")
      ->transform(integerRange(1, 1000000))
      ->capture_default_str()
      ->needs(converge);
  app.add_option("--every", o.every, "also write every K-th frame, and the last, as OUT_NNNN.png")
      ->transform(integerRange(1, 1000000));
  app.add_flag("--marks", o.marks,
               "draw orientation marks into the PNG (not the EXR): at each edge's middle the sides of the "
               "patient it faces (LPS letters), and the volume's axes in the bottom-left corner, as the "
               "viewer draws them");
  app.add_flag("-q,--quiet", o.quiet, "no progress line (drawn only when stderr is a terminal)");
}

namespace {

const CommandRegistration renderCommand("render", 50, [](CLI::App& app) -> std::function<int()> {
  auto o = std::make_shared<RenderOptions>();
  app.description(
      "render a store, a volume or procedural:NAME:SIZE headless to PNG (and EXR, depth, per-frame stats)");
  app.add_option("input", o->input,
                 "store file (.rcast), a volume as convert reads it (converted to a temporary store first), "
                 "or procedural:NAME:SIZE")
      ->required();
  app.add_option("-o,--output", o->output, "output PNG")->required()->check(nonEmptyPath("a file"));
  addRenderOptions(app, *o);
  app.add_option("--times", o->times,
                 "render time points A to B - 1 of a time series, from 0 (A:B, A:, :B or :, as Python's "
                 "slices), each as --time T would, to OUT_TTTT.png (--exr's and --depth's numbered alike; "
                 "--stats lines say their time_point)")
      ->excludes(app.get_option("--time"));
  return [o, &app] { return runRender(app, *o); };
});

}  // namespace
}  // namespace ropecast::tools
