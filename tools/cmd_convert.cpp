// `ropecast convert INPUT -o OUT [options]`: builds an octree store from any volume source
// (store/converter.h). Main thread; the converter starts its own compression workers.
#include <cstdio>
#include <memory>
#include <optional>

#include "core/error.h"
#include "core/sample_type.h"
#include "store/converter.h"
#include "store/cropped_source.h"
#include "store/store_writer.h"
#include "store/volume_source.h"
#include "tools/cli_checks.h"
#include "tools/cli_values.h"
#include "tools/command.h"
#include "tools/convert_progress.h"
#include "tools/output_guard.h"
#include "tools/progress_bar.h"
#include "tools/volume_read_options.h"

namespace ropecast::tools {
namespace {

struct ConvertArgs {
  std::string input, output;
  VolumeReadArgs read;
  std::vector<std::string> crop;  // --crop: three voxel ranges; empty: the whole volume
  uint32_t brick = kDefaultBrickSize;
  std::optional<double> discardBelow;
  int zstdLevel = 3;
  unsigned threads = 0;
  bool quiet = false;
};

int runConvert(const ConvertArgs& a) {
  const SourceOptions sourceOptions = sourceOptionsOf(a.read, "convert");
  ConvertOptions options;
  options.brickSize = a.brick;
  options.discardBelow = a.discardBelow;
  options.zstdLevel = a.zstdLevel;
  options.workerThreads = a.threads;
  if (const std::string problem = convertOptionsProblem(options); !problem.empty()) throw UsageError(problem);
  OutputGuard guard("convert");
  guard.addVolumeInput("the input", a.input);
  guard.addOutput("-o", a.output);
  guard.check();
  removeTemporaryFilesOnSignals();  // an interrupted run leaves no temporary behind
  std::unique_ptr<VolumeSource> source = openVolumeSource(a.input, sourceOptions);
  if (!a.crop.empty()) {
    const VoxelBox box = voxelBoxOf("--crop", a.crop, source->info().dims);
    source = cropVolumeSource(std::move(source), box.begin, box.end);
  }
  for (const std::string& note : source->info().notes)  // said even with -q: the store keeps what was read
    std::fprintf(stderr, "ropecast convert: warning: %s\n", note.c_str());

  ConvertProgressBars progress(a.quiet);
  options.progress = [&progress](const ConvertProgress& p) { progress.update(p); };
  const ConvertStats stats = convertVolume(*source, a.output, options);
  progress.finish();
  if (a.discardBelow && stats.emptyNodes == stats.nodes)  // said even with -q: the store shows nothing
    std::fprintf(stderr,
                 "ropecast convert: warning: every sample lies below --discard-below %s: %s holds no data\n",
                 formatNumber(*a.discardBelow).c_str(), a.output.c_str());
  // Said even with -q: the store holds values the source did not have there.
  const auto warnSamples = [](uint64_t count, const std::string& what, const std::string& storedAs) {
    if (count > 0)
      std::fprintf(stderr, "ropecast convert: warning: %llu %s %s; stored as %s\n", (unsigned long long)count,
                   count == 1 ? "sample is" : "samples are", what.c_str(), storedAs.c_str());
  };
  const std::string range = "[" + formatNumber(stats.valueMin) + ", " + formatNumber(stats.valueMax) + "]";
  warnSamples(stats.nanSamples, "NaN", "the value range's low end, " + formatNumber(stats.valueMin));
  warnSamples(stats.infiniteSamples, "infinite", "the nearer end of the value range " + range);
  warnSamples(stats.clampedSamples, "outside the value range the source gives, " + range, "the nearer end");
  if (!a.quiet) {
    const VolumeInfo& info = source->info();
    const double rawBytes = double(info.sampleCount()) * double(bytesPerSample(info.type));
    std::printf(
        "wrote %s: %ux%ux%u %s, %llu nodes (%llu with data, %llu constant, %llu empty), %s of "
        "bricks = %.3f of the raw size\n",
        a.output.c_str(), info.dims.x, info.dims.y, info.dims.z,
        std::string(sampleTypeName(info.type)).c_str(), (unsigned long long)stats.nodes,
        (unsigned long long)stats.dataNodes, (unsigned long long)stats.constantNodes,
        (unsigned long long)stats.emptyNodes, formatBytes(stats.payloadBytes).c_str(),
        double(stats.payloadBytes) / rawBytes);
    // Where a file turns its axes, say so: it changes what the default view shows, and a mirroring volume's
    // store holds x reversed (store/converter.h).
    if (info.axes != AxisDirections(1.0))
      std::printf("axes %s%s\n", orientationCode(info.axes).c_str(),
                  mirrors(info.axes) ? " (mirroring: the store keeps x reversed)" : "");
  }
  return 0;
}

const CommandRegistration convertCommand("convert", 10, [](CLI::App& app) -> std::function<int()> {
  app.description(
      "build an octree store from a volume (raw, NRRD, MetaImage, NIfTI, VTK, image stack, DICOM series, "
      "HDF5, Zarr, N5, procedural:NAME:SIZE)");
  auto a = std::make_shared<ConvertArgs>();
  app.add_option("input", a->input,
                 "volume: file.raw (name_XxYxZ_type.raw or --dims/--type), .nrrd/.nhdr, .mha/.mhd, "
                 ".nii/.nii.gz/.hdr, .vti, legacy .vtk, "
                 "directory or glob of slices, multi-page TIFF, DICOM folder or image, HDF5 file (.h5, .ims, "
                 "...; FILE:/DATASET names a dataset), Zarr array or OME-Zarr image folder, N5 dataset or "
                 "multiscale group folder, procedural:NAME:SIZE")
      ->required();
  app.add_option("-o,--output", a->output, "the store file to write")
      ->required()
      ->check(nonEmptyPath("a file"));
  app.add_option("--brick", a->brick, "brick edge in samples (power of two in [4, 256])")
      ->capture_default_str();
  app.add_option("--discard-below", a->discardBelow, "mark nodes whose max is below V (data units) empty")
      ->check(finiteIn(-HUGE_VAL, HUGE_VAL));
  addVoxelRangesOption(
      app, "--crop", a->crop,
      "convert only the voxels X0..X1-1, Y0..Y1-1, Z0..Z1-1 of the input: X0:X1,Y0:Y1,Z0:Z1, as "
      "Python slices (X0: or :X1 to the volume's edge, : the whole axis), as render --crop "
      "takes them (default: the whole volume)");
  addVolumeReadOptions(app, a->read);
  app.add_option("--zstd-level", a->zstdLevel, "zstd compression level")->capture_default_str();
  app.add_option("--threads", a->threads, "compression threads (0: one per core), at most 1024")
      ->capture_default_str()
      ->transform(integerRange(0, 1024));
  app.add_flag("-q,--quiet", a->quiet, "no progress bar and no summary");
  return [a] { return runConvert(*a); };
});

}  // namespace
}  // namespace ropecast::tools
