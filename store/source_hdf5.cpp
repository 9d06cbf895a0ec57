#include "store/source_hdf5.h"

#include <hdf5.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <thread>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/file_names.h"
#include "core/header_text.h"
#include "core/input_file.h"
#include "store/array_axes.h"
#include "store/bdv_xml.h"
#include "store/chunk_codecs.h"
#include "store/chunk_layer.h"
#include "store/hdf5_spec.h"
#include "store/picked_volume.h"
#include "store/source_raw.h"

namespace ropecast {
namespace {

// Where Imaris keeps its full resolution's time points, their channels, and the image's true size and
// extents (its datasets are padded to whole chunks).
constexpr const char* kImarisTimePoint = "/DataSet/ResolutionLevel 0/TimePoint ";
constexpr const char* kImarisImageInfo = "/DataSetInfo/Image";

std::string imarisChannel(uint64_t timePoint) {
  return kImarisTimePoint + std::to_string(timePoint) + "/Channel ";
}
std::string imarisDataset(uint64_t timePoint, uint64_t channel) {
  return imarisChannel(timePoint) + std::to_string(channel) + "/Data";
}

// The chunk cache of a dataset read slab by slab holds one layer of its chunks (a slab thinner than a chunk
// would otherwise decompress each chunk again for every slab it crosses), up to this much.
constexpr size_t kMaxChunkCacheBytes = size_t(512) << 20;

// The library prints its error stack to stderr unless told not to; ropecast says what failed itself. Per
// thread in the thread-safe library, so every entry point calls it.
void silenceHdf5Errors() {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

// The innermost description on this thread's error stack (the most specific: "file signature not found"),
// which it clears.
std::string hdf5Problem() {
  std::string text;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_UPWARD,
      [](unsigned n, const H5E_error2_t* error, void* data) -> herr_t {
        if (n == 0 && error->desc) *static_cast<std::string*>(data) = error->desc;
        return 0;
      },
      &text);
  H5Eclear2(H5E_DEFAULT);
  return text.empty() ? "the HDF5 library gives no reason" : text;
}

// An HDF5 identifier, closed with its kind's close function.
class Handle {
 public:
  Handle() = default;
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  Handle(Handle&& other) noexcept : id_(std::exchange(other.id_, -1)), close_(other.close_) {}
  Handle& operator=(Handle&& other) noexcept {
    std::swap(id_, other.id_);
    std::swap(close_, other.close_);
    return *this;
  }
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  hid_t get() const { return id_; }
  explicit operator bool() const { return id_ >= 0; }

 private:
  hid_t id_ = -1;
  herr_t (*close_)(hid_t) = nullptr;
};

// The sample type of an HDF5 datatype, or why it has none.
struct TypeMatch {
  std::optional<SampleType> type;
  std::string problem;
};

TypeMatch sampleTypeOf(hid_t datatype) {
  const H5T_class_t kind = H5Tget_class(datatype);
  const size_t size = H5Tget_size(datatype);
  if (kind == H5T_INTEGER) {
    const bool isSigned = H5Tget_sign(datatype) == H5T_SGN_2;
    switch (size) {
      case 1:
        return {isSigned ? SampleType::Int8 : SampleType::UInt8, ""};
      case 2:
        return {isSigned ? SampleType::Int16 : SampleType::UInt16, ""};
      case 4:
        return {isSigned ? SampleType::Int32 : SampleType::UInt32, ""};
      default:
        return {std::nullopt, std::to_string(size * 8) + "-bit integers (8, 16 and 32 bits are read)"};
    }
  }
  if (kind == H5T_FLOAT) {
    if (size == 4) return {SampleType::Float32, ""};
    if (size == 8) return {SampleType::Float64, ""};
    return {std::nullopt, std::to_string(size * 8) + "-bit floats (32 and 64 bits are read)"};
  }
  const char* name = kind == H5T_STRING      ? "strings"
                     : kind == H5T_COMPOUND  ? "compound records"
                     : kind == H5T_ENUM      ? "enumerations"
                     : kind == H5T_ARRAY     ? "arrays per element"
                     : kind == H5T_REFERENCE ? "references"
                                             : "values that are not numbers";
  return {std::nullopt, name};
}

hid_t memoryTypeOf(SampleType type) {
  switch (type) {
    case SampleType::UInt8:
      return H5T_NATIVE_UINT8;
    case SampleType::Int8:
      return H5T_NATIVE_INT8;
    case SampleType::UInt16:
      return H5T_NATIVE_UINT16;
    case SampleType::Int16:
      return H5T_NATIVE_INT16;
    case SampleType::UInt32:
      return H5T_NATIVE_UINT32;
    case SampleType::Int32:
      return H5T_NATIVE_INT32;
    case SampleType::Float32:
      return H5T_NATIVE_FLOAT;
    case SampleType::Float64:
      return H5T_NATIVE_DOUBLE;
  }
  return H5T_NATIVE_UINT8;
}

// A dataset's shape as a volume: which three of its axes are z, y and x, or why it is not one.
struct VolumeShape {
  std::vector<uint64_t> extent;  // every axis, in HDF5's order
  std::array<int, 3> axes{};     // z, y, x
  int time = -1, channel = -1;   // axes named t and c (ilastik's axistags), or -1
  std::vector<uint64_t> picked;  // per axis, the index read along it where it is not z, y or x (else 0)
  std::optional<SampleType> type;
  std::string problem;  // empty when it is a volume
};

// An attribute's text: a string, fixed or variable in length, or an array of characters; "" where it is
// missing or none of these.
std::string attributeText(hid_t object, const char* name) {
  if (H5Aexists(object, name) <= 0) {
    H5Eclear2(H5E_DEFAULT);
    return "";
  }
  const Handle attribute(H5Aopen(object, name, H5P_DEFAULT), H5Aclose);
  const Handle type(attribute ? H5Aget_type(attribute.get()) : -1, H5Tclose);
  const Handle space(attribute ? H5Aget_space(attribute.get()) : -1, H5Sclose);
  std::string text;
  if (type && space && H5Tget_class(type.get()) == H5T_STRING) {
    const hssize_t count = H5Sget_simple_extent_npoints(space.get());
    if (H5Tis_variable_str(type.get()) > 0 && count == 1) {
      const Handle memoryType(H5Tcopy(H5T_C_S1), H5Tclose);
      char* value = nullptr;
      if (memoryType && H5Tset_size(memoryType.get(), H5T_VARIABLE) >= 0 &&
          H5Aread(attribute.get(), memoryType.get(), &value) >= 0 && value) {
        text = value;
        H5free_memory(value);
      }
    } else if (H5Tis_variable_str(type.get()) == 0 && count > 0 && count <= (1 << 20)) {
      text.assign(size_t(count) * H5Tget_size(type.get()), '\0');
      if (H5Aread(attribute.get(), type.get(), text.data()) < 0) text.clear();
      text = text.c_str();  // up to the first NUL
    }
  }
  H5Eclear2(H5E_DEFAULT);
  return text;
}

// The names of a dataset's axes, in HDF5's order, where ilastik's `axistags` attribute gives them (JSON:
// {"axes": [{"key": "t"}, {"key": "z"}, ...]}, the dataset's axes in order); none otherwise.
std::vector<std::string> axisTagNames(hid_t dataset) {
  const std::string text = attributeText(dataset, "axistags");
  if (text.empty()) return {};
  const nlohmann::json tags = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (!tags.is_object() || !tags.contains("axes") || !tags["axes"].is_array()) return {};
  std::vector<std::string> names;
  for (const nlohmann::json& axis : tags["axes"]) {
    if (!axis.is_object() || !axis.contains("key") || !axis["key"].is_string()) return {};
    names.push_back(axis["key"].get<std::string>());
  }
  return names;
}

// `givenAxes`: --axes's letters, for a dataset without axistags (store/array_axes.h).
VolumeShape volumeShapeOf(hid_t dataset, const std::string& givenAxes) {
  VolumeShape shape;
  const Handle datatype(H5Dget_type(dataset), H5Tclose);
  const TypeMatch match = datatype ? sampleTypeOf(datatype.get()) : TypeMatch{std::nullopt, hdf5Problem()};
  if (!match.type) {
    shape.problem = "its elements are " + match.problem;
    return shape;
  }
  shape.type = match.type;
  const Handle space(H5Dget_space(dataset), H5Sclose);
  const int rank = space ? H5Sget_simple_extent_ndims(space.get()) : -1;
  if (rank < 0) {
    shape.problem = "its dataspace cannot be read: " + hdf5Problem();
    return shape;
  }
  std::vector<hsize_t> extent(static_cast<size_t>(rank));
  if (rank > 0) H5Sget_simple_extent_dims(space.get(), extent.data(), nullptr);
  shape.extent.assign(extent.begin(), extent.end());
  shape.picked.assign(shape.extent.size(), 0);
  const std::vector<std::string> names = axisTagNames(dataset);
  const ArrayAxes axes = arrayAxesOf(
      shape.extent, names.size() == shape.extent.size() ? names : std::vector<std::string>{}, givenAxes);
  shape.axes = axes.zyx;
  shape.time = axes.time;
  shape.channel = axes.channel;
  shape.problem = axes.problem;
  return shape;
}

// The object at `path` opened, or an empty handle when there is none (or it cannot be opened).
Handle openObject(hid_t file, const std::string& path) {
  const hid_t id = H5Oopen(file, path.c_str(), H5P_DEFAULT);
  if (id < 0) H5Eclear2(H5E_DEFAULT);
  return Handle(id, H5Oclose);
}

// How many of the objects "PREFIX0", "PREFIX1", ... exist, counting up from 0 (Imaris numbers its time
// points and channels so).
uint64_t countNumbered(hid_t file, const std::string& prefix) {
  uint64_t count = 0;
  while (openObject(file, prefix + std::to_string(count))) ++count;
  return count;
}

struct DatasetList {
  std::vector<std::string> volumes;  // "/path" of each dataset that is a volume
  std::vector<std::string> others;   // "/path (why not)" of the rest
};

DatasetList listDatasets(hid_t file, const std::string& givenAxes) {
  DatasetList list;
  struct Visit {
    hid_t file;
    DatasetList* list;
    const std::string& givenAxes;
  } visit{file, &list, givenAxes};
  // The link-info argument's type differs between HDF5 1.10 and 1.12; it is not used.
  const auto onLink = [](hid_t, const char* name, const auto*, void* data) -> herr_t {
    auto& v = *static_cast<Visit*>(data);
    const std::string path = std::string("/") + name;
    const Handle object = openObject(v.file, path);
    if (!object || H5Iget_type(object.get()) != H5I_DATASET) return 0;
    const VolumeShape shape = volumeShapeOf(object.get(), v.givenAxes);
    if (shape.problem.empty())
      v.list->volumes.push_back(path);
    else
      v.list->others.push_back(path + " (" + shape.problem + ")");
    return 0;
  };
  H5Lvisit(file, H5_INDEX_NAME, H5_ITER_INC, onLink, &visit);
  H5Eclear2(H5E_DEFAULT);
  return list;
}

// An attribute's values as numbers: numeric elements, or a string of one (Imaris writes its numbers as
// arrays of characters). Empty when the attribute is missing or neither.
std::vector<double> attributeNumbers(hid_t object, const char* name) {
  if (H5Aexists(object, name) <= 0) {
    H5Eclear2(H5E_DEFAULT);
    return {};
  }
  const Handle attribute(H5Aopen(object, name, H5P_DEFAULT), H5Aclose);
  const Handle type(attribute ? H5Aget_type(attribute.get()) : -1, H5Tclose);
  const Handle space(attribute ? H5Aget_space(attribute.get()) : -1, H5Sclose);
  if (!type || !space) {
    H5Eclear2(H5E_DEFAULT);
    return {};
  }
  const hssize_t count = H5Sget_simple_extent_npoints(space.get());
  const H5T_class_t kind = H5Tget_class(type.get());
  if (count <= 0 || count > 64) return {};
  if (kind == H5T_INTEGER || kind == H5T_FLOAT) {
    std::vector<double> values(static_cast<size_t>(count));
    if (H5Aread(attribute.get(), H5T_NATIVE_DOUBLE, values.data()) < 0) {
      H5Eclear2(H5E_DEFAULT);
      return {};
    }
    return values;
  }
  if (kind == H5T_STRING && H5Tis_variable_str(type.get()) == 0) {
    std::string text(size_t(count) * H5Tget_size(type.get()), '\0');
    if (H5Aread(attribute.get(), type.get(), text.data()) < 0) {
      H5Eclear2(H5E_DEFAULT);
      return {};
    }
    text = text.c_str();  // up to the first NUL
    char* end = nullptr;
    const double value = std::strtod(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size()) return {};
    return {value};
  }
  return {};
}

// The filters of a chunked dataset that this HDF5 library cannot apply ("32001 (blosc)"), which it would
// only name once a read fails.
std::vector<std::string> missingFilters(hid_t dataset) {
  std::vector<std::string> missing;
  const Handle create(H5Dget_create_plist(dataset), H5Pclose);
  if (!create) return missing;
  const int filters = H5Pget_nfilters(create.get());
  for (int i = 0; i < filters; ++i) {
    unsigned flags = 0, config = 0;
    size_t values = 0;
    char name[256] = {};
    const H5Z_filter_t id =
        H5Pget_filter2(create.get(), unsigned(i), &flags, &values, nullptr, sizeof name, name, &config);
    if (id >= 0 && H5Zfilter_avail(id) <= 0)
      missing.push_back(std::to_string(id) + (name[0] ? std::string(" (") + name + ")" : ""));
  }
  H5Eclear2(H5E_DEFAULT);
  return missing;
}

bool isPrime(size_t n) {
  if (n < 2) return false;
  for (size_t d = 2; d * d <= n; ++d)
    if (n % d == 0) return false;
  return true;
}

// A dataset access list whose chunk cache holds a layer of the chunks of `dataset` (see kMaxChunkCacheBytes).
Handle chunkCacheFor(hid_t dataset, const VolumeShape& shape, size_t sampleBytes) {
  Handle access(H5Pcreate(H5P_DATASET_ACCESS), H5Pclose);
  const Handle create(H5Dget_create_plist(dataset), H5Pclose);
  if (!access || !create || H5Pget_layout(create.get()) != H5D_CHUNKED) return access;
  std::vector<hsize_t> chunk(shape.extent.size());
  if (H5Pget_chunk(create.get(), int(chunk.size()), chunk.data()) != int(chunk.size())) {
    H5Eclear2(H5E_DEFAULT);
    return access;
  }
  size_t chunkBytes = sampleBytes, layerChunks = 1;
  for (hsize_t n : chunk) chunkBytes *= size_t(n);
  for (int i = 1; i < 3; ++i) {
    const size_t a = size_t(shape.axes[size_t(i)]);
    layerChunks *= size_t((shape.extent[a] + chunk[a] - 1) / chunk[a]);
  }
  const size_t bytes = std::min(kMaxChunkCacheBytes, std::max(chunkBytes, layerChunks * chunkBytes));
  // The library's advice: a prime, about 100 times the chunks cached (a million slots, 8 MiB, at most).
  size_t slots = std::clamp<size_t>(100 * (bytes / std::max<size_t>(chunkBytes, 1)), 521, size_t(1) << 20);
  while (!isPrime(slots)) ++slots;
  H5Pset_chunk_cache(access.get(), slots, bytes, 1.0);
  return access;
}

// How a chunked dataset whose filters ropecast decodes itself (none, deflate once, shuffle, in any order) is
// read: a layer's chunks as the file stores them, a few per core at a time, through the library (which is
// serial), then decoded and placed on one thread per core (store/chunk_layer.h). Absent for other datasets
// (other filters, a checksum, samples the library converts), which the library reads.
struct ChunkedReading {
  std::vector<hsize_t> chunk;         // samples per axis, in HDF5's order
  std::vector<H5Z_filter_t> filters;  // in the order they were applied when written
  bool bigEndian = false;             // the samples' byte order in the file
  std::vector<std::byte> fill;        // one sample of the dataset's fill value (unwritten chunks)
};

std::optional<ChunkedReading> chunkedReadingOf(hid_t dataset, const VolumeShape& shape) {
  const Handle create(H5Dget_create_plist(dataset), H5Pclose);
  const Handle fileType(H5Dget_type(dataset), H5Tclose);
  if (!create || !fileType || H5Pget_layout(create.get()) != H5D_CHUNKED) return std::nullopt;
  ChunkedReading r;
  r.chunk.resize(shape.extent.size());
  if (H5Pget_chunk(create.get(), int(r.chunk.size()), r.chunk.data()) != int(r.chunk.size()))
    return std::nullopt;
  const int filters = H5Pget_nfilters(create.get());
  for (int i = 0; i < filters; ++i) {
    unsigned flags = 0, config = 0;
    size_t values = 0;
    const H5Z_filter_t id =
        H5Pget_filter2(create.get(), unsigned(i), &flags, &values, nullptr, 0, nullptr, &config);
    if (id != H5Z_FILTER_DEFLATE && id != H5Z_FILTER_SHUFFLE) return std::nullopt;
    r.filters.push_back(id);
  }
  // One deflate at most: a second one's output size is not known before it is inflated.
  if (std::count(r.filters.begin(), r.filters.end(), H5Z_FILTER_DEFLATE) > 1) return std::nullopt;
  // The file's samples must be the memory type's but for their byte order.
  const hid_t memoryType = memoryTypeOf(*shape.type);
  const Handle ordered(H5Tcopy(memoryType), H5Tclose);
  const H5T_order_t order = H5Tget_order(fileType.get());
  if (!ordered || (order != H5T_ORDER_LE && order != H5T_ORDER_BE) ||
      H5Tset_order(ordered.get(), order) < 0 || H5Tequal(fileType.get(), ordered.get()) <= 0)
    return std::nullopt;
  r.bigEndian = order == H5T_ORDER_BE;
  r.fill.assign(bytesPerSample(*shape.type), std::byte{0});
  H5D_fill_value_t defined = H5D_FILL_VALUE_UNDEFINED;
  if (H5Pfill_value_defined(create.get(), &defined) >= 0 && defined != H5D_FILL_VALUE_UNDEFINED &&
      H5Pget_fill_value(create.get(), memoryType, r.fill.data()) < 0)
    return std::nullopt;
  return r;
}

// A chunk as the file stores it: its bytes and which filters were skipped for it (bit i: filter i), or none
// where it was never written (the fill value).
struct StoredChunk {
  bool written = false;
  uint32_t skipped = 0;
  std::vector<std::byte> bytes;
};

// A worker's buffers, kept from chunk to chunk.
struct ChunkBuffers {
  std::vector<std::byte> decoded, scratch;
};

class Hdf5Source final : public VolumeSource {
 public:
  // `chunked`: how the dataset's chunks are read as stored (chunkedReadingOf), or none for the library's
  // reads.
  Hdf5Source(VolumeInfo info, Handle file, Handle dataset, VolumeShape shape, std::string where,
             std::optional<ChunkedReading> chunked)
      : info_(std::move(info)),
        file_(std::move(file)),
        dataset_(std::move(dataset)),
        shape_(std::move(shape)),
        where_(std::move(where)),
        chunked_(std::move(chunked)) {
    if (chunked_)
      layer_.emplace(info_.dims, info_.type, chunked_->chunk[size_t(shape_.axes[0])], kMaxChunkCacheBytes);
  }

  const VolumeInfo& info() const override { return info_; }

 protected:
  void readSlices(uint32_t z0, uint32_t count, std::span<std::byte> out) override {
    silenceHdf5Errors();
    if (layer_) {
      layer_->read(z0, count, out, [this](uint64_t z) { decodeLayer(z); });
      return;
    }
    std::vector<hsize_t> start(shape_.picked.begin(), shape_.picked.end()), extent(shape_.extent.size(), 1);
    start[size_t(shape_.axes[0])] = z0;
    extent[size_t(shape_.axes[0])] = count;
    extent[size_t(shape_.axes[1])] = info_.dims.y;
    extent[size_t(shape_.axes[2])] = info_.dims.x;
    const Handle fileSpace(H5Dget_space(dataset_.get()), H5Sclose);
    // The memory space has the selection's shape: a flat one makes the library copy sample by sample.
    const Handle memorySpace(H5Screate_simple(int(extent.size()), extent.data(), nullptr), H5Sclose);
    if (!fileSpace || !memorySpace ||
        H5Sselect_hyperslab(fileSpace.get(), H5S_SELECT_SET, start.data(), nullptr, extent.data(), nullptr) <
            0 ||
        H5Dread(dataset_.get(), memoryTypeOf(*shape_.type), memorySpace.get(), fileSpace.get(), H5P_DEFAULT,
                out.data()) < 0)
      throw Error(where_ + ": reading slices " + std::to_string(z0) + " to " +
                  std::to_string(z0 + count - 1) + " failed: " + hdf5Problem());
  }

 private:
  // The chunk (cx, cy) of chunk layer `layer`: where it starts, per axis in HDF5's order.
  std::vector<hsize_t> chunkOffset(uint64_t layer, uint64_t cy, uint64_t cx) const {
    std::vector<hsize_t> offset(shape_.extent.size(), 0);
    const auto& chunk = chunked_->chunk;
    for (size_t a = 0; a < offset.size(); ++a) offset[a] = shape_.picked[a] - shape_.picked[a] % chunk[a];
    offset[size_t(shape_.axes[0])] = layer * chunk[size_t(shape_.axes[0])];
    offset[size_t(shape_.axes[1])] = cy * chunk[size_t(shape_.axes[1])];
    offset[size_t(shape_.axes[2])] = cx * chunk[size_t(shape_.axes[2])];
    return offset;
  }

  // "the chunk at (0, 64, 128)", for messages.
  static std::string chunkText(const std::vector<hsize_t>& offset) {
    std::string text = "the chunk at (";
    for (size_t a = 0; a < offset.size(); ++a) text += (a ? ", " : "") + std::to_string(offset[a]);
    return text + ")";
  }

  // Reads the chunks of z's chunk layer that reach the slices the layer holds from z on, as stored (the
  // library is serial), then decodes and places them on worker threads.
  void decodeLayer(uint64_t z) {
    const uint64_t layer = layer_->begin(z);
    const auto& chunk = chunked_->chunk;
    const glm::u64vec3 box(chunk[size_t(shape_.axes[2])], chunk[size_t(shape_.axes[1])],
                           chunk[size_t(shape_.axes[0])]);
    // Chunks that only pad the dataset past the volume (Imaris) are not read.
    const uint64_t across = (info_.dims.x + box.x - 1) / box.x, down = (info_.dims.y + box.y - 1) / box.y;
    size_t chunkBytes = bytesPerSample(info_.type);
    for (const hsize_t n : chunk) chunkBytes *= size_t(n);
    std::vector<uint64_t> strides(chunk.size(), 1);
    for (size_t a = chunk.size() - 1; a-- > 0;) strides[a] = strides[a + 1] * chunk[a + 1];
    const glm::u64vec3 stride(strides[size_t(shape_.axes[2])], strides[size_t(shape_.axes[1])],
                              strides[size_t(shape_.axes[0])]);
    // The picked time point's and channel's samples within a chunk.
    uint64_t first = 0;
    for (size_t a = 0; a < chunk.size(); ++a) first += shape_.picked[a] % chunk[a] * strides[a];
    const size_t pickedAt = size_t(first) * bytesPerSample(info_.type);
    // In batches of a few chunks per core, so that the stored bytes held stay a few chunks'.
    const uint64_t chunks = across * down;
    const uint64_t batch = std::min<uint64_t>(chunks, 4 * std::max(1u, std::thread::hardware_concurrency()));
    std::vector<StoredChunk> stored(batch);
    for (uint64_t first = 0; first < chunks; first += batch) {
      const uint64_t count = std::min(batch, chunks - first);
      for (uint64_t j = 0; j < count; ++j) {
        const std::vector<hsize_t> offset = chunkOffset(layer, (first + j) / across, (first + j) % across);
        StoredChunk& c = stored[j];
        hsize_t bytes = 0;
        c.written = H5Dget_chunk_storage_size(dataset_.get(), offset.data(), &bytes) >= 0 && bytes > 0;
        if (!c.written) {
          H5Eclear2(H5E_DEFAULT);  // never written: the fill value
          continue;
        }
        c.bytes.resize(bytes);
        if (H5Dread_chunk(dataset_.get(), H5P_DEFAULT, offset.data(), &c.skipped, c.bytes.data()) < 0)
          throw Error(where_ + ": reading " + chunkText(offset) + " failed: " + hdf5Problem());
      }
      runOnWorkers<ChunkBuffers>(count, [&](uint64_t j, ChunkBuffers& b) -> std::string {
        const uint64_t i = first + j;
        b.decoded.resize(chunkBytes);
        if (const std::string problem = decodeChunk(stored[j], b); !problem.empty())
          return where_ + ": " + chunkText(chunkOffset(layer, i / across, i % across)) + " " + problem;
        layer_->place(b.decoded.data() + pickedAt, stride, glm::u64vec3(i % across, i / across, layer) * box,
                      box);
        return "";
      });
    }
  }

  // Decodes a stored chunk into b.decoded (its size set): the filters undone in reverse, those skipped for it
  // left out, the samples in native byte order. Returns the problem, if any.
  std::string decodeChunk(StoredChunk& stored, ChunkBuffers& b) const {
    const size_t width = chunked_->fill.size(), chunkBytes = b.decoded.size();
    if (!stored.written) {
      for (size_t i = 0; i + width <= chunkBytes; i += width)
        std::memcpy(b.decoded.data() + i, chunked_->fill.data(), width);
      return "";
    }
    std::span<const std::byte> data = stored.bytes;
    for (size_t f = chunked_->filters.size(); f-- > 0;) {
      if (stored.skipped & (1u << f)) continue;
      // A shuffle keeps the size (a compressed stream's too); the one deflate gives the chunk's bytes.
      std::vector<std::byte>& into = data.data() == b.scratch.data() ? b.decoded : b.scratch;
      const bool inflating = chunked_->filters[f] == H5Z_FILTER_DEFLATE;
      into.resize(inflating ? chunkBytes : data.size());
      if (inflating) {
        if (!inflateExactly(data, into, false))
          return "is damaged or of another size (deflate); expected " + std::to_string(chunkBytes) + " bytes";
      } else {
        unshuffleBytes(data, into, width);
      }
      data = into;
    }
    if (data.size() != chunkBytes)
      return "holds " + std::to_string(data.size()) + " bytes; expected " + std::to_string(chunkBytes);
    if (data.data() != b.decoded.data()) {
      b.decoded.resize(chunkBytes);
      std::memcpy(b.decoded.data(), data.data(), chunkBytes);
    }
    if (chunked_->bigEndian) samplesToNative(b.decoded, info_.type, true);
    return "";
  }

  VolumeInfo info_;
  Handle file_, dataset_;
  VolumeShape shape_;
  std::string where_;  // "HDF5 file F, dataset /D", for messages
  std::optional<ChunkedReading> chunked_;
  std::optional<ChunkLayer> layer_;  // with chunked_
};

}  // namespace

namespace {

// A view of a BigDataViewer dataset, read through its XML: what the XML says that the HDF5 file does not.
struct BdvView {
  std::string xml;
  std::optional<glm::dvec3> voxelSize;
  PickedVolume picked;  // of its time points and view setups
};

std::unique_ptr<VolumeSource> openDataset(const std::string& path, std::string datasetPath,
                                          const SourceOptions& options, const std::optional<BdvView>& bdv);

// A BigDataViewer XML's view: one of its time points (--time, in the XML's order) and view setups
// (--channel), by default the first of each.
std::unique_ptr<VolumeSource> openBdvXml(const std::string& xml, const SourceOptions& options) {
  const BdvDataset dataset = parseBdvXml(readTextInput(xml, "BigDataViewer XML " + xml), xml);
  if (dataset.format != BdvImageFormat::Hdf5)
    throw Error("BigDataViewer XML " + xml +
                ": its images are not in an HDF5 file (the N5 source reads them)");
  const PickedVolume picked = pickBdvView(dataset, options, xml);
  const BdvSetup& setup = dataset.setups[picked.channel];
  SourceOptions picking = options;  // the dataset itself is one volume
  picking.timePoint.reset();
  picking.channel.reset();
  return openDataset(dataset.images, bdvCellsPath(dataset.timepoints[picked.timePoint], setup.id), picking,
                     BdvView{xml, setup.voxelSize, picked});
}

}  // namespace

std::unique_ptr<VolumeSource> openHdf5Source(const std::string& spec, const SourceOptions& options) {
  silenceHdf5Errors();
  if (lowerExtension(spec) == ".xml") {
    if (!options.axes.empty())
      throw UsageError(spec +
                       ": --axes: a BigDataViewer dataset names its axes itself (--axes is for arrays "
                       "that do not)");
    return openBdvXml(spec, options);
  }
  const std::optional<Hdf5Spec> parts = hdf5SpecOf(spec);
  if (!parts) throw Error(spec + ": not an HDF5 file (nor FILE:/DATASET of one)");
  return openDataset(parts->file, parts->dataset, options, std::nullopt);
}

namespace {

std::unique_ptr<VolumeSource> openDataset(const std::string& path, std::string datasetPath,
                                          const SourceOptions& options, const std::optional<BdvView>& bdv) {
  const std::string inFile = "HDF5 file " + path;
  if (!startsWithHdf5Signature(path) && H5Fis_hdf5(path.c_str()) <= 0) {
    H5Eclear2(H5E_DEFAULT);
    throw Error(inFile + ": not an HDF5 file (no HDF5 signature" +
                (lowerExtension(path) == ".hdf" ? "; HDF4 files are not read)" : ")"));
  }
  Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!file) throw Error(inFile + ": cannot be opened: " + hdf5Problem());

  if (!datasetPath.empty() && datasetPath.front() != '/') datasetPath = "/" + datasetPath;
  PickedVolume picked;
  bool imaris = false;
  if (datasetPath.empty()) {
    if (openObject(file.get(), imarisDataset(0, 0))) {
      if (!options.axes.empty())
        throw UsageError(inFile +
                         ": --axes: an Imaris file names its axes itself (--axes is for arrays that "
                         "do not)");
      imaris = true;
      picked = pickVolume(
          options, {countNumbered(file.get(), kImarisTimePoint), countNumbered(file.get(), imarisChannel(0))},
          "Imaris file " + path);
      datasetPath = imarisDataset(picked.timePoint, picked.channel);
    } else {
      const DatasetList list = listDatasets(file.get(), options.axes);
      if (list.volumes.size() > 1)
        throw Error(inFile + ": holds " + std::to_string(list.volumes.size()) +
                    " datasets that are volumes: " + listedNames(list.volumes) + "; name one, as in " + path +
                    ":" + list.volumes.front());
      if (list.volumes.empty())
        throw Error(inFile + ": holds no dataset that is a volume (a 3D array of numbers)" +
                    (list.others.empty() ? std::string(", and no dataset at all")
                                         : "; its datasets: " + listedNames(list.others)));
      datasetPath = list.volumes.front();
    }
  }
  const std::string where = inFile + ", dataset " + datasetPath;
  Handle object = openObject(file.get(), datasetPath);
  if (!object) throw Error(inFile + ": has no object " + datasetPath);
  if (const H5I_type_t kind = H5Iget_type(object.get()); kind != H5I_DATASET)
    throw Error(where + (kind == H5I_GROUP ? ": is a group, not a dataset (name a dataset inside it)"
                                           : ": is not a dataset"));
  VolumeShape shape = volumeShapeOf(object.get(), options.axes);
  if (!shape.problem.empty()) throw Error(where + ": not a volume: " + shape.problem);
  if (bdv) {
    picked = bdv->picked;
  } else if (!imaris) {  // a dataset whose axistags name a time or channel axis: one of its volumes
    picked = pickVolume(options,
                        {shape.time < 0 ? 1 : shape.extent[size_t(shape.time)],
                         shape.channel < 0 ? 1 : shape.extent[size_t(shape.channel)]},
                        where);
    if (shape.time >= 0) shape.picked[size_t(shape.time)] = picked.timePoint;
    if (shape.channel >= 0) shape.picked[size_t(shape.channel)] = picked.channel;
  }
  if (const std::vector<std::string> missing = missingFilters(object.get()); !missing.empty())
    throw Error(where + ": compressed with HDF5 filter " + listedNames(missing) +
                ", which this HDF5 library lacks (filter plugins are found through HDF5_PLUGIN_PATH)");

  VolumeInfo info;
  info.type = *shape.type;
  // BigDataViewer keeps unsigned 16-bit images in datasets of signed ones (Java has no unsigned types): the
  // same bytes, read as unsigned.
  if ((bdv || isBdvCellsPath(datasetPath)) && info.type == SampleType::Int16) info.type = SampleType::UInt16;
  const auto extentOf = [&](int i) { return shape.extent[size_t(shape.axes[size_t(i)])]; };
  const glm::u64vec3 extent(extentOf(2), extentOf(1), extentOf(0));
  glm::dvec3 spacing(1.0);
  // A dataset whose chunks ropecast reads as stored needs no chunk cache of the library's.
  std::optional<ChunkedReading> chunked = chunkedReadingOf(object.get(), shape);
  H5Eclear2(H5E_DEFAULT);
  const Handle access = chunked ? Handle() : chunkCacheFor(object.get(), shape, bytesPerSample(info.type));
  object = Handle();  // a dataset opened twice shares its first opening's chunk cache
  Handle dataset(H5Dopen2(file.get(), datasetPath.c_str(), access ? access.get() : H5P_DEFAULT), H5Dclose);
  if (!dataset) throw Error(where + ": cannot be opened: " + hdf5Problem());

  glm::u64vec3 dims = extent;
  if (imaris) {
    // Imaris pads its datasets to whole chunks: the image is the box its info group states, whose extents
    // give the spacing.
    if (const Handle image = openObject(file.get(), kImarisImageInfo)) {
      const char* names[] = {"X", "Y", "Z"};
      for (int a = 0; a < 3; ++a) {
        const std::vector<double> n = attributeNumbers(image.get(), names[a]);
        if (n.size() == 1 && n[0] >= 1 && n[0] <= double(extent[a])) dims[a] = uint64_t(n[0]);
      }
      for (int a = 0; a < 3; ++a) {
        const std::string axis = std::to_string(a);
        const std::vector<double> lo = attributeNumbers(image.get(), ("ExtMin" + axis).c_str());
        const std::vector<double> hi = attributeNumbers(image.get(), ("ExtMax" + axis).c_str());
        if (lo.size() == 1 && hi.size() == 1 && std::isfinite(hi[0] - lo[0]) && hi[0] > lo[0])
          spacing[a] = (hi[0] - lo[0]) / double(dims[a]);
      }
    }
  } else if (bdv) {
    if (bdv->voxelSize) spacing = *bdv->voxelSize;
  } else if (const std::vector<double> size = attributeNumbers(dataset.get(), "element_size_um");
             size.size() == 3 || size.size() == shape.extent.size()) {
    const auto along = [&](int i) {
      return size.size() == 3 ? size[size_t(i)] : size[size_t(shape.axes[size_t(i)])];
    };
    spacing = {along(2), along(1), along(0)};
  }
  if (dims.x > kMaxDimsPerAxis || dims.y > kMaxDimsPerAxis || dims.z > kMaxDimsPerAxis)
    throw Error(where + ": " + formatExtent(shape.extent) + " samples; a store holds at most " +
                std::to_string(kMaxDimsPerAxis) + " per axis");
  info.dims = glm::u32vec3(dims);
  if (!isValidSpacing(spacing)) {
    info.notes.push_back(where + ": its voxel size (" + formatSpacing(spacing) +
                         ") is not a valid spacing; 1,1,1 is used");
    spacing = glm::dvec3(1.0);
  }
  info.spacing = options.spacing.value_or(spacing);
  info.description = (bdv ? "bdv:" + bdv->xml + " (" : "hdf5:") + path + ":" + datasetPath + (bdv ? ")" : "");
  describePicked(info, picked);
  return std::make_unique<Hdf5Source>(std::move(info), std::move(file), std::move(dataset), std::move(shape),
                                      where, std::move(chunked));
}

}  // namespace
}  // namespace ropecast
