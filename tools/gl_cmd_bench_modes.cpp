// `ropecast bench modes`: rendering strategies side by side on one input (tools/bench_modes.h). Each
// configuration renders the same camera path with a fresh FrameRenderer (cold CPU cache and GPU pool), every
// frame synchronous, so every configuration draws the same cut of each view; the repetitions are interleaved
// (repetition 1 of every configuration, then repetition 2, ...) so that a change of the machine's load falls
// on all of them. Writes DIR/bench.json, DIR/frame_times.png (matplotlib, through the script it writes as
// DIR/plot_frame_times.py), DIR/images/ (each configuration's last frame and its difference from the first
// configuration's; PPM from a build without OpenImageIO) and prints a table. Main thread only.
#include <spawn.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/camera_path.h"
#include "core/error.h"
#include "core/orientation.h"
#include "core/temporary_file.h"
#include "core/transfer_function.h"
#include "reference/image_compare.h"
#include "reference/image_io.h"
#include "render/backend_choice.h"
#include "render/frame_renderer.h"
#include "render/gl_context.h"
#include "tools/bench_modes.h"
#include "tools/cli_checks.h"
#include "tools/cli_values.h"
#include "tools/command.h"
#include "tools/gl_render_options.h"
#include "tools/output_guard.h"
#include "tools/progress_bar.h"
#include "tools/volume_read_options.h"

extern char** environ;

namespace ropecast::tools {
namespace {

// The configurations `--configs` can name: the single pass with each entry point, and the multi-pass
// renderer (Gobbetti et al. 2008, Sect. 2).
const std::vector<std::pair<std::string, RenderBackend>> kConfigs{
    {"single-fragment", RenderBackend::Fragment},
    {"single-compute", RenderBackend::Compute},
    {"multipass", RenderBackend::Multipass}};
constexpr double kDifferenceScale = 10.0;  // the difference images show |a - b| times this

struct Options {
  std::string input;
  std::string path;
  std::vector<double> orbit;
  double turnDeg = 90.0;
  uint32_t frames = 8;
  uint32_t reps = 3;
  RenderMode mode = RenderMode::Iso;
  std::optional<double> iso;
  std::string tf;               // empty: ct-soft, or gray for an intensity projection
  std::vector<double> tfRange;  // --tf-range LO,HI; empty: none
  std::vector<uint32_t> size{512, 512};
  double step = 0.5;
  double voxelsPerPixel = 1.0;
  uint64_t gpuBudget = 0;
  uint64_t cpuCache = uint64_t(1) << 30;
  std::optional<uint32_t> brick;  // procedural inputs only
  VolumeReadArgs read;            // for a volume read from its file
  std::string configs;
  std::string out = "bench_modes";
  bool quiet = false;
  bool noPlot = false;  // no frame_times.png
};

// The plot, run as `python3 plot_frame_times.py bench.json frame_times.png`: frame time along the path per
// configuration (the median over repetitions, each repetition faint), with a legend.
constexpr const char* kPlotScript =
    R"PY(# Written and run by `ropecast bench modes`: plots DIR/bench.json's frame times along the camera path.
import json
import statistics
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.ticker import MaxNLocator

bench = json.load(open(sys.argv[1]))
settings = bench["settings"]
per_rep = settings["frames"]
fig, ax = plt.subplots(figsize=(9, 4.8), dpi=100)
for i, config in enumerate(bench["configs"]):
    times = [f["frame_ms"] for f in config["frames"]]
    reps = [times[r * per_rep:(r + 1) * per_rep] for r in range(len(times) // per_rep)]
    color = "C%d" % i
    for rep in reps:
        ax.plot(range(per_rep), rep, color=color, alpha=0.25, linewidth=1)
    median = [statistics.median(rep[f] for rep in reps) for f in range(per_rep)]
    warm = [t for i, t in enumerate(times) if per_rep == 1 or i % per_rep != 0]  # as the printed table
    ax.plot(range(per_rep), median, color=color, marker="o", linewidth=2,
            label="%s (median %.1f ms)" % (config["name"], statistics.median(warm)))
ax.set_xlabel("frame along the camera path (frame 0: cold start)")
ax.set_ylabel("frame time [ms]")
ax.set_yscale("log")
ax.xaxis.set_major_locator(MaxNLocator(integer=True))
ax.set_title("%s, %s, %dx%d, %s" % (settings["input"], settings["mode"], settings["width"],
                                     settings["height"], bench["gl_renderer"]), fontsize=9)
ax.grid(True, which="both", alpha=0.3)
ax.legend()
fig.tight_layout()
fig.savefig(sys.argv[2])
)PY";

// "a,b,c" -> the named configurations; empty: the single pass with the platform's default entry point, the
// single pass with the other one, multi-pass.
std::vector<std::pair<std::string, RenderBackend>> chooseConfigs(const std::string& list,
                                                                 const std::string& glRenderer) {
  if (list.empty()) {
    const RenderBackend first = resolveBackend(RenderBackend::Auto, glRenderer);
    const RenderBackend second =
        first == RenderBackend::Fragment ? RenderBackend::Compute : RenderBackend::Fragment;
    std::vector<std::pair<std::string, RenderBackend>> chosen;
    for (RenderBackend b : {first, second, RenderBackend::Multipass})
      for (const auto& c : kConfigs)
        if (c.second == b) chosen.push_back(c);
    return chosen;
  }
  std::vector<std::pair<std::string, RenderBackend>> chosen;
  std::stringstream names(list);
  for (std::string name; std::getline(names, name, ',');) {
    const auto c =
        std::find_if(kConfigs.begin(), kConfigs.end(), [&](const auto& e) { return e.first == name; });
    if (c == kConfigs.end())
      throw UsageError("--configs: unknown configuration '" + name +
                       "' (expected a comma-separated list of single-fragment, single-compute, multipass)");
    if (std::find(chosen.begin(), chosen.end(), *c) != chosen.end())
      throw UsageError("--configs: '" + name + "' is listed twice");
    chosen.push_back(*c);
  }
  return chosen;
}

double percentile(std::vector<double> values, double p) {
  std::sort(values.begin(), values.end());
  const double rank = p * double(values.size() - 1);
  const size_t lo = size_t(std::floor(rank)), hi = size_t(std::ceil(rank));
  return values[lo] + (values[hi] - values[lo]) * (rank - double(lo));
}

// The Python that has Debian's python3-matplotlib: $ROPECAST_PYTHON, else the system's /usr/bin/python3
// (a python3 found first on PATH, pyenv's or a virtualenv's, need not see Debian's packages), else python3.
std::string pythonInterpreter() {
  if (const char* chosen = std::getenv("ROPECAST_PYTHON"); chosen && *chosen) return chosen;
  if (std::filesystem::exists("/usr/bin/python3")) return "/usr/bin/python3";
  return "python3";
}

// Runs `PYTHON script args...` without a shell; its exit status (127: the interpreter was not found).
int runPython(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  std::string python = pythonInterpreter();
  argv.push_back(python.data());
  std::vector<std::string> copies = args;
  for (std::string& a : copies) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawnp(&pid, python.c_str(), nullptr, nullptr, argv.data(), environ) != 0) return 127;
  int status = 0;
  if (waitpid(pid, &status, 0) != pid) return 127;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

void writeText(const std::filesystem::path& path, const std::string& text) {
  writeFileAtomically(path, std::as_bytes(std::span(text)), "bench modes");
}

// The outermost folder a run made for --out and its images/, removed again with what is in it unless the run
// keeps it: a bench that fails leaves no empty or half-filled folder behind.
class MadeFolders {
 public:
  MadeFolders() = default;
  MadeFolders(const MadeFolders&) = delete;
  MadeFolders& operator=(const MadeFolders&) = delete;
  ~MadeFolders() {
    std::error_code ignored;
    if (made_) std::filesystem::remove_all(*made_, ignored);
  }
  // Makes `folder` and its missing parents.
  void make(const std::filesystem::path& folder, std::error_code& error) {
    std::filesystem::path outermost;
    for (std::filesystem::path p = std::filesystem::absolute(folder);
         !p.empty() && !std::filesystem::exists(p); p = p.parent_path())
      outermost = p;
    std::filesystem::create_directories(folder, error);
    if (!error && !outermost.empty()) made_ = outermost;
  }
  void keep() { made_.reset(); }

 private:
  std::optional<std::filesystem::path> made_;
};

int runModesBench(const Options& o) {
  if (o.reps == 0) throw UsageError("--reps must be at least 1");
  if (o.frames == 0) throw UsageError("--frames must be at least 1");
  if (!o.path.empty() && !o.orbit.empty()) throw UsageError("--path and --orbit exclude each other");
  checkTfRange(o.tfRange);
  const std::filesystem::path out(o.out);
  if (!o.configs.empty()) chooseConfigs(o.configs, "");  // names checked before anything is read
  // No output may be an input (the store, --tf, --path); checked before anything is written.
  OutputGuard guard("bench modes");
  guard.addVolumeInput("the input", o.input);
  if (std::filesystem::is_regular_file(o.tf)) guard.addInput("--tf", o.tf);
  guard.addInput("--path", o.path);
  guard.addOutput("--out", (out / "bench.json").string());
  if (!o.noPlot) {
    guard.addOutput("--out", (out / "plot_frame_times.py").string());
    guard.addOutput("--out", (out / "frame_times.png").string());
  }
  guard.addOutputSeries("--out", (out / "images").string(), "*", [](const std::string&) { return true; });
  guard.check();
  const std::unique_ptr<BrickSource> source =
      openBrickSource(o.input, o.brick, o.read, o.quiet, "bench modes");
  const BrickSourceInfo& info = source->info();
  const glm::dvec3 boxMax = info.volume.worldMax();

  FrameRequest request;
  request.width = o.size.at(0);
  request.height = o.size.at(1);
  request.synchronous = true;
  request.voxelsPerPixel = o.voxelsPerPixel;
  request.params.mode = o.mode;
  request.params.stepVoxels = o.step;
  request.params.gradients = GradientSource::Stored;
  const uint32_t storedMax = storedMaxOf(info.storedType);
  const double lo = info.volume.valueMin.value_or(info.mapping.toData(0));
  const double hi = info.volume.valueMax.value_or(info.mapping.toData(storedMax));
  request.params.isoValue = o.iso.value_or(0.5 * (lo + hi));
  if (o.mode == RenderMode::Slice)  // the axial plane through the center, as render's default
    request.params.clipPlane = defaultSlicePlane(request.params, info.volume);
  std::optional<TfTable> tf;
  const std::string tfSpec = !o.tf.empty() ? o.tf : showsOneValue(o.mode) ? defaultTfSpec(o.mode) : "ct-soft";
  const TransferFunction function =
      windowed(TransferFunction::fromSpec(tfSpec, tfDataRangeFor(info)), o.tfRange);
  if (usesTransferFunction(o.mode)) {
    tf = TfTable::bake(function, info.mapping, storedMax);
    request.tf = &*tf;
  }

  CameraPath path;
  if (!o.path.empty()) {
    path = loadCameraPath(o.path);
  } else {
    const glm::dvec3 orbit = o.orbit.empty() ? glm::dvec3(30.0, 20.0, 1.6) : toVec3(o.orbit);
    if (!(orbit.z > 0.0))
      throw UsageError("--orbit: the distance must be positive, got " + formatTriple(o.orbit));
    CameraKeyframe a, b;
    a.isOrbit = b.isOrbit = true;
    a.orbit = orbit;
    b.orbit = orbit + glm::dvec3(o.turnDeg, 0.0, 0.0);
    b.time = 1.0;
    path.keyframes = {a, b};
  }
  std::vector<Camera> cameras;
  for (uint32_t f = 0; f < o.frames; ++f) {
    cameras.push_back(sampleCameraPath(path, f, o.frames, glm::dvec3(0.0), boxMax));
    if (const std::string problem = viewProblem(cameras.back().eye, cameras.back().target); !problem.empty())
      throw Error("camera path frame " + std::to_string(f) + ": " + problem);
  }

  // The outputs' folder is made and checked before the first frame. Images are PNG, or PPM from a build
  // without OpenImageIO (made to be carried to a GPU machine), which writes nothing else.
  std::error_code error;
  MadeFolders madeFolders;
  madeFolders.make(out / "images", error);
  if (error) throw Error("--out " + o.out + ": cannot create the folder: " + error.message());
  const std::string imageExt =
      imageOutputProblem((out / "images" / "x.png").string(), ImageOutputKind::Color8).empty() ? ".png"
                                                                                               : ".ppm";
  if (const std::string problem =
          imageOutputProblem((out / "images" / ("x" + imageExt)).string(), ImageOutputKind::Color8);
      !problem.empty())
    throw Error("--out " + o.out + ": " + problem);

  GlContext gl;
  const auto configs = chooseConfigs(o.configs, gl.info().renderer);
  struct Run {
    std::vector<FrameStats> frames;
    FloatImage lastColor;
  };
  std::vector<Run> runs(configs.size());
  ProgressBar progress("bench modes", "frames", o.quiet);
  const uint64_t total = uint64_t(o.reps) * configs.size() * o.frames;
  uint64_t done = 0;
  for (uint32_t rep = 0; rep < o.reps; ++rep)
    for (size_t c = 0; c < configs.size(); ++c) {
      FrameRendererConfig config;
      config.gpuBudgetBytes = o.gpuBudget;
      config.cpuCacheBytes = o.cpuCache;
      config.storedGradients = usesStoredGradients(request.params);
      FrameRenderer renderer(gl.info(), *source, config);
      request.params.backend = configs[c].second;
      request.camera = cameras.front();
      renderer.prepare(request);  // shader compilation outside the frames' times
      for (const Camera& camera : cameras) {
        request.camera = camera;
        runs[c].frames.push_back(renderer.render(request));
        progress.update(++done, total);
      }
      if (rep + 1 == o.reps) runs[c].lastColor = renderer.readColor();
    }
  progress.finish();

  // bench.json
  nlohmann::json settings = {
      {"input", o.input},
      {"mode", std::string(renderModeName(o.mode))},
      {"width", request.width},
      {"height", request.height},
      {"step", o.step},
      {"voxels_per_pixel", o.voxelsPerPixel},
      {"gpu_budget", o.gpuBudget},
      {"cpu_cache", o.cpuCache},
      {"frames", o.frames},
      {"reps", o.reps},
      {"frames_order", "repetition-major: frames[rep * frames + i] is camera i"},
      {"cold_start", "a fresh FrameRenderer (empty CPU cache and GPU pool) per repetition"},
      {"synchronous", true},
      {"difference_scale", kDifferenceScale}};
  if (o.mode == RenderMode::Iso) settings["iso"] = request.params.isoValue;
  if (usesTransferFunction(o.mode)) settings["tf"] = tfSpec;
  if (usesTransferFunction(o.mode) && o.tfRange.size() == 2) settings["tf_range"] = o.tfRange;
  if (!o.path.empty())
    settings["path"] = o.path;
  else
    settings["orbit"] = {{"start", o.orbit.empty() ? std::vector<double>{30.0, 20.0, 1.6} : o.orbit},
                         {"turn_deg", o.turnDeg}};
  nlohmann::json bench = {
      {"settings", settings}, {"gl_renderer", gl.info().renderer}, {"configs", nlohmann::json::array()}};
  for (size_t c = 0; c < configs.size(); ++c) {
    nlohmann::json frames = nlohmann::json::array();
    for (const FrameStats& s : runs[c].frames)
      frames.push_back({{"frame_ms", s.frameMs},
                        {"raycast_ms", s.raycastMs},
                        {"draw_calls", s.drawCalls},
                        {"leaves", s.leaves},
                        {"bricks_resident", s.bricksResident},
                        {"bytes_uploaded", s.bytesUploaded}});
    bench["configs"].push_back({{"name", configs[c].first}, {"frames", frames}});
  }
  // File names (the input, --path) need not be UTF-8: bytes that are not become U+FFFD.
  writeText(out / "bench.json", bench.dump(1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");

  // images/: each last frame, and its difference from the first configuration's; an earlier run's images of
  // other configurations go, so that the folder shows this run alone.
  for (const auto& entry : std::filesystem::directory_iterator(out / "images")) {
    const std::string stem = entry.path().stem().string();
    const bool ours =
        entry.path().extension() == imageExt &&
        (stem.starts_with("diff_") ||
         std::any_of(kConfigs.begin(), kConfigs.end(), [&](const auto& c) { return c.first == stem; }));
    if (ours && entry.is_regular_file()) std::filesystem::remove(entry.path());
  }
  const FloatImage& reference = runs.front().lastColor;
  std::vector<double> psnr(configs.size(), std::numeric_limits<double>::infinity());
  for (size_t c = 0; c < configs.size(); ++c) {
    const FloatImage& image = runs[c].lastColor;
    writePng((out / "images" / (configs[c].first + imageExt)).string(), image, false);
    if (c == 0) continue;
    psnr[c] = compareImages(reference.pixels, 4, image.pixels, 4, 3).psnrDb;
    FloatImage diff = image;
    for (size_t i = 0; i < diff.pixels.size(); ++i)
      diff.pixels[i] =
          i % 4 == 3
              ? 1.0f
              : std::min(1.0f, float(kDifferenceScale) * std::abs(image.pixels[i] - reference.pixels[i]));
    writePng((out / "images" / ("diff_" + configs[c].first + "_vs_" + configs[0].first + imageExt)).string(),
             diff, false);
  }

  // The table: frame and ray-cast times without each repetition's cold first frame (when there are others).
  std::printf("bench modes: %s, %s, %ux%u, %u frames x %u repetitions, %s\n", o.input.c_str(),
              std::string(renderModeName(o.mode)).c_str(), request.width, request.height, o.frames, o.reps,
              gl.info().renderer.c_str());
  std::printf("  times over %s; ratios: configuration / %s; PSNR of the last frame against %s\n",
              o.frames > 1 ? "frames 1.. of each repetition (frame 0 is the cold start)" : "every frame",
              configs[0].first.c_str(), configs[0].first.c_str());
  std::printf("  %-16s %10s %10s %10s %12s %8s %8s %10s %8s %8s %9s\n", "config", "median ms", "p95 ms",
              "max ms", "raycast ms", "ratio", "p95 rat", "draws", "frag/px", "leaves", "PSNR dB");
  double refMedian = 0.0, refP95 = 0.0;
  for (size_t c = 0; c < configs.size(); ++c) {
    std::vector<double> frameMs, raycastMs, fragmentsPerPixel;
    uint64_t draws = 0, leaves = 0;
    for (size_t i = 0; i < runs[c].frames.size(); ++i) {
      const FrameStats& s = runs[c].frames[i];
      if (o.frames > 1 && i % o.frames == 0) continue;
      frameMs.push_back(s.frameMs);
      raycastMs.push_back(s.raycastMs);
      fragmentsPerPixel.push_back(double(s.fragments) / (double(request.width) * request.height));
      draws = std::max(draws, s.drawCalls);
      leaves = std::max(leaves, s.leaves);
    }
    const double median = percentile(frameMs, 0.5), p95 = percentile(frameMs, 0.95);
    if (c == 0) refMedian = median, refP95 = p95;
    std::printf("  %-16s %10.1f %10.1f %10.1f %12.1f %8.2f %8.2f %10llu %8.2f %8llu %9s\n",
                configs[c].first.c_str(), median, p95, *std::max_element(frameMs.begin(), frameMs.end()),
                percentile(raycastMs, 0.5), median / refMedian, p95 / refP95, (unsigned long long)draws,
                percentile(fragmentsPerPixel, 0.5), (unsigned long long)leaves,
                std::isinf(psnr[c]) ? "inf" : std::to_string(psnr[c]).substr(0, 6).c_str());
  }

  madeFolders.keep();  // bench.json and the images are written

  // The plot. An earlier run's goes first, so that a failed or skipped plot leaves none that looks like this
  // run's.
  std::error_code removeError;
  std::filesystem::remove(out / "frame_times.png", removeError);
  if (o.noPlot) {
    std::printf("  wrote %s, %s\n", (out / "bench.json").string().c_str(), (out / "images").string().c_str());
    return 0;
  }
  writeText(out / "plot_frame_times.py", kPlotScript);
  const int status = runPython({(out / "plot_frame_times.py").string(), (out / "bench.json").string(),
                                (out / "frame_times.png").string()});
  if (status != 0) {
    std::filesystem::remove(out / "frame_times.png", removeError);  // whatever the failed plot left
    std::fprintf(stderr,
                 "ropecast: error: bench modes: plotting %s failed (exit status %d): it needs %s with "
                 "matplotlib (Debian: python3-matplotlib, which scripts/bootstrap installs); bench.json and "
                 "images/ are written\n",
                 (out / "frame_times.png").string().c_str(), status, pythonInterpreter().c_str());
    return 1;
  }
  std::printf("  wrote %s, %s, %s\n", (out / "bench.json").string().c_str(),
              (out / "frame_times.png").string().c_str(), (out / "images").string().c_str());
  return 0;
}

}  // namespace

std::function<int()> setupModesBench(CLI::App& app) {
  auto o = std::make_shared<Options>();
  app.add_option("input", o->input,
                 "store file (.rcast), a volume as convert reads it (converted to a temporary store first), "
                 "or procedural:NAME:SIZE")
      ->required();
  app.add_option("--path", o->path, "camera path: JSON list of cameras or keyframes (see `render --path`)")
      ->check(notEmpty("a camera path file"));
  addTripleOption(app, "--orbit", o->orbit,
                  "AZ,EL,DIST: the path's first camera, turning --turn degrees around the volume (default "
                  "30,20,1.6)");
  app.add_option("--turn", o->turnDeg, "degrees of azimuth the --orbit path turns")
      ->check(finiteIn(-3600.0, 3600.0))
      ->capture_default_str()
      ->excludes(app.get_option("--path"));
  app.add_option("--frames", o->frames, "frames along the path")
      ->transform(integerRange(1, 100000))
      ->capture_default_str();
  app.add_option("--reps", o->reps, "repetitions of the path per configuration, interleaved")
      ->transform(integerRange(1, 1000))
      ->capture_default_str();
  addEnumOption(app, "--mode", o->mode, kModeNames, kModeHelp);
  app.add_option("--iso", o->iso,
                 "isovalue in data units (default: middle of the value range: a store's recorded one, the "
                 "sample type's for procedural inputs)")
      ->check(finiteIn(-HUGE_VAL, HUGE_VAL));
  app.add_option("--tf", o->tf,
                 tfOptionHelp("ct-soft; gray with --mode mip, minip or aip; window with --mode slice"))
      ->check(notEmpty("a preset or a JSON file"));
  addRangeOption(
      app, "--tf-range", o->tfRange,
      "LO,HI: the transfer function stretched so its first point lies at LO and its last at HI, as "
      "render --tf-range");
  addImageSizeOption(app, "--size", o->size, "image size WxH (default 512x512)");
  app.add_option("--step", o->step, "sample distance in voxels of the level crossed")
      ->check(finiteIn(0.01, 8.0))
      ->capture_default_str();
  app.add_option("--voxels-per-pixel", o->voxelsPerPixel, "refinement target: voxels per pixel")
      ->check(finiteIn(0.01, 64.0))
      ->capture_default_str();
  addByteSizeOption(app, "--gpu-budget", o->gpuBudget, "GPU brick pool bytes (default from the driver)")
      ->check(nonZeroSize("leave --gpu-budget out for the driver's default"));
  addByteSizeOption(app, "--cpu-cache", o->cpuCache, "CPU brick cache bytes")->default_str("1G");
  app.add_option("--brick", o->brick, "brick size for procedural inputs and volumes")
      ->check(oneOf(std::vector<uint32_t>{8, 16, 32, 64}));
  addVolumeReadOptions(app, o->read);
  app.add_option(
         "--configs", o->configs,
         "comma-separated configurations: single-fragment, single-compute, multipass (default: the single "
         "pass with the platform's default entry point, then the other one, then multipass)")
      ->check(CLI::Validator(
          [](const std::string& list) {
            return list.empty() ? "expected at least one of single-fragment, single-compute, multipass "
                                  "(leave --configs out for the default set)"
                                : "";
          },
          "", "configs"));
  app.add_option("--out", o->out, "output folder: bench.json, frame_times.png, images/")
      ->capture_default_str()
      ->check(nonEmptyPath("a folder"));
  app.add_flag("-q,--quiet", o->quiet, "no progress bar");
  app.add_flag("--no-plot", o->noPlot, "write no frame_times.png (a machine without matplotlib)");
  return [o] { return runModesBench(*o); };
}

}  // namespace ropecast::tools
