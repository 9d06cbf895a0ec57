#include "tools/gl_render_options.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/number_text.h"
#include "core/orientation.h"
#include "loader/io_queue.h"
#include "store/procedural_bricks.h"
#include "store/store.h"
#include "store/volume_source.h"
#include "tools/cli_checks.h"
#include "tools/cli_values.h"
#include "tools/command.h"
#include "tools/progress_bar.h"
#include "tools/temporary_store.h"
#include "tools/volume_read_options.h"

namespace ropecast::tools {

namespace {
// A core name table as addEnumOption takes it.
template <class Enum, size_t N>
std::vector<std::pair<std::string, Enum>> optionNames(
    const std::array<std::pair<std::string_view, Enum>, N>& table) {
  std::vector<std::pair<std::string, Enum>> names;
  for (const auto& [name, value] : table) names.emplace_back(name, value);
  return names;
}
}  // namespace

const std::vector<std::pair<std::string, RenderMode>> kModeNames = optionNames(kRenderModeNames);
const char* const kModeHelp =
    "iso: isosurface; dvr: direct volume rendering; mip, minip, aip: maximum, minimum, average intensity "
    "projection; slice: the values on a plane, --clip-plane's or --slice's (default: the axial plane through "
    "the center)";
const std::vector<std::pair<std::string, bool>> kOnOffNames{{"on", true}, {"off", false}};
const std::vector<std::pair<std::string, GradientSource>> kGradientNames{
    {"stored", GradientSource::Stored}, {"computed", GradientSource::Computed}};

const std::vector<std::pair<std::string, RenderBackend>> kBruteStageNames{
    {"auto", RenderBackend::Auto},
    {"fragment", RenderBackend::Fragment},
    {"compute", RenderBackend::Compute}};

std::vector<std::pair<std::string, RenderBackend>> backendNames() {
  return optionNames(kRenderBackendNames);
}

void addSceneOptions(CLI::App& app, RenderOptions& o, SceneCommand command) {
  CLI::Option* mode = addEnumOption(app, "--mode", o.mode, kModeNames, kModeHelp);
  app.add_option("--iso", o.iso,
                 "isovalue in data units (default: middle of the value range: a store's recorded one, the "
                 "sample type's for procedural inputs)")
      ->check(finiteIn(-HUGE_VAL, HUGE_VAL));
  app.add_option("--tf", o.tf,
                 tfOptionHelp("linear; gray with --mode mip, minip or aip; window with --mode slice"))
      ->check(notEmpty("a preset or a JSON file"));
  addRangeOption(
      app, "--tf-range", o.tfRange,
      "LO,HI: a window in data units: the transfer function stretched so that its first point lies at "
      "LO and its last at HI (a preset placed over LO..HI instead of the value range; CT window "
      "width 400 at level 40: -160,240)");
  addImageSizeOption(app, "--size", o.size, "image size WxH, each in [1, 16384] (default 512x512)");
  CLI::Option* orbit = addTripleOption(
      app, "--orbit", o.orbit,
      "AZ,EL,DIST: degrees, degrees, bounding-sphere radii about z (default 30,20,3; for a volume in a "
      "patient's frame -60,20,3, facing the patient from its left front)");
  std::vector<std::pair<std::string, AnatomicalView>> views;
  for (const auto& [name, view] : kAnatomicalViewNames) views.emplace_back(name, view);
  CLI::Option* view = addEnumOption(
      app, "--view", o.view, views,
      "the eye on that side of the patient (LPS world: anterior toward -y, left toward +x, superior toward "
      "+z), looking at the volume's center from 3 bounding-sphere radii; superior up, anterior up from above "
      "and below (instead of --orbit)");
  orbit->excludes(view);
  // One way to place the camera: an orbit, a named view, or eye and target (and up); a camera ignored would
  // be a surprise.
  for (CLI::Option* camera : {addTripleOption(app, "--eye", o.eye, "camera position X,Y,Z (world units)"),
                              addTripleOption(app, "--target", o.target, "point looked at X,Y,Z"),
                              addTripleOption(app, "--up", o.up,
                                              "up vector X,Y,Z with --eye and --target (default 0,0,1; 0,1,0 "
                                              "when looking along z)")}) {
    orbit->excludes(camera);
    view->excludes(camera);
  }
  app.add_option("--fov", o.fov, "vertical field of view, degrees")
      ->check(finiteIn(1.0, 179.0))
      ->capture_default_str();
  addTripleOptionIn(app, "--background", o.background, "background R,G,B in [0,1] (default 0,0,0)", 0.0, 1.0);
  addVoxelRangesOption(
      app, "--crop", o.crop,
      "draw only the voxels X0..X1-1, Y0..Y1-1, Z0..Z1-1 of the volume: X0:X1,Y0:Y1,Z0:Z1, as "
      "Python slices (X0: or :X1 to the volume's edge, : the whole axis); bricks wholly "
      "outside are neither read nor drawn (default: the whole volume)");
  addPlaneOption(
      app, "--clip-plane", o.clipPlane,
      "X,Y,Z,NX,NY,NZ: cut the volume with the plane through the point X,Y,Z (world units) and "
      "draw the side its normal NX,NY,NZ points to; bricks wholly on the other side are neither read "
      "nor drawn (default: none); with --mode slice, the plane shown, and only bricks it crosses are read");
  // Given alone, --slice means --mode slice (options are parsed in the order they are added: --mode first).
  app.add_option_function<std::string>(
         "--slice",
         [&o, mode](const std::string& value) {
           o.slice = value;
           if (mode->count() == 0) o.mode = RenderMode::Slice;
         },
         "AXIS:INDEX: the slice of voxels INDEX along the volume's x, y or z axis (from 0, as --crop "
         "counts), its plane through their centers; --mode slice unless --mode says otherwise (instead "
         "of --clip-plane)")
      ->check(notEmpty("AXIS:INDEX, e.g. z:100"));
  app.add_option(
         "--slab", o.slab,
         "T: keep the slab of thickness T (world units) centered on --clip-plane's or --slice's plane, "
         "not a half-space: a thick-slab MIP, MinIP, AIP or DVR (default: none)")
      ->check(finiteIn(1e-12, 1e15));
  addEnumOption(app, "--caps", o.caps, kOnOffNames,
                "isosurface: where --crop or --clip-plane cuts the surface, close it with the cut's face "
                "(on), or leave it open to show it from within (off)");
  const LightingParams lighting;
  addTripleOptionIn(
      app, "--iso-color", o.isoColor,
      "isosurface color R,G,B in [0,1] (default " +
          formatTriple({lighting.isoBaseColor.x, lighting.isoBaseColor.y, lighting.isoBaseColor.z}) + ")",
      0.0, 1.0);
  addEnumOption(app, "--shading", o.shading, kOnOffNames,
                "DVR: light the transfer function's colors by the gradient (on), or keep them unlit (off, "
                "VTK's and ParaView's default for volumes)");
  addMaterialOption(app, "--material", o.material,
                    "KA,KD,KS,SHININESS: ambient, diffuse and specular weights in [0,1] and specular "
                    "exponent in [1,1024] of the headlight's shading, isosurface and DVR (default " +
                        formatNumber(lighting.ambient) + "," + formatNumber(lighting.diffuse) + "," +
                        formatNumber(lighting.specular) + "," + formatNumber(lighting.shininess) + ")");
  std::vector<std::pair<std::string, RenderBackend>> backends = backendNames();
  if (command == SceneCommand::View)
    std::erase_if(backends, [](const auto& named) { return named.second == RenderBackend::Brute; });
  addEnumOption(
      app, "--backend", o.backend, backends,
      std::string("auto: compute on hardware GPUs, fragment on software rasterizers (llvmpipe); "
                  "fragment or compute: the octree ray caster's entry point; ") +
          (command == SceneCommand::Render
               ? "brute: level 0 in one 3D texture, no index (a benchmark baseline; its shader stage: "
                 "--brute-stage); "
               : "") +
          "multipass: the same cut drawn one data brick per pass, composited front to back (no "
          "occlusion queries, no feedback). --stats names the one used");
  if (command == SceneCommand::Render)
    addEnumOption(
        app, "--brute-stage", o.bruteStage, kBruteStageNames,
        "with --backend brute: the shader stage its rays are cast in; auto: the one --backend auto "
        "picks for the octree ray caster on this GL renderer (compute on hardware GPUs, fragment on "
        "software rasterizers), so that the two are compared in the same stage. --stats names it "
        "(stage)")
        ->default_str("auto");
  addEnumOption(
      app, "--gradients", o.gradients, kGradientNames,
      "DVR gradients: stored (derived at upload, one lookup per sample, 8 more bytes per pool texel) "
      "or computed (six more lookups per sample)");
  app.add_option("--step", o.step, "sample distance in voxels of the level crossed")
      ->check(finiteIn(0.01, 8.0))
      ->capture_default_str();
  // At 0 every ray would end before its first sample.
  app.add_option("--ert", o.ert, "early ray termination: a ray ends when its opacity reaches this (DVR)")
      ->check(finiteAbove(0.0, 1.0))
      ->capture_default_str();
  app.add_option("--voxels-per-pixel", o.voxelsPerPixel, "refinement target: voxels per pixel")
      ->check(finiteIn(0.01, 64.0))
      ->capture_default_str();
  addByteSizeOption(app, "--gpu-budget", o.gpuBudget,
                    "GPU brick pool bytes, allocated at start (e.g. 512M; default: half the GPU memory the "
                    "driver reports, at most 4G, or 512M if it reports none)")
      ->check(nonZeroSize("leave --gpu-budget out for the driver's default"));
  addByteSizeOption(app, "--cpu-cache", o.cpuCache, "CPU brick cache bytes")->default_str("1G");
  addByteSizeOption(app, "--upload-budget", o.uploadBudget,
                    "brick upload bytes per progressive frame (default: unlimited; a synchronous frame "
                    "uploads its whole view)");
  app.add_option(
         "--upload-time-budget", o.uploadTimeBudgetMs,
         "brick upload milliseconds per progressive frame, from the measured throughput (default: none)")
      ->check(finiteIn(0.0, 100000.0));
  app.add_flag("--upload-pbo", o.uploadPbo, "upload bricks through a pixel buffer object");
  app.add_option(
         "--target-frame-ms", o.targetFrameMs,
         "progressive frames: sample at up to 4x --step while a frame takes longer than this (render: "
         "the written images too; view: while the camera moves; default: off)")
      ->check(finiteIn(0.0, 100000.0));
  app.add_option("--io-delay-ms", o.ioDelayMs, "added latency per brick read (shows asynchrony)")
      ->check(finiteIn(0.0, 10000.0));
  app.add_option("--io-threads", o.ioThreads,
                 "threads that read and decompress bricks (default: " + std::to_string(defaultIoThreads()) +
                     " on this machine; " + std::string(kDefaultIoThreadsRule) + ")")
      ->transform(integerRange(1, kMaxIoThreads));
  addEnumOption(app, "--occlusion", o.occlusion, kOnOffNames,
                "progressive frames: occlusion queries between screen tiles keep hidden nodes from refining");
  addEnumOption(app, "--feedback", o.feedback, kOnOffNames,
                "progressive frames: the rays report the bricks they used and where they wanted finer data; "
                "requested nodes and the tree in use refine first, nodes no ray sampled do not refine, used "
                "bricks stay in the pool");
  app.add_option("--query-budget", o.queryBudget, "occlusion queries per frame")
      ->transform(integerRange(1, 1000000))
      ->capture_default_str();
  app.add_option("--visibility-threshold", o.visibilityThreshold,
                 "visible pixels below which a queried node counts as occluded")
      ->transform(integerRange(0, 4294967295.0))
      ->capture_default_str();
  app.add_option("--brick", o.brick, "brick size for procedural inputs and volumes")
      ->check(oneOf(std::vector<uint32_t>{8, 16, 32, 64}));
  addVolumeReadOptions(app, o.read);
}

namespace {

void checkBrickOption(const std::string& input, std::optional<uint32_t> brick) {
  if (brick && isStoreInput(input))
    throw UsageError("--brick " + std::to_string(*brick) +
                     " applies to procedural inputs and volumes; the store " + input +
                     " has the brick size it was converted with");
}

// The camera of --eye and --target (and --up), or none with an orbit.
std::optional<Camera> eyeTargetCamera(const RenderOptions& o) {
  if (o.eye.empty() && o.target.empty()) return std::nullopt;
  if (o.eye.empty() || o.target.empty()) throw UsageError("--eye and --target go together");
  Camera c;
  c.eye = toVec3(o.eye);
  c.target = toVec3(o.target);
  c.fovYDeg = o.fov;
  c.up = o.up.empty() ? defaultUp(c.target - c.eye) : toVec3(o.up);
  if (const std::string problem = cameraProblem(c); !problem.empty())
    throw UsageError("--eye " + formatTriple(o.eye) + " --target " + formatTriple(o.target) +
                     (o.up.empty() ? "" : " --up " + formatTriple(o.up)) + ": " + problem);
  return c;
}

}  // namespace

glm::dvec3 orbitFor(const RenderOptions& o, const VolumeInfo& volume) {
  const double* fallback = volume.patientFrame ? kPatientDefaultOrbit : kDefaultOrbit;
  const glm::dvec3 orbit =
      o.orbit.empty() ? glm::dvec3(fallback[0], fallback[1], fallback[2]) : toVec3(o.orbit);
  if (orbit.z <= 0.0)
    throw UsageError("--orbit: the distance must be positive, got " + formatTriple(o.orbit));
  return orbit;
}

void checkSceneOptions(const RenderOptions& o) {
  checkBrickOption(o.input, o.brick);
  checkTfRange(o.tfRange);
  if (!o.material.empty())
    if (const std::string problem = materialProblem("--material", o.material); !problem.empty())
      throw UsageError(problem);
  if (o.bruteStage && o.backend != RenderBackend::Brute)
    throw UsageError("--brute-stage " + std::string(renderBackendName(*o.bruteStage)) +
                     " applies to --backend brute; the octree ray caster's stage is --backend fragment or "
                     "compute");
  if (!eyeTargetCamera(o)) orbitFor(o, VolumeInfo{});
  // Only frames that query: progressive ones of the octree's single pass (not one synchronous frame,
  // --reference, brute force or multi-pass).
  const bool queries = o.occlusion && (o.converge || o.frames > 1) && !o.reference &&
                       o.backend != RenderBackend::Brute && o.backend != RenderBackend::Multipass;
  if (const uint64_t pixels = uint64_t(o.size.at(0)) * o.size.at(1);
      queries && o.visibilityThreshold > pixels)
    throw UsageError("--visibility-threshold " + std::to_string(o.visibilityThreshold) +
                     " is more than the " + std::to_string(pixels) + " pixels of the image (--size " +
                     std::to_string(o.size.at(0)) + "x" + std::to_string(o.size.at(1)) +
                     "): every node would count as occluded; give a smaller --visibility-threshold, or "
                     "--occlusion off");
}

void warnIfPoolLimited(const RenderOptions& o, const FrameStats& last, const char* who) {
  if (last.leavesPoolFull == 0) return;
  std::fprintf(
      stderr,
      "%sropecast %s: warning: %llu leaves stay coarser than --voxels-per-pixel %g asks: the GPU pool has no "
      "room for their children beside the %llu bricks it holds (%.1f MiB); raise --gpu-budget for the full "
      "detail of this view\n",
      o.messagePrefix.c_str(), who, static_cast<unsigned long long>(last.leavesPoolFull), o.voxelsPerPixel,
      static_cast<unsigned long long>(last.bricksResident), mebibytes(last.gpuPoolUsedBytes));
}

std::unique_ptr<BrickSource> openBrickSource(const std::string& input, std::optional<uint32_t> brick,
                                             const VolumeReadArgs& read, bool quiet, const std::string& who,
                                             VolumeInfo* volume) {
  if (isProceduralSpec(input)) {
    refuseVolumeReadOptions(read, input + " is generated");
    return openProceduralBricks(input, brick.value_or(kDefaultBrickSize));
  }
  if (input.empty())
    throw UsageError("the input: expected a store file (.rcast), a volume or procedural:NAME:SIZE, got ''");
  if (isStoreInput(input)) {
    checkBrickOption(input, brick);
    refuseVolumeReadOptions(read, "the store " + input + " keeps what it was converted with");
    if (!std::filesystem::exists(input)) throw Error(input + ": no such store file");
    return Store::open(input);
  }
  ConversionReport report;
  report.quiet = quiet;
  return openVolumeAsStore(input, sourceOptionsOf(read, who), brick, report, who, volume);
}

std::unique_ptr<BrickSource> openBrickSource(const RenderOptions& o, const std::string& who,
                                             VolumeInfo* volume) {
  return openBrickSource(o.input, o.brick, o.read, o.quiet, who, volume);
}

Camera chooseCamera(const RenderOptions& o, const BrickSourceInfo& info) {
  if (const std::optional<Camera> camera = eyeTargetCamera(o)) return *camera;
  if (o.view)
    return anatomicalViewCamera(*o.view, kDefaultOrbit[2], glm::dvec3(0.0), info.volume.worldMax(), o.fov);
  const glm::dvec3 orbit = orbitFor(o, info.volume);
  return orbitCamera(orbit.x, orbit.y, orbit.z, glm::dvec3(0.0), info.volume.worldMax(), o.fov);
}

std::pair<double, double> valueRangeOf(const BrickSourceInfo& info) {
  const uint32_t storedMax = storedMaxOf(info.storedType);
  return {info.volume.valueMin.value_or(info.mapping.toData(0)),
          info.volume.valueMax.value_or(info.mapping.toData(storedMax))};
}

CropBox cropBoxOf(const std::vector<std::string>& ranges, const BrickSourceInfo& info) {
  if (ranges.empty()) return {};
  const VoxelBox box = voxelBoxOf("--crop", ranges, info.volume.dims);
  return fileCropOf({glm::dvec3(box.begin), glm::dvec3(box.end)}, info);
}

CropBox fileCropOf(const CropBox& crop, const BrickSourceInfo& info) {
  if (!info.xReversed || crop == CropBox{}) return crop;
  const double n = info.volume.dims.x;
  CropBox mirrored = crop;
  mirrored.lo.x = std::max(0.0, n - std::min(crop.hi.x, n));
  mirrored.hi.x = n - crop.lo.x;
  return mirrored;
}

ClipPlane clipPlaneOf(const std::vector<double>& values) {
  if (values.empty()) return {};
  if (values.size() != 6) throw UsageError("--clip-plane: expected six numbers X,Y,Z,NX,NY,NZ");
  // The shaders take the plane in single precision: a point farther out would make its offset overflow.
  constexpr double kLargest = 1e15;
  for (double v : values)
    if (!(std::abs(v) <= kLargest))
      throw UsageError("--clip-plane: expected six numbers within +-1e15, got " +
                       formatTriple({values[0], values[1], values[2]}) + "," +
                       formatTriple({values[3], values[4], values[5]}));
  const glm::dvec3 point(values[0], values[1], values[2]), normal(values[3], values[4], values[5]);
  const double length = glm::length(normal);
  if (!(length > 0.0) || !std::isfinite(length))
    throw UsageError("--clip-plane: the normal " + formatTriple({values[3], values[4], values[5]}) +
                     " has no direction; give the direction of the side to draw, e.g. 0,0,1");
  return {point, normal / length};
}

void setMaterial(LightingParams& lighting, const std::vector<double>& material) {
  lighting.ambient = material.at(0);
  lighting.diffuse = material.at(1);
  lighting.specular = material.at(2);
  lighting.shininess = material.at(3);
}

namespace {
// The plane of --slice AXIS:INDEX, checked against the volume's voxels and the crop box `params` draw.
ClipPlane slicePlaneOf(const std::string& slice, const RenderParams& params, const VolumeInfo& volume) {
  const size_t colon = slice.find(':');
  const std::string axisName = colon == std::string::npos ? "" : slice.substr(0, colon);
  const int axis = axisName == "x" ? 0 : axisName == "y" ? 1 : axisName == "z" ? 2 : -1;
  const std::optional<uint32_t> index =
      colon == std::string::npos ? std::nullopt : parseWholeNumber<uint32_t>(slice.substr(colon + 1));
  if (axis < 0 || !index)
    throw UsageError("--slice " + slice +
                     ": expected AXIS:INDEX, AXIS x, y or z and INDEX a voxel counted from 0, e.g. z:100");
  const uint32_t voxels = volume.dims[axis];
  if (*index >= voxels)
    throw UsageError("--slice " + slice + ": the volume has " + std::to_string(voxels) + " voxels along " +
                     axisName + ", 0 to " + std::to_string(voxels - 1));
  if (!(double(*index) >= params.crop.lo[axis] && double(*index) < params.crop.hi[axis]))
    throw UsageError("--slice " + slice + " lies outside --crop, which keeps voxels " +
                     formatNumber(params.crop.lo[axis]) + " to " +
                     formatNumber(std::min(params.crop.hi[axis], double(voxels)) - 1.0) + " along " +
                     axisName);
  return voxelSlicePlane(params, axis, *index, volume.dims, volume.spacing, volume.axes);
}
}  // namespace

RenderParams renderParamsOf(const RenderOptions& o, const BrickSourceInfo& info, const char* command) {
  const auto [lo, hi] = valueRangeOf(info);
  RenderParams params;
  params.mode = o.mode;
  params.isoValue = o.iso.value_or(0.5 * (lo + hi));
  params.stepVoxels = o.step;
  params.ert = o.ert;
  params.background = toVec3(o.background);
  params.backend = o.backend;
  params.gradients = o.gradients;
  params.crop = cropBoxOf(o.crop, info);
  params.clipPlane = clipPlaneOf(o.clipPlane);
  if (!o.slice.empty()) {
    if (!o.clipPlane.empty())
      throw UsageError("--slice and --clip-plane both give the slice's plane: give one");
    if (params.mode != RenderMode::Slice && !(o.slab > 0.0))
      throw UsageError("--slice " + o.slice + " shows a slice, and --mode " +
                       std::string(renderModeName(params.mode)) +
                       " draws something else: leave --mode out, give --mode slice, or add --slab T for the "
                       "slab about it");
    params.clipPlane = slicePlaneOf(o.slice, params, info.volume);
  }
  if (o.slab > 0.0) {
    if (params.mode == RenderMode::Slice)
      throw UsageError("--slab " + formatNumber(o.slab) +
                       ": a slice has no thickness; for a slab's projection give --mode mip, minip or aip");
    if (!params.clipPlane.enabled())
      throw UsageError("--slab " + formatNumber(o.slab) + " is about a plane: give --clip-plane or --slice");
    params.clipPlane.slab = o.slab;
  }
  if (params.mode == RenderMode::Slice && !params.clipPlane.enabled())
    params.clipPlane = defaultSlicePlane(params, info.volume);
  params.isoCaps = o.caps;
  if (!o.isoColor.empty()) params.lighting.isoBaseColor = toVec3(o.isoColor);
  if (!o.material.empty()) setMaterial(params.lighting, o.material);
  params.lighting.dvrShading = o.shading;
  if (params.mode == RenderMode::Iso && !(params.isoValue >= lo && params.isoValue <= hi))
    std::fprintf(stderr,
                 "%sropecast %s: warning: --iso %g lies outside the volume's value range [%g, %g]: the "
                 "isosurface is empty\n",
                 o.messagePrefix.c_str(), command, params.isoValue, lo, hi);
  return params;
}

std::string tfOptionHelp(const std::string& defaultText) {
  std::string presets;
  for (const std::string& name : TransferFunction::presetNames())
    presets += (presets.empty() ? "" : ", ") + name;
  return "transfer function: a preset (" + presets + ") or a JSON file (default: " + defaultText + ")";
}

std::string defaultTfSpec(RenderMode mode) {
  return std::string(mode == RenderMode::Slice ? TransferFunction::kSliceDefaultPreset
                     : showsOneValue(mode)     ? TransferFunction::kMipDefaultPreset
                                               : TransferFunction::kDefaultPreset);
}

void checkTfRange(const std::vector<double>& tfRange) {
  if (tfRange.size() == 2 && !(tfRange[0] < tfRange[1]))
    throw UsageError("--tf-range " + formatNumber(tfRange[0]) + "," + formatNumber(tfRange[1]) +
                     ": expected LO,HI with LO < HI (data units)");
}

TransferFunction windowed(const TransferFunction& function, const std::vector<double>& tfRange) {
  return tfRange.size() == 2 ? function.stretchedOver(tfRange[0], tfRange[1]) : function;
}

TransferFunction transferFunctionOf(const std::string& spec, const BrickSourceInfo& info, RenderMode mode,
                                    const std::vector<double>& tfRange) {
  return windowed(TransferFunction::fromSpec(spec.empty() ? defaultTfSpec(mode) : spec, tfDataRangeFor(info)),
                  tfRange);
}

TfTable bakeFor(const TransferFunction& function, const BrickSourceInfo& info) {
  return TfTable::bake(function, info.mapping, storedMaxOf(info.storedType));
}

FrameRendererConfig frameRendererConfigOf(const RenderOptions& o, const RenderParams& params) {
  FrameRendererConfig config;
  config.gpuBudgetBytes = o.gpuBudget;
  config.cpuCacheBytes = o.cpuCache;
  config.uploadBudgetBytes = o.uploadBudget;
  config.uploadTimeBudgetMs = o.uploadTimeBudgetMs;
  config.storedGradients = usesStoredGradients(params);
  config.uploadThroughPbo = o.uploadPbo;
  if (o.ioThreads > 0) config.ioThreads = o.ioThreads;
  config.occlusion = o.occlusion;
  config.feedback = o.feedback;
  config.visibility.tiles.queryBudget = o.queryBudget;
  config.visibility.thresholdPixels = o.visibilityThreshold;
  return config;
}

}  // namespace ropecast::tools
