// `ropecast extract STORE --level L [--crop X0:X1,Y0:Y1,Z0:Z1] -o OUT.raw|OUT.nrrd|OUT.nii`: one resolution
// level, or a box of it, as a raw volume in the original type, plain or after a NRRD or NIfTI-1 header
// (store/extract.h). Main thread.
#include <cstdio>
#include <memory>

#include <glm/common.hpp>

#include "core/file_names.h"
#include "store/extract.h"
#include "store/store.h"
#include "store/store_writer.h"
#include "tools/cli_checks.h"
#include "tools/cli_values.h"
#include "tools/command.h"
#include "tools/output_guard.h"

namespace ropecast::tools {
namespace {

struct ExtractArgs {
  std::string store, output;
  uint32_t level = 0;
  std::vector<std::string> crop;  // --crop: three voxel ranges of the level; empty: all of it
  bool quiet = false;
};

int runExtract(const ExtractArgs& a) {
  // A compressed name would hold uncompressed bytes that its readers take for garbage.
  if (hasExtension(a.output, ".gz") || hasExtension(a.output, ".bz2") || hasExtension(a.output, ".zst"))
    throw UsageError(
        "extract: -o " + a.output +
        ": extract writes uncompressed files: name it .raw, .nrrd or .nii (compress it afterwards)");
  OutputGuard guard("extract");
  guard.addInput("the store", a.store);
  guard.addOutput("-o", a.output);
  guard.check();
  removeTemporaryFilesOnSignals();  // an interrupted run leaves no temporary behind
  const auto store = Store::open(a.store);
  LevelRegion region;
  if (!a.crop.empty()) {
    const VoxelBox box =
        voxelBoxOf("--crop", a.crop, levelDimsOf(*store, a.level), "level " + std::to_string(a.level) + "'s");
    region = {box.begin, box.end};
  }
  // A .nrrd or .nii output says what it holds: its type and size, and where it lies (spacing, axes, origin).
  const bool nrrd = hasExtension(a.output, ".nrrd"), nifti = hasExtension(a.output, ".nii");
  const std::string header = nrrd    ? nrrdHeaderOf(*store, a.level, region)
                             : nifti ? niftiHeaderOf(*store, a.level, region)
                                     : "";
  extractLevelToFile(*store, a.level, a.output, region, header);
  if (!a.quiet) {
    const glm::u32vec3 d = glm::min(region.end, levelDimsOf(*store, a.level)) - region.begin;
    std::printf("wrote %s: level %u, %ux%ux%u %s, x fastest, little-endian%s\n", a.output.c_str(), a.level,
                d.x, d.y, d.z, std::string(sampleTypeName(store->info().volume.type)).c_str(),
                nrrd    ? ", after a NRRD header"
                : nifti ? ", after a NIfTI-1 header"
                        : "");
  }
  return 0;
}

const CommandRegistration extractCommand("extract", 40, [](CLI::App& app) -> std::function<int()> {
  app.description("write one resolution level of a store as a raw volume in its original type");
  auto a = std::make_shared<ExtractArgs>();
  app.add_option("store", a->store, "store file")->required();
  app.add_option("--level", a->level, "resolution level (0 = full, L has ceil(n / 2^L) samples per axis)")
      ->capture_default_str();
  app.add_option(
         "-o,--output", a->output,
         "raw file to write; a .nrrd or .nii name writes a NRRD or NIfTI-1 file (the raw samples after a "
         "header that says their type, size, spacing, axes and where they lie)")
      ->required()
      ->check(nonEmptyPath("a file"));
  addVoxelRangesOption(
      app, "--crop", a->crop,
      "write only the voxels X0..X1-1, Y0..Y1-1, Z0..Z1-1 of the level: X0:X1,Y0:Y1,Z0:Z1, as "
      "Python slices (X0: or :X1 to the level's edge, : the whole axis); only the bricks that "
      "hold them are read (default: the whole level)");
  app.add_flag("-q,--quiet", a->quiet, "no summary");
  return [a] { return runExtract(*a); };
});

}  // namespace
}  // namespace ropecast::tools
