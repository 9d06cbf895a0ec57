#include "store/source_zarr.h"

#include <blosc.h>
#include <zlib.h>
#include <zstd.h>

#include <glm/common.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <thread>
#include <vector>

#include "core/error.h"
#include "core/input_file.h"
#include "store/array_axes.h"
#include "store/source_raw.h"
#include "store/zarr_metadata.h"

namespace ropecast {
namespace {

namespace fs = std::filesystem;

// Metadata files are small JSON; a larger one is not Zarr's.
constexpr size_t kMaxMetadataBytes = size_t(16) << 20;
// How far below a group its arrays are looked for, for the message that lists them.
constexpr int kArraySearchDepth = 4;

bool present(const fs::path& path) {
  std::error_code ec;
  return fs::exists(path, ec);
}

std::string readMetadata(const fs::path& file) {
  return readTextInput(file.string(), file.string(), kMaxMetadataBytes);
}

// The folders holding a `.zarray` below `group` (relative to it), not looking inside arrays.
std::vector<std::string> arraysBelow(const fs::path& group) {
  std::vector<std::string> arrays;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(group, fs::directory_options::skip_permission_denied, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (!it->is_directory(ec)) continue;
    if (present(it->path() / ".zarray")) {
      arrays.push_back(fs::relative(it->path(), group, ec).string());
      it.disable_recursion_pending();
    } else if (it.depth() + 1 >= kArraySearchDepth) {
      it.disable_recursion_pending();
    }
  }
  std::sort(arrays.begin(), arrays.end());
  return arrays;
}

std::string listed(const std::vector<std::string>& names) {
  constexpr size_t kShown = 8;
  std::string text;
  for (size_t i = 0; i < std::min(names.size(), kShown); ++i) text += (i ? ", " : "") + names[i];
  if (names.size() > kShown) text += " and " + std::to_string(names.size() - kShown) + " more";
  return text;
}

// Inflates a zlib (or, with `gzip`, a gzip) stream into exactly out.size() bytes; false otherwise.
bool inflateExactly(std::span<const std::byte> in, std::span<std::byte> out, bool gzip) {
  z_stream zs{};
  if (inflateInit2(&zs, gzip ? 15 + 16 : 15) != Z_OK) return false;
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<std::byte*>(in.data()));
  zs.avail_in = uInt(in.size());
  zs.next_out = reinterpret_cast<Bytef*>(out.data());
  zs.avail_out = uInt(out.size());
  const int status = inflate(&zs, Z_FINISH);
  const bool whole = status == Z_STREAM_END && zs.total_out == out.size();
  inflateEnd(&zs);
  return whole;
}

// Decodes a stored chunk into `out` (one whole chunk's bytes), or says why it cannot.
std::string decodeChunk(ZarrCompressor compressor, std::span<const std::byte> in, std::span<std::byte> out) {
  const std::string expected = "; expected " + std::to_string(out.size()) + " bytes of samples";
  switch (compressor) {
    case ZarrCompressor::None:
      if (in.size() != out.size()) return "holds " + std::to_string(in.size()) + " bytes" + expected;
      std::memcpy(out.data(), in.data(), out.size());
      return "";
    case ZarrCompressor::Blosc: {
      size_t bytes = 0;
      if (blosc_cbuffer_validate(in.data(), in.size(), &bytes) != 0) return "is not blosc data" + expected;
      if (bytes != out.size()) return "decompresses to " + std::to_string(bytes) + " bytes" + expected;
      if (blosc_decompress_ctx(in.data(), out.data(), out.size(), 1) != int(out.size()))
        return "is damaged (blosc)";
      return "";
    }
    case ZarrCompressor::Zlib:
    case ZarrCompressor::Gzip:
      if (!inflateExactly(in, out, compressor == ZarrCompressor::Gzip))
        return std::string("is damaged or of another size (") +
               (compressor == ZarrCompressor::Gzip ? "gzip" : "zlib") + ")" + expected;
      return "";
    case ZarrCompressor::Zstd: {
      const size_t n = ZSTD_decompress(out.data(), out.size(), in.data(), in.size());
      if (ZSTD_isError(n)) return std::string("is damaged (zstd: ") + ZSTD_getErrorName(n) + ")";
      if (n != out.size()) return "decompresses to " + std::to_string(n) + " bytes" + expected;
      return "";
    }
  }
  return "has an unknown compressor";
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
  ZarrSource(VolumeInfo info, fs::path folder, ZarrArray array, std::array<int, 3> zyx,
             uint64_t maxBufferedBytes)
      : info_(std::move(info)),
        folder_(std::move(folder)),
        array_(std::move(array)),
        zyx_(zyx),
        maxBufferedBytes_(maxBufferedBytes) {
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
    const size_t sliceBytes = info_.sliceBytes();
    for (uint32_t done = 0; done < count;) {
      const uint64_t z = uint64_t(z0) + done;
      if (z < bufferBegin_ || z >= bufferEnd_) decodeSlices(z);
      const uint32_t slices = uint32_t(std::min<uint64_t>(count - done, bufferEnd_ - z));
      std::memcpy(out.data() + size_t(done) * sliceBytes, buffer_.data() + (z - bufferBegin_) * sliceBytes,
                  size_t(slices) * sliceBytes);
      done += slices;
    }
  }

 private:
  fs::path chunkFile(const std::vector<uint64_t>& index) const {
    std::string key;
    for (size_t a = 0; a < index.size(); ++a) {
      if (a) key += array_.separator;
      key += std::to_string(index[a]);
    }
    return folder_ / key;
  }

  // Decodes chunk (layer, cy, cx) and copies its samples inside the array and the buffered slices into the
  // buffer (each chunk's samples are their own part of it: workers call this for different chunks at once).
  // Returns the problem, if any, naming the chunk file.
  std::string copyChunk(uint64_t layer, uint64_t cy, uint64_t cx, std::vector<std::byte>& stored,
                        std::vector<std::byte>& decoded) {
    std::vector<uint64_t> index(array_.shape.size(), 0);
    index[size_t(zyx_[0])] = layer, index[size_t(zyx_[1])] = cy, index[size_t(zyx_[2])] = cx;
    const fs::path file = chunkFile(index);
    const size_t width = bytesPerSample(info_.type);
    decoded.resize(array_.chunkSamples() * width);
    std::error_code ec;
    if (!fs::exists(file, ec)) {
      fillChunk(decoded, info_.type, array_.fillValue);
    } else {
      try {
        const PosixFile input(file.string());
        stored.resize(input.sizeBytes());
        input.readAt(0, stored);
      } catch (const Error& e) {
        return e.what();
      }
      if (const std::string problem = decodeChunk(array_.compressor, stored, decoded); !problem.empty())
        return "Zarr chunk " + file.string() + ": " + problem;
      samplesToNative(decoded, info_.type, array_.bigEndian);
    }
    // The chunk's box inside the array: edge chunks are stored whole, past the array's end.
    const glm::u64vec3 chunk(array_.chunks[size_t(zyx_[2])], array_.chunks[size_t(zyx_[1])],
                             array_.chunks[size_t(zyx_[0])]);
    const glm::u64vec3 origin(cx * chunk.x, cy * chunk.y, layer * chunk.z);
    const glm::u64vec3 extent = glm::min(chunk, glm::u64vec3(info_.dims) - origin);
    const uint64_t sx = strides_[size_t(zyx_[2])], sy = strides_[size_t(zyx_[1])],
                   sz = strides_[size_t(zyx_[0])];
    const uint64_t zBegin = std::max(origin.z, bufferBegin_),
                   zEnd = std::min(origin.z + extent.z, bufferEnd_);
    for (uint64_t slice = zBegin; slice < zEnd; ++slice)
      for (uint64_t y = 0; y < extent.y; ++y) {
        const uint64_t z = slice - origin.z;
        std::byte* target =
            buffer_.data() +
            (((slice - bufferBegin_) * info_.dims.y + origin.y + y) * info_.dims.x + origin.x) * width;
        const std::byte* source = decoded.data() + (z * sz + y * sy) * width;
        if (sx == 1) {
          std::memcpy(target, source, extent.x * width);
        } else {
          for (uint64_t x = 0; x < extent.x; ++x)
            std::memcpy(target + x * width, source + x * sx * width, width);
        }
      }
    return "";
  }

  // Fills the buffer with the slices from z on that it holds: the rest of z's chunk layer, or as much of it
  // as maxBufferedBytes_ allows, decoding each chunk of the layer on worker threads.
  void decodeSlices(uint64_t z) {
    const uint64_t depth = array_.chunks[size_t(zyx_[0])], layer = z / depth;
    const uint64_t layerEnd = std::min<uint64_t>((layer + 1) * depth, info_.dims.z);
    const uint64_t fits = std::max<uint64_t>(1, maxBufferedBytes_ / info_.sliceBytes());
    const uint64_t begin = layerEnd - layer * depth <= fits ? layer * depth : z;
    const uint64_t end = std::min(layerEnd, begin + fits);
    buffer_.resize(size_t(end - begin) * info_.sliceBytes());
    bufferBegin_ = begin, bufferEnd_ = end;
    const uint64_t across =
        (info_.dims.x + array_.chunks[size_t(zyx_[2])] - 1) / array_.chunks[size_t(zyx_[2])];
    const uint64_t down =
        (info_.dims.y + array_.chunks[size_t(zyx_[1])] - 1) / array_.chunks[size_t(zyx_[1])];
    const uint64_t chunks = across * down;
    const unsigned workers = unsigned(std::clamp<uint64_t>(std::thread::hardware_concurrency(), 1, chunks));
    std::vector<std::string> problems(workers);
    {
      std::vector<std::jthread> threads;
      for (unsigned w = 0; w < workers; ++w)
        threads.emplace_back([&, w] {
          std::vector<std::byte> stored, decoded;
          try {
            for (uint64_t i = w; i < chunks && problems[w].empty(); i += workers)
              problems[w] = copyChunk(layer, i / across, i % across, stored, decoded);
          } catch (const std::exception& e) {  // out of memory: the reading thread hears of it
            problems[w] = e.what();
          }
        });
    }
    for (const std::string& problem : problems)
      if (!problem.empty()) {
        bufferBegin_ = bufferEnd_ = 0;
        throw Error(problem);
      }
  }

  VolumeInfo info_;
  fs::path folder_;
  ZarrArray array_;
  std::array<int, 3> zyx_;
  uint64_t maxBufferedBytes_;
  std::vector<uint64_t> strides_;             // samples between neighbors along each axis within a chunk
  uint64_t bufferBegin_ = 0, bufferEnd_ = 0;  // the slices decoded into buffer_
  std::vector<std::byte> buffer_;
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
  if (present(folder / "zarr.json"))
    throw Error(path + ": a Zarr v3 array or group (zarr.json); ropecast reads Zarr v2 (.zarray)");
  std::optional<OmeMultiscale> ome;
  fs::path arrayFolder = folder;
  if (!present(folder / ".zarray")) {
    if (present(folder / ".zattrs"))
      ome = parseOmeMultiscale(readMetadata(folder / ".zattrs"), (folder / ".zattrs").string());
    if (!ome) {
      const std::vector<std::string> arrays = arraysBelow(folder);
      throw Error(path + ": a Zarr group that is no OME-Zarr image (no 'multiscales' in its .zattrs); " +
                  (arrays.empty() ? std::string("no array lies below it")
                                  : "give one of its arrays' folders: " + listed(arrays)));
    }
    arrayFolder = folder / ome->datasetPath;
    if (!present(arrayFolder / ".zarray"))
      throw Error(path + ": its OME-Zarr image's first dataset, " + arrayFolder.string() +
                  ", holds no .zarray");
  }
  const fs::path metadata = arrayFolder / ".zarray";
  ZarrArray array = parseZarrArray(readMetadata(metadata), metadata.string());
  const ArrayAxes axes =
      ome && !ome->axisNames.empty() ? volumeAxesNamed(array.shape, ome->axisNames) : volumeAxes(array.shape);
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
  info.description = "zarr:" + arrayFolder.lexically_normal().string();
  return std::make_unique<ZarrSource>(std::move(info), arrayFolder, std::move(array), axes.zyx,
                                      maxBufferedBytes);
}

}  // namespace ropecast
