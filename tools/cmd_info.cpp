// `ropecast info INPUT [--json]`: what a store holds (store/store.h summarizeStore), or what `convert` would
// read of a volume (its VolumeInfo: size, type, spacing, which file or dataset, notes), without reading its
// samples. Main thread.
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "store/store.h"
#include "store/store_writer.h"
#include "store/volume_source.h"
#include "tools/command.h"
#include "tools/progress_bar.h"
#include "tools/volume_read_options.h"

namespace ropecast::tools {
namespace {

double ratio(uint64_t a, uint64_t b) {
  return b > 0 ? double(a) / double(b) : 0.0;
}

// "stored", "stored - 32768", "stored * 0.6824 - 5000": the mapping as a person reads it.
std::string mappingFormula(const ValueMapping& m) {
  char text[96];
  const char* sign = m.offset < 0 ? "-" : "+";
  if (m.scale == 1.0) {
    if (m.offset == 0.0) return "stored";
    std::snprintf(text, sizeof text, "stored %s %g", sign, std::abs(m.offset));
  } else if (m.offset == 0.0) {
    std::snprintf(text, sizeof text, "stored * %g", m.scale);
  } else {
    std::snprintf(text, sizeof text, "stored * %g %s %g", m.scale, sign, std::abs(m.offset));
  }
  return text;
}

// Where the axes point, as a person reads it: "LPS", "LPS (oblique)", and for a volume whose axes mirror,
// what its store will hold.
std::string axesText(const AxisDirections& axes) {
  std::string text = orientationCode(axes);
  if (mirrors(axes)) {
    AxisDirections stored = axes;
    stored[0] = -axes[0];
    text += ", mirroring: a store keeps x reversed, as " + orientationCode(stored);
  }
  return text;
}

nlohmann::json axesJson(const AxisDirections& a) {
  return {{a[0].x, a[0].y, a[0].z}, {a[1].x, a[1].y, a[1].z}, {a[2].x, a[2].y, a[2].z}};
}

// The lines that place the volume, a store's or a file's: its size, spacing and axes.
void printPlacement(const VolumeInfo& v) {
  std::printf("dims       %u x %u x %u samples, spacing %g x %g x %g\n", v.dims.x, v.dims.y, v.dims.z,
              v.spacing.x, v.spacing.y, v.spacing.z);
  std::printf("axes       %s\n", axesText(v.axes).c_str());
  if (v.patientFrame) std::printf("frame      a patient's (LPS): the default view faces the patient\n");
  if (v.origin)
    std::printf("origin     %g, %g, %g (the center of voxel 0, 0, 0, in the axes' frame)\n", v.origin->x,
                v.origin->y, v.origin->z);
}

// File names need not be UTF-8: bytes that are not become U+FFFD, as in the store's metadata.
void printJson(const nlohmann::json& j) {
  std::printf("%s\n", j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace).c_str());
}

// A volume input: what openVolumeSource makes of it.
int runVolumeInfo(const std::string& spec, const SourceOptions& options, bool json) {
  const std::unique_ptr<VolumeSource> source = openVolumeSource(spec, options);
  const VolumeInfo& v = source->info();
  const uint64_t rawBytes = v.sampleCount() * bytesPerSample(v.type);
  if (json) {
    nlohmann::json j = {{"input", spec},
                        {"kind", "volume"},
                        {"dims", {v.dims.x, v.dims.y, v.dims.z}},
                        {"spacing", {v.spacing.x, v.spacing.y, v.spacing.z}},
                        {"axes", axesJson(v.axes)},
                        {"origin", v.origin ? nlohmann::json{v.origin->x, v.origin->y, v.origin->z}
                                            : nlohmann::json(nullptr)},
                        {"orientation", orientationCode(v.axes)},
                        {"patientFrame", v.patientFrame},
                        {"type", std::string(sampleTypeName(v.type))},
                        {"source", v.description},
                        {"notes", v.notes},
                        {"timePoints", v.timePoints},
                        {"timePoint", v.timePoint},
                        {"channels", v.channels},
                        {"channel", v.channel},
                        {"rawBytes", rawBytes}};
    if (v.valueMin) j["valueMin"] = *v.valueMin;
    if (v.valueMax) j["valueMax"] = *v.valueMax;
    printJson(j);
    return 0;
  }
  std::printf("volume     %s (not a store: `ropecast convert` makes one of it)\n", spec.c_str());
  printPlacement(v);
  std::printf("type       %s\n", std::string(sampleTypeName(v.type)).c_str());
  if (v.valueMin && v.valueMax) std::printf("values     [%g, %g]\n", *v.valueMin, *v.valueMax);
  std::printf("source     %s\n", v.description.c_str());
  std::printf("size       raw volume %.2f MiB\n", mebibytes(rawBytes));
  for (const std::string& note : v.notes) std::printf("note       %s\n", note.c_str());
  return 0;
}

int runInfo(const std::string& path, const VolumeReadArgs& read, bool json) {
  if (!isStoreInput(path)) return runVolumeInfo(path, sourceOptionsOf(read, "info"), json);
  refuseVolumeReadOptions(read, "the store " + path + " keeps what it was converted with");
  const auto store = Store::open(path);
  const StoreMetadata& m = store->metadata();
  const StoreSummary s = summarizeStore(*store);
  const VolumeInfo& v = m.volume;
  if (json) {
    nlohmann::json levels = nlohmann::json::array();
    for (const auto& l : s.levels)
      levels.push_back({{"level", l.level},
                        {"depth", l.depth},
                        {"dims", {l.dims.x, l.dims.y, l.dims.z}},
                        {"nodesPerAxis", {l.nodes.x, l.nodes.y, l.nodes.z}},
                        {"nodes", l.total},
                        {"empty", l.empty},
                        {"constant", l.constant},
                        {"data", l.data},
                        {"payloadBytes", l.payloadBytes}});
    nlohmann::json j = nlohmann::json::parse(storeMetadataToJson(m));
    j["file"] = path;
    j["orientation"] = orientationCode(v.axes);
    j["patientFrame"] = v.patientFrame;
    j["nodes"] = {{"total", s.total}, {"empty", s.empty}, {"constant", s.constant}, {"data", s.data}};
    j["levelsDetail"] = levels;
    j["bytes"] = {{"file", s.fileBytes},
                  {"payload", s.payloadBytes},
                  {"payloadUncompressed", s.uncompressedBytes},
                  {"allBricksUncompressed", s.allBricksBytes},
                  {"raw", s.rawBytes}};
    j["compressionRatio"] = ratio(s.uncompressedBytes, s.payloadBytes);
    j["fileToRawRatio"] = ratio(s.fileBytes, s.rawBytes);
    printJson(j);
    return 0;
  }
  std::printf("store      %s\n", path.c_str());
  // The file's voxel 0, 0, 0, as the other voxel indices: a store that keeps x reversed has it at its far x.
  VolumeInfo placed = v;
  if (m.xReversed && v.origin) placed.origin = originAtLastX(v);
  printPlacement(placed);
  if (m.xReversed) {
    AxisDirections file = v.axes;
    file[0] = -v.axes[0];
    std::printf(
        "           x kept reversed: its file's axes mirror (%s); voxel indices (--crop, extract, the "
        "viewer's "
        "probe) are the file's\n",
        orientationCode(file).c_str());
  }
  std::printf("type       %s (stored as %s, data = %s)\n", std::string(sampleTypeName(v.type)).c_str(),
              std::string(sampleTypeName(m.storedType)).c_str(), mappingFormula(m.mapping).c_str());
  std::printf("values     [%g, %g]%s\n", v.valueMin.value_or(0), v.valueMax.value_or(0),
              m.discardBelow ? (", discarded below " + std::to_string(*m.discardBelow)).c_str() : "");
  std::printf("bricks     %u^3 + border %u, %u levels, zstd level %d\n", m.brickSize, m.border, m.levels,
              m.zstdLevel);
  std::printf("source     %s (by %s)\n", v.description.c_str(), m.creationTool.c_str());
  std::printf("nodes      %llu total: %llu with data, %llu constant, %llu empty\n",
              (unsigned long long)s.total, (unsigned long long)s.data, (unsigned long long)s.constant,
              (unsigned long long)s.empty);
  std::printf("  level depth        dims         nodes    data  constant   empty   payload MiB\n");
  for (const auto& l : s.levels)
    std::printf("  %5u %5u %5ux%5ux%5u %8llu %7llu %9llu %7llu %13.2f\n", l.level, l.depth, l.dims.x,
                l.dims.y, l.dims.z, (unsigned long long)l.total, (unsigned long long)l.data,
                (unsigned long long)l.constant, (unsigned long long)l.empty, mebibytes(l.payloadBytes));
  std::printf(
      "size       file %.2f MiB; payload %.2f MiB compressed from %.2f MiB (ratio %.2f); raw volume %.2f MiB "
      "(file/raw %.3f)\n",
      mebibytes(s.fileBytes), mebibytes(s.payloadBytes), mebibytes(s.uncompressedBytes),
      ratio(s.uncompressedBytes, s.payloadBytes), mebibytes(s.rawBytes), ratio(s.fileBytes, s.rawBytes));
  return 0;
}

const CommandRegistration infoCommand("info", 20, [](CLI::App& app) -> std::function<int()> {
  app.description(
      "print what a store holds: dims, type, value range, levels, node counts, sizes; or what convert reads "
      "of a "
      "volume");
  auto path = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  app.add_option("input", *path, "store file, or a volume as convert takes it")->required();
  app.add_flag("--json", *json, "print JSON");
  auto read = std::make_shared<VolumeReadArgs>();
  addVolumeReadOptions(app, *read);
  return [path, json, read] { return runInfo(*path, *read, *json); };
});

}  // namespace
}  // namespace ropecast::tools
