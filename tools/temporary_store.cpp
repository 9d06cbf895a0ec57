#include "tools/temporary_store.h"

#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <filesystem>

#include "core/error.h"
#include "store/converter.h"
#include "store/volume_source.h"
#include "tools/convert_progress.h"

namespace ropecast::tools {

std::unique_ptr<Store> openVolumeAsStore(const std::string& input, const SourceOptions& sourceOptions,
                                         std::optional<uint32_t> brick, const ConversionReport& report,
                                         const std::string& who, VolumeInfo* volume) {
  const std::unique_ptr<VolumeSource> source = openVolumeSource(input, sourceOptions);
  if (volume) *volume = source->info();
  if (report.notes)
    for (const std::string& note : source->info().notes)
      std::fprintf(stderr, "ropecast %s: warning: %s\n", who.c_str(), note.c_str());
  ConvertOptions options;
  options.brickSize = brick.value_or(kDefaultBrickSize);
  options.creationTool = "ropecast " + who;
  if (const std::string problem = convertOptionsProblem(options); !problem.empty()) throw UsageError(problem);

  static std::atomic<uint32_t> made{0};
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("ropecast-" + std::to_string(::getpid()) + "-" + std::to_string(made++) + ".rcast");
  if (!report.quiet)
    std::fprintf(
        stderr,
        "ropecast %s: %s is a volume: converting it to a temporary store (`ropecast convert` makes one "
        "to keep)\n",
        who.c_str(), input.c_str());
  ConvertProgressBars progress(report.quiet || report.progress);
  bool scanned = false;  // the range pass, where there is one, reads the volume once more: the first half
  options.progress = [&](const ConvertProgress& p) {
    if (!report.progress) return progress.update(p);
    const double done = p.bytesTotal ? double(p.bytesDone) / double(p.bytesTotal) : 1.0;
    if (p.phase == ConvertProgress::Phase::ValueRange) scanned = true;
    report.progress(p.phase == ConvertProgress::Phase::ValueRange ? 0.5 * done
                    : scanned                                     ? 0.5 + 0.5 * done
                                                                  : done);
  };
  convertVolume(*source, path, options);
  progress.finish();
  std::unique_ptr<Store> store;
  try {
    store = Store::open(path);
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(path, ec);
    throw;
  }
  std::error_code ec;
  std::filesystem::remove(path, ec);  // the open store keeps its bytes to the end of the process
  return store;
}

}  // namespace ropecast::tools
