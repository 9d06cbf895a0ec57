#include "store/source_zarr.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <vector>

#include "core/error.h"
#include "core/header_text.h"
#include "core/input_file.h"
#include "store/array_axes.h"
#include "store/array_groups.h"
#include "store/chunk_codecs.h"
#include "store/chunk_layer.h"
#include "store/picked_volume.h"
#include "store/source_raw.h"
#include "store/zarr_metadata.h"

namespace ropecast {
namespace {

namespace fs = std::filesystem;

// Metadata files are small JSON; a larger one is not Zarr's.
constexpr size_t kMaxMetadataBytes = size_t(16) << 20;

bool present(const fs::path& path) {
  std::error_code ec;
  return fs::exists(path, ec);
}

std::string readMetadata(const fs::path& file) {
  return readTextInput(file.string(), file.string(), kMaxMetadataBytes);
}

// The metadata file of the array in `folder` (v2's `.zarray`, or a v3 `zarr.json` of an array), or an empty
// path when the folder holds none.
fs::path arrayMetadata(const fs::path& folder) {
  if (present(folder / ".zarray")) return folder / ".zarray";
  const fs::path v3 = folder / "zarr.json";
  if (present(v3) && zarrV3NodeType(readMetadata(v3), v3.string()) == "array") return v3;
  return {};
}

// The compressor of a bytes-to-bytes codec other than a checksum.
Compressor compressorOf(ZarrCodec codec) {
  switch (codec) {
    case ZarrCodec::Blosc:
      return Compressor::Blosc;
    case ZarrCodec::Zlib:
      return Compressor::Zlib;
    case ZarrCodec::Gzip:
      return Compressor::Gzip;
    case ZarrCodec::Zstd:
      return Compressor::Zstd;
    case ZarrCodec::Lz4:
      return Compressor::Lz4Sized;
    case ZarrCodec::Lzma:
      return Compressor::Xz;
    case ZarrCodec::Bz2:
      return Compressor::Bzip2;
    case ZarrCodec::Crc32c:  // decodeBytes drops its bytes before any compressor
      break;
  }
  throw Error("a Zarr checksum codec has no compressor");
}

// Decodes stored bytes through `codecs` (in encoding order: undone in reverse) into exactly out.size() bytes,
// or says why it cannot. A CRC-32C codec's 4 bytes are dropped, not checked; the metadata parser allows one
// compressor at most.
std::string decodeBytes(const std::vector<ZarrCodec>& codecs, std::span<const std::byte> in,
                        std::span<std::byte> out, std::vector<std::byte>& scratch) {
  constexpr size_t kChecksumBytes = 4;
  for (size_t i = codecs.size(); i-- > 0;) {
    if (codecs[i] == ZarrCodec::Crc32c) {
      if (in.size() < kChecksumBytes) return "is shorter than its checksum";
      in = in.first(in.size() - kChecksumBytes);
      continue;
    }
    // CRC-32C codecs applied before the compressor: their bytes end its output.
    const size_t checksumsBefore =
        size_t(std::count(codecs.begin(), codecs.begin() + long(i), ZarrCodec::Crc32c));
    if (checksumsBefore == 0) return decompressExactly(compressorOf(codecs[i]), in, out);
    scratch.resize(out.size() + kChecksumBytes * checksumsBefore);
    if (const std::string problem = decompressExactly(compressorOf(codecs[i]), in, scratch); !problem.empty())
      return problem;
    in = std::span<const std::byte>(scratch).first(out.size());
    break;
  }
  if (in.size() != out.size())
    return "holds " + std::to_string(in.size()) + " bytes; expected " + std::to_string(out.size()) +
           " bytes of samples";
  std::memcpy(out.data(), in.data(), out.size());
  return "";
}

// Every sample of `chunk` set to `value` in `type` (an integer type's NaN or out-of-range fill saturates).
void fillChunk(std::span<std::byte> chunk, SampleType type, double value) {
  forSampleType(type, [&](auto zero) {
    using T = decltype(zero);
    T v{};
    if constexpr (std::is_floating_point_v<T>) {
      v = T(value);
    } else if (std::isfinite(value)) {
      v = T(
          std::clamp(value, double(std::numeric_limits<T>::lowest()), double(std::numeric_limits<T>::max())));
    }
    for (size_t i = 0; i + sizeof(T) <= chunk.size(); i += sizeof(T))
      std::memcpy(chunk.data() + i, &v, sizeof v);
  });
}

class ZarrSource final : public VolumeSource {
 public:
  // `picked`: the index read along each axis that is not z, y or x (a time point, a channel).
  ZarrSource(VolumeInfo info, fs::path folder, ZarrArray array, std::array<int, 3> zyx,
             std::vector<uint64_t> picked, uint64_t maxBufferedBytes)
      : info_(std::move(info)),
        folder_(std::move(folder)),
        array_(std::move(array)),
        zyx_(zyx),
        picked_(std::move(picked)),
        layer_(info_.dims, info_.type, array_.chunks[size_t(zyx_[0])], maxBufferedBytes) {
    const size_t rank = array_.shape.size();
    strides_.assign(rank, 1);
    if (array_.fortranOrder) {
      for (size_t a = 1; a < rank; ++a) strides_[a] = strides_[a - 1] * array_.chunks[a - 1];
    } else {
      for (size_t a = rank - 1; a-- > 0;) strides_[a] = strides_[a + 1] * array_.chunks[a + 1];
    }
  }

  const VolumeInfo& info() const override { return info_; }

 protected:
  void readSlices(uint32_t z0, uint32_t count, std::span<std::byte> out) override {
    layer_.read(z0, count, out, [this](uint64_t z) {
      layer_.decodeLayer<ChunkBuffers>(
          z, array_.chunks[size_t(zyx_[2])], array_.chunks[size_t(zyx_[1])],
          [this](uint64_t layer, uint64_t cy, uint64_t cx, ChunkBuffers& buffers) {
            return copyChunk(layer, cy, cx, buffers);
          });
    });
  }

 private:
  // A worker's buffers, kept from chunk to chunk.
  struct ChunkBuffers {
    std::vector<std::byte> stored, decoded, scratch, inner;
  };

  // The file holding chunk (or shard) `index`, per axis of the array.
  fs::path chunkFile(const std::vector<uint64_t>& index) const {
    std::string key = array_.keyPrefix;
    for (size_t a = 0; a < index.size(); ++a) {
      if (a) key += array_.separator;
      key += std::to_string(index[a]);
    }
    return folder_ / key;
  }

  glm::u64vec3 zyxOf(const std::vector<uint64_t>& perAxis) const {
    return {perAxis[size_t(zyx_[2])], perAxis[size_t(zyx_[1])], perAxis[size_t(zyx_[0])]};
  }

  // Whether the inner chunk at `at` (inner chunks of `inner` samples per axis, counted within the shard)
  // holds the picked time point and channel.
  bool holdsPicked(const std::vector<uint64_t>& at, const std::vector<uint64_t>& inner) const {
    for (size_t a = 0; a < at.size(); ++a)
      if (int(a) != zyx_[0] && int(a) != zyx_[1] && int(a) != zyx_[2] &&
          at[a] != picked_[a] % array_.chunks[a] / inner[a])
        return false;
    return true;
  }

  // Decodes a shard (v3's sharding_indexed; empty when it is not stored) whose first sample lies at `origin`,
  // inner chunk by inner chunk (those its index lists, the others the fill value), each placed in the buffer
  // if it reaches the buffered slices. Returns the problem, if any.
  std::string placeShard(std::span<const std::byte> shard, glm::u64vec3 origin, ChunkBuffers& b) {
    const ZarrSharding& sharding = *array_.sharding;
    const size_t rank = array_.chunks.size();
    std::vector<uint64_t> grid(rank), at(rank), strides(rank, 1);
    uint64_t count = 1, innerSamples = 1;
    for (size_t a = 0; a < rank; ++a) {
      grid[a] = array_.chunks[a] / sharding.chunks[a];
      count *= grid[a];
      innerSamples *= sharding.chunks[a];
    }
    for (size_t a = rank - 1; a-- > 0;) strides[a] = strides[a + 1] * sharding.chunks[a + 1];
    const uint64_t indexBytes = count * 16 + (sharding.indexChecksum ? 4 : 0);
    if (!shard.empty() && shard.size() < indexBytes)
      return "is shorter (" + std::to_string(shard.size()) + " bytes) than its index of " +
             std::to_string(count) + " inner chunks";
    const std::byte* index = shard.empty()         ? nullptr
                             : sharding.indexAtEnd ? shard.data() + shard.size() - indexBytes
                                                   : shard.data();
    const auto littleEndian = [](const std::byte* p) {
      uint64_t v = 0;
      for (int i = 7; i >= 0; --i) v = v << 8 | uint64_t(p[i]);
      return v;
    };
    const glm::u64vec3 inner = zyxOf(sharding.chunks);
    b.inner.resize(innerSamples * bytesPerSample(info_.type));
    for (uint64_t i = 0; i < count; ++i) {
      for (uint64_t a = rank, rest = i; a-- > 0;) at[a] = rest % grid[a], rest /= grid[a];
      const glm::u64vec3 innerOrigin = origin + zyxOf(at) * inner;
      if (!layer_.reaches(innerOrigin.z, inner.z) || !holdsPicked(at, sharding.chunks)) continue;
      const uint64_t offset = index ? littleEndian(index + 16 * i) : ~uint64_t(0);
      const uint64_t bytes = index ? littleEndian(index + 16 * i + 8) : ~uint64_t(0);
      if (offset == ~uint64_t(0) && bytes == ~uint64_t(0)) {
        fillChunk(b.inner, info_.type, array_.fillValue);
      } else {
        if (offset > shard.size() || bytes > shard.size() - offset)
          return "inner chunk " + std::to_string(i) + " lies past the shard's end";
        if (const std::string problem =
                decodeBytes(sharding.codecs, shard.subspan(offset, bytes), b.inner, b.scratch);
            !problem.empty())
          return "inner chunk " + std::to_string(i) + " " + problem;
        samplesToNative(b.inner, info_.type, sharding.bigEndian);
      }
      uint64_t first = 0;
      for (size_t a = 0; a < rank; ++a)
        first += picked_[a] % array_.chunks[a] % sharding.chunks[a] * strides[a];
      layer_.place(b.inner.data() + first * bytesPerSample(info_.type), zyxOf(strides), innerOrigin, inner);
    }
    return "";
  }

  // Reads and decodes chunk (or shard) (layer, cy, cx) and places its samples in the buffer. Returns the
  // problem, if any, naming the file.
  std::string copyChunk(uint64_t layer, uint64_t cy, uint64_t cx, ChunkBuffers& b) {
    std::vector<uint64_t> index(array_.shape.size(), 0);
    for (size_t a = 0; a < index.size(); ++a) index[a] = picked_[a] / array_.chunks[a];
    index[size_t(zyx_[0])] = layer, index[size_t(zyx_[1])] = cy, index[size_t(zyx_[2])] = cx;
    const fs::path file = chunkFile(index);
    const glm::u64vec3 chunk = zyxOf(array_.chunks), origin = glm::u64vec3(cx, cy, layer) * chunk;
    std::error_code ec;
    const bool stored = fs::exists(file, ec);
    b.stored.clear();
    if (stored) {
      try {
        const PosixFile input(file.string());
        b.stored.resize(input.sizeBytes());
        input.readAt(0, b.stored);
      } catch (const Error& e) {
        return e.what();
      }
    }
    if (array_.sharding) {
      const std::string problem = placeShard(b.stored, origin, b);
      return problem.empty() ? "" : "Zarr shard " + file.string() + ": " + problem;
    }
    b.decoded.resize(array_.chunkSamples() * bytesPerSample(info_.type));
    if (!stored) {
      fillChunk(b.decoded, info_.type, array_.fillValue);
    } else {
      if (const std::string problem = decodeBytes(array_.codecs, b.stored, b.decoded, b.scratch);
          !problem.empty())
        return "Zarr chunk " + file.string() + ": " + problem;
      samplesToNative(b.decoded, info_.type, array_.bigEndian);
    }
    // The picked time point's and channel's samples within the chunk.
    uint64_t first = 0;
    for (size_t a = 0; a < index.size(); ++a) first += picked_[a] % array_.chunks[a] * strides_[a];
    layer_.place(b.decoded.data() + first * bytesPerSample(info_.type), zyxOf(strides_), origin, chunk);
    return "";
  }

  VolumeInfo info_;
  fs::path folder_;
  ZarrArray array_;
  std::array<int, 3> zyx_;
  std::vector<uint64_t> picked_;
  ChunkLayer layer_;
  std::vector<uint64_t> strides_;  // samples between neighbors along each axis within a chunk
};

}  // namespace

bool isZarrFolder(const std::string& path) {
  std::error_code ec;
  if (!fs::is_directory(path, ec)) return false;
  const fs::path folder(path);
  return present(folder / ".zarray") || present(folder / ".zgroup") || present(folder / ".zattrs") ||
         present(folder / "zarr.json");
}

std::unique_ptr<VolumeSource> openZarrSource(const std::string& path, const SourceOptions& options,
                                             uint64_t maxBufferedBytes) {
  const fs::path folder(path);
  std::optional<OmeMultiscale> ome;
  fs::path arrayFolder = folder, metadata = arrayMetadata(folder);
  if (metadata.empty()) {  // a group: an OME-Zarr image's metadata is in .zattrs (v2) or zarr.json (v3)
    for (const char* name : {".zattrs", "zarr.json"})
      if (!ome && present(folder / name))
        ome = parseOmeMultiscale(readMetadata(folder / name), (folder / name).string());
    if (!ome) {
      const std::vector<std::string> arrays =
          arraysBelow(folder.string(), [](const std::string& f) { return !arrayMetadata(f).empty(); });
      throw Error(path + ": a Zarr group that is no OME-Zarr image (no 'multiscales' in its metadata); " +
                  (arrays.empty() ? std::string("no array lies below it")
                                  : "give one of its arrays' folders: " + listedNames(arrays)));
    }
    arrayFolder = folder / ome->datasetPath;
    metadata = arrayMetadata(arrayFolder);
    if (metadata.empty())
      throw Error(path + ": its OME-Zarr image's first dataset, " + arrayFolder.string() +
                  ", holds no Zarr array (.zarray or zarr.json)");
  } else {  // an array: perhaps a level of an OME-Zarr image, which then says its axes, scale and place
    fs::path level = folder.lexically_normal();
    if (!level.has_filename()) level = level.parent_path();
    const fs::path image = level.parent_path();
    for (const char* name : {".zattrs", "zarr.json"}) {
      std::error_code ec;
      if (ome || image.empty() || !fs::is_regular_file(image / name, ec)) continue;
      try {
        ome = parseOmeMultiscale(readMetadata(image / name), (image / name).string(),
                                 level.filename().string());
      } catch (const Error&) {  // the array alone was asked for: its image's metadata counts for nothing then
      }
    }
  }
  ZarrArray array = metadata.filename() == ".zarray"
                        ? parseZarrArray(readMetadata(metadata), metadata.string())
                        : parseZarrV3Array(readMetadata(metadata), metadata.string());
  // Axes by name: an OME-Zarr image's, else a v3 array's dimension names when they name z, y and x (others,
  // "lat" or "dim_0", say nothing of which axis is which).
  const auto namesZyx = [](const std::vector<std::string>& n) {
    return std::ranges::count(n, "z") == 1 && std::ranges::count(n, "y") == 1 &&
           std::ranges::count(n, "x") == 1;
  };
  const std::vector<std::string> names = ome && !ome->axisNames.empty()   ? ome->axisNames
                                         : namesZyx(array.dimensionNames) ? array.dimensionNames
                                                                          : std::vector<std::string>{};
  const ArrayAxes axes = arrayAxesOf(array.shape, names, options.axes);
  if (!axes.problem.empty())
    throw Error("Zarr array " + arrayFolder.string() + ": not a volume: " + axes.problem);
  const auto along = [&](int i) { return array.shape[size_t(axes.zyx[size_t(i)])]; };
  if (along(0) > kMaxDimsPerAxis || along(1) > kMaxDimsPerAxis || along(2) > kMaxDimsPerAxis)
    throw Error("Zarr array " + arrayFolder.string() + ": " + formatExtent(array.shape) +
                " samples; a store holds at most " + std::to_string(kMaxDimsPerAxis) + " per axis");

  VolumeInfo info;
  info.dims = glm::u32vec3(uint32_t(along(2)), uint32_t(along(1)), uint32_t(along(0)));
  info.type = array.type;
  glm::dvec3 spacing(1.0);
  if (ome && ome->scale && ome->scale->size() == array.shape.size()) {
    const auto scale = [&](int i) { return (*ome->scale)[size_t(axes.zyx[size_t(i)])]; };
    spacing = {scale(2), scale(1), scale(0)};
    if (!isValidSpacing(spacing)) {
      info.notes.push_back(path + ": its OME-Zarr scale of z, y, x (" + formatSpacing(spacing) +
                           ") is not a valid spacing; 1,1,1 is used");
      spacing = glm::dvec3(1.0);
    }
  }
  info.spacing = options.spacing.value_or(spacing);
  if (ome && ome->translation && ome->translation->size() == array.shape.size()) {
    const auto shift = [&](int i) { return (*ome->translation)[size_t(axes.zyx[size_t(i)])]; };
    const glm::dvec3 origin(shift(2), shift(1), shift(0));
    if (std::isfinite(origin.x) && std::isfinite(origin.y) && std::isfinite(origin.z)) info.origin = origin;
  }
  const PickedVolume picked = pickVolume(options,
                                         {axes.time < 0 ? 1 : array.shape[size_t(axes.time)],
                                          axes.channel < 0 ? 1 : array.shape[size_t(axes.channel)], "channel",
                                          ome ? ome->channelLabels : std::vector<std::string>{}},
                                         (ome ? "OME-Zarr image " : "Zarr array ") + path);
  std::vector<uint64_t> pickedIndex(array.shape.size(), 0);
  if (axes.time >= 0) pickedIndex[size_t(axes.time)] = picked.timePoint;
  if (axes.channel >= 0) pickedIndex[size_t(axes.channel)] = picked.channel;
  info.description = "zarr:" + arrayFolder.lexically_normal().string();
  describePicked(info, picked);
  return std::make_unique<ZarrSource>(std::move(info), arrayFolder, std::move(array), axes.zyx,
                                      std::move(pickedIndex), maxBufferedBytes);
}

}  // namespace ropecast
