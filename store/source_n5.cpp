#include "store/source_n5.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <vector>

#include "core/error.h"
#include "core/header_text.h"
#include "core/input_file.h"
#include "store/array_axes.h"
#include "store/array_groups.h"
#include "store/chunk_codecs.h"
#include "store/chunk_layer.h"
#include "store/n5_metadata.h"
#include "store/picked_volume.h"
#include "store/source_raw.h"
#include "store/source_zarr.h"

namespace ropecast {
namespace {

namespace fs = std::filesystem;

// Attributes are small JSON; a larger file is not N5's.
constexpr size_t kMaxAttributesBytes = size_t(16) << 20;

fs::path attributesOf(const fs::path& folder) {
  return folder / "attributes.json";
}

std::string readAttributes(const fs::path& folder) {
  const fs::path file = attributesOf(folder);
  return readTextInput(file.string(), file.string(), kMaxAttributesBytes);
}

bool holdsDataset(const fs::path& folder) {
  std::error_code ec;
  return fs::exists(attributesOf(folder), ec) &&
         isN5Dataset(readAttributes(folder), attributesOf(folder).string());
}

// Strides, in samples, of a block of `size` samples per axis (slowest first) whose first axis varies slowest.
std::vector<uint64_t> stridesOf(const std::vector<uint64_t>& size) {
  std::vector<uint64_t> strides(size.size(), 1);
  for (size_t a = size.size() - 1; a-- > 0;) strides[a] = strides[a + 1] * size[a + 1];
  return strides;
}

class N5Source final : public VolumeSource {
 public:
  // `picked`: the index read along each axis that is not z, y or x (a time point, a channel).
  N5Source(VolumeInfo info, fs::path folder, N5Dataset dataset, std::array<int, 3> zyx,
           std::vector<uint64_t> picked, uint64_t maxBufferedBytes)
      : info_(std::move(info)),
        folder_(std::move(folder)),
        dataset_(std::move(dataset)),
        zyx_(zyx),
        picked_(std::move(picked)),
        layer_(info_.dims, info_.type, dataset_.blockSize[size_t(zyx_[0])], maxBufferedBytes) {}

  const VolumeInfo& info() const override { return info_; }

 protected:
  void readSlices(uint32_t z0, uint32_t count, std::span<std::byte> out) override {
    layer_.read(z0, count, out, [this](uint64_t z) {
      layer_.decodeLayer<BlockBuffers>(
          z, dataset_.blockSize[size_t(zyx_[2])], dataset_.blockSize[size_t(zyx_[1])],
          [this](uint64_t layer, uint64_t by, uint64_t bx, BlockBuffers& buffers) {
            return copyBlock(layer, by, bx, buffers);
          });
    });
  }

 private:
  // A worker's buffers, kept from block to block.
  struct BlockBuffers {
    std::vector<std::byte> stored, decoded;
  };

  // The file of block `index` (slowest axis first): its indices fastest axis first, a folder each.
  fs::path blockFile(const std::vector<uint64_t>& index) const {
    fs::path file = folder_;
    for (size_t a = index.size(); a-- > 0;) file /= std::to_string(index[a]);
    return file;
  }

  glm::u64vec3 zyxOf(const std::vector<uint64_t>& perAxis) const {
    return {perAxis[size_t(zyx_[2])], perAxis[size_t(zyx_[1])], perAxis[size_t(zyx_[0])]};
  }

  // A block's samples per axis inside the dataset (slowest first), for messages.
  std::vector<uint64_t> blockExtent(const std::vector<uint64_t>& index) const {
    std::vector<uint64_t> extent(index.size());
    for (size_t a = 0; a < index.size(); ++a)
      extent[a] = std::min(dataset_.blockSize[a], dataset_.shape[a] - index[a] * dataset_.blockSize[a]);
    return extent;
  }

  // Decodes a stored block into b.decoded; `size` gets its samples per axis. Returns the problem, if any.
  std::string decodeBlock(const std::vector<uint64_t>& index, std::vector<uint64_t>& size, BlockBuffers& b) {
    N5BlockHeader header;
    if (std::string problem = parseN5BlockHeader(b.stored, index.size(), header); !problem.empty())
      return problem;
    // A block holds the samples of its part of the dataset: whole, or cut at the dataset's far edges.
    const std::vector<uint64_t> inside = blockExtent(index);
    for (size_t a = 0; a < index.size(); ++a)
      if (header.size[a] < inside[a] || header.size[a] > dataset_.blockSize[a])
        return "holds " + formatExtent(header.size) + " samples; expected " + formatExtent(inside) +
               " (the dataset's part there) up to " + formatExtent(dataset_.blockSize) + " (its block size)";
    size = header.size;
    uint64_t samples = 1;
    for (const uint64_t s : size) samples *= s;
    b.decoded.resize(samples * bytesPerSample(info_.type));
    const std::span<const std::byte> data = std::span<const std::byte>(b.stored).subspan(header.bytes);
    if (dataset_.compressor) {
      // N5's lz4 is lz4-java's block stream; zarr-python's N5 store writes numcodecs' framing instead.
      const bool javaBlocks = data.size() >= 8 && std::memcmp(data.data(), "LZ4Block", 8) == 0;
      const Compressor compressor = *dataset_.compressor == Compressor::Lz4Blocks && !javaBlocks
                                        ? Compressor::Lz4Sized
                                        : *dataset_.compressor;
      if (std::string problem = decompressExactly(compressor, data, b.decoded); !problem.empty())
        return problem;
    } else if (data.size() != b.decoded.size()) {
      return "holds " + std::to_string(data.size()) + " bytes of samples; expected " +
             std::to_string(b.decoded.size());
    } else {
      std::memcpy(b.decoded.data(), data.data(), data.size());
    }
    samplesToNative(b.decoded, info_.type, true);
    return "";
  }

  // Reads and decodes block (layer, by, bx) and places its samples in the buffer. Returns the problem, if
  // any, naming the file.
  std::string copyBlock(uint64_t layer, uint64_t by, uint64_t bx, BlockBuffers& b) {
    std::vector<uint64_t> index(dataset_.shape.size(), 0);
    for (size_t a = 0; a < index.size(); ++a) index[a] = picked_[a] / dataset_.blockSize[a];
    index[size_t(zyx_[0])] = layer, index[size_t(zyx_[1])] = by, index[size_t(zyx_[2])] = bx;
    const fs::path file = blockFile(index);
    std::error_code ec;
    std::vector<uint64_t> size = dataset_.blockSize;
    if (fs::exists(file, ec)) {
      try {
        const PosixFile input(file.string());
        b.stored.resize(input.sizeBytes());
        input.readAt(0, b.stored);
      } catch (const Error& e) {
        return e.what();
      }
      if (std::string problem = decodeBlock(index, size, b); !problem.empty())
        return "N5 block " + file.string() + ": " + problem;
    } else {  // N5 has no fill value: a block not stored holds zeros
      uint64_t samples = 1;
      for (const uint64_t s : size) samples *= s;
      b.decoded.assign(samples * bytesPerSample(info_.type), std::byte{0});
    }
    // The picked time point's and channel's samples within the block.
    const std::vector<uint64_t> strides = stridesOf(size);
    uint64_t first = 0;
    for (size_t a = 0; a < index.size(); ++a) first += picked_[a] % dataset_.blockSize[a] * strides[a];
    const glm::u64vec3 origin = glm::u64vec3(bx, by, layer) * zyxOf(dataset_.blockSize);
    layer_.place(b.decoded.data() + first * bytesPerSample(info_.type), zyxOf(strides), origin, zyxOf(size));
    return "";
  }

  VolumeInfo info_;
  fs::path folder_;
  N5Dataset dataset_;
  std::array<int, 3> zyx_;
  std::vector<uint64_t> picked_;
  ChunkLayer layer_;
};

// What a BigDataViewer XML says of the view it reads that the N5 container does not.
struct BdvView {
  std::string xml;
  std::optional<glm::dvec3> voxelSize;
  PickedVolume picked;  // of its time points and view setups
};

// The dataset in `datasetFolder` (`path` as given, for messages), one of the levels of the group in
// `groupFolder` where that holds group attributes (empty: none).
std::unique_ptr<VolumeSource> openDataset(const std::string& path, const fs::path& datasetFolder,
                                          const fs::path& groupFolder, const SourceOptions& options,
                                          uint64_t maxBufferedBytes, const std::optional<BdvView>& bdv);

}  // namespace

bool isN5Folder(const std::string& path) {
  std::error_code ec;
  return fs::is_directory(path, ec) && fs::exists(attributesOf(path), ec) && !isZarrFolder(path);
}

std::unique_ptr<VolumeSource> openN5Source(const std::string& path, const SourceOptions& options,
                                           uint64_t maxBufferedBytes) {
  const fs::path folder(path);
  if (holdsDataset(folder)) {  // perhaps a level of a group, which then says its calibration
    fs::path level = folder.lexically_normal();
    if (!level.has_filename()) level = level.parent_path();  // "s2/"
    return openDataset(path, folder, level.parent_path(), options, maxBufferedBytes, std::nullopt);
  }
  // A group: its multiscale pyramid's first dataset, named by `multiscales` or as s0.
  const std::optional<std::string> multiscale =
      n5MultiscaleDataset(readAttributes(folder), attributesOf(folder).string());
  const fs::path datasetFolder = folder / multiscale.value_or("s0");
  if (!holdsDataset(datasetFolder)) {
    if (multiscale)
      throw Error(path + ": its first multiscale dataset, " + datasetFolder.string() +
                  ", holds no N5 dataset (attributes.json with dimensions)");
    const std::vector<std::string> datasets =
        arraysBelow(folder.string(), [](const std::string& f) { return holdsDataset(f); });
    throw Error(path + ": an N5 group that is no multiscale image (no 'multiscales', no s0 dataset); " +
                (datasets.empty() ? std::string("no dataset lies below it")
                                  : "give one of its datasets' folders: " + listedNames(datasets)));
  }
  return openDataset(path, datasetFolder, folder, options, maxBufferedBytes, std::nullopt);
}

std::unique_ptr<VolumeSource> openBdvN5Source(const std::string& xml, const BdvDataset& dataset,
                                              const SourceOptions& options) {
  const PickedVolume picked = pickBdvView(dataset, options, xml);
  const BdvSetup& setup = dataset.setups[picked.channel];
  const fs::path folder =
      fs::path(dataset.images) / bdvN5DatasetPath(dataset.timepoints[picked.timePoint], setup.id);
  if (!holdsDataset(folder))
    throw Error("BigDataViewer XML " + xml + ": its view (time point " +
                std::to_string(dataset.timepoints[picked.timePoint]) + ", setup " + std::to_string(setup.id) +
                ") has no N5 dataset " + folder.string());
  SourceOptions picking = options;  // the dataset itself is one volume
  picking.timePoint.reset();
  picking.channel.reset();
  return openDataset(folder.string(), folder, {}, picking, kN5MaxBufferedBytes,
                     BdvView{xml, setup.voxelSize, picked});
}

namespace {

// The calibration of the group in `groupFolder` at the level whose attributes are `level` (its
// pixelResolution or resolution is the full resolution's: times the level's downsamplingFactors); empty where
// the folder holds no group's attributes. Attributes that cannot be read throw where the group was given
// (`groupGiven`), and count for nothing where the dataset alone was.
N5Calibration groupCalibration(const fs::path& groupFolder, bool groupGiven, const std::string& level,
                               const std::string& where) {
  std::error_code ec;
  if (groupFolder.empty() || !fs::exists(attributesOf(groupFolder), ec)) return {};
  N5Calibration calibration;
  try {
    const std::string attributes = readAttributes(groupFolder);
    if (isN5Dataset(attributes, attributesOf(groupFolder).string())) return {};
    calibration = parseN5Calibration(attributes, attributesOf(groupFolder).string());
  } catch (const Error&) {
    if (groupGiven) throw;
    return {};
  }
  const std::optional<std::vector<double>> factors = parseN5DownsamplingFactors(level, where);
  if (factors && calibration.scale && calibration.attribute != "transform" &&
      factors->size() == calibration.scale->size())
    for (size_t a = 0; a < factors->size(); ++a) (*calibration.scale)[a] *= (*factors)[a];
  return calibration;
}

std::unique_ptr<VolumeSource> openDataset(const std::string& path, const fs::path& datasetFolder,
                                          const fs::path& groupFolder, const SourceOptions& options,
                                          uint64_t maxBufferedBytes, const std::optional<BdvView>& bdv) {
  const std::string attributes = readAttributes(datasetFolder);
  const std::string where = attributesOf(datasetFolder).string();
  N5Dataset dataset = parseN5Dataset(attributes, where);
  N5Calibration calibration = parseN5Calibration(attributes, where);
  if (calibration.attribute.empty())
    calibration = groupCalibration(groupFolder, datasetFolder != fs::path(path), attributes, where);
  const ArrayAxes axes = arrayAxesOf(dataset.shape, calibration.axisNames, options.axes);
  if (!axes.problem.empty())
    throw Error("N5 dataset " + datasetFolder.string() + ": not a volume: " + axes.problem);
  const auto along = [&](int i) { return dataset.shape[size_t(axes.zyx[size_t(i)])]; };
  if (along(0) > kMaxDimsPerAxis || along(1) > kMaxDimsPerAxis || along(2) > kMaxDimsPerAxis)
    throw Error("N5 dataset " + datasetFolder.string() + ": " + formatExtent(dataset.shape) +
                " samples; a store holds at most " + std::to_string(kMaxDimsPerAxis) + " per axis");

  VolumeInfo info;
  info.dims = glm::u32vec3(uint32_t(along(2)), uint32_t(along(1)), uint32_t(along(0)));
  info.type = dataset.type;
  glm::dvec3 spacing(1.0);
  const auto zyxOf = [&](const std::vector<double>& perAxis) {
    return glm::dvec3(perAxis[size_t(axes.zyx[2])], perAxis[size_t(axes.zyx[1])],
                      perAxis[size_t(axes.zyx[0])]);
  };
  if (calibration.scale) {
    if (calibration.scale->size() != dataset.shape.size()) {
      info.notes.push_back(path + ": its " + calibration.attribute + " has " +
                           std::to_string(calibration.scale->size()) + " values for " +
                           std::to_string(dataset.shape.size()) + " axes; 1,1,1 is used");
    } else if (!isValidSpacing(zyxOf(*calibration.scale))) {
      info.notes.push_back(path + ": its " + calibration.attribute + " of x, y, z (" +
                           formatSpacing(zyxOf(*calibration.scale)) +
                           ") is not a valid spacing; 1,1,1 is used");
    } else {
      spacing = zyxOf(*calibration.scale);
    }
  }
  if (bdv && bdv->voxelSize) spacing = *bdv->voxelSize;
  info.spacing = options.spacing.value_or(spacing);
  if (calibration.translation && calibration.translation->size() == dataset.shape.size()) {
    const glm::dvec3 origin = zyxOf(*calibration.translation);
    if (std::isfinite(origin.x) && std::isfinite(origin.y) && std::isfinite(origin.z)) info.origin = origin;
  }
  const PickedVolume picked = bdv ? bdv->picked
                                  : pickVolume(options,
                                               {axes.time < 0 ? 1 : dataset.shape[size_t(axes.time)],
                                                axes.channel < 0 ? 1 : dataset.shape[size_t(axes.channel)],
                                                "channel",
                                                {}},
                                               "N5 dataset " + path);
  std::vector<uint64_t> pickedIndex(dataset.shape.size(), 0);
  if (axes.time >= 0) pickedIndex[size_t(axes.time)] = picked.timePoint;
  if (axes.channel >= 0) pickedIndex[size_t(axes.channel)] = picked.channel;
  info.description = "n5:" + datasetFolder.lexically_normal().string();
  if (bdv) info.description = "bdv:" + bdv->xml + " (" + info.description + ")";
  describePicked(info, picked);
  return std::make_unique<N5Source>(std::move(info), datasetFolder, std::move(dataset), axes.zyx,
                                    std::move(pickedIndex), maxBufferedBytes);
}

}  // namespace
}  // namespace ropecast
