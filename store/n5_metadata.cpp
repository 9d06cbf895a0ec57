#include "store/n5_metadata.h"

#include <algorithm>
#include <cctype>

#include <nlohmann/json.hpp>

#include "core/error.h"

namespace ropecast {
namespace {

using nlohmann::json;

constexpr uint64_t kMaxBlockBytes = uint64_t(1) << 31;

json parseObject(std::string_view text, const std::string& where) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {
    throw Error(where + ": not JSON (" + e.what() + ")");
  }
  if (!j.is_object()) throw Error(where + ": not a JSON object of attributes");
  return j;
}

// A list of N5's (fastest axis first), slowest first.
template <typename T>
std::vector<T> slowestFirst(const json& list, const char* key, const std::string& where, const char* what) {
  const auto refuse = [&] {
    throw Error(where + ": '" + key + "' must be " + what + ", got " + list.dump());
  };
  if (!list.is_array() || list.empty()) refuse();
  std::vector<T> values;
  for (const json& v : list) {
    if constexpr (std::is_integral_v<T>) {
      if (!v.is_number_unsigned()) refuse();
    } else if (!v.is_number()) {
      refuse();
    }
    values.push_back(v.get<T>());
  }
  std::reverse(values.begin(), values.end());
  return values;
}

SampleType readDataType(const json& j, const std::string& where) {
  const json d = j.value("dataType", json());
  const std::string name = d.is_string() ? d.get<std::string>() : d.dump();
  for (const SampleType type :
       {SampleType::UInt8, SampleType::Int8, SampleType::UInt16, SampleType::Int16, SampleType::UInt32,
        SampleType::Int32, SampleType::Float32, SampleType::Float64})
    if (name == sampleTypeName(type)) return type;
  throw Error(where + ": 'dataType' " + d.dump() +
              " is not read; read are 8-, 16- and 32-bit integers and 32- and 64-bit floats");
}

// `compression` (N5 1.0 on: an object with a type) or `compressionType` (before: a name); raw when neither.
std::optional<Compressor> readCompression(const json& j, const std::string& where) {
  json type = j.value("compressionType", json("raw"));
  bool zlib = false;
  if (j.contains("compression")) {
    const json& c = j.at("compression");
    if (!c.is_object() || !c.contains("type"))
      throw Error(where + ": 'compression' " + c.dump() + " has no 'type'");
    type = c.at("type");
    const json useZlib = c.value("useZlib", json(false));
    if (!useZlib.is_boolean())
      throw Error(where + ": 'compression' 'useZlib' must be true or false, got " + useZlib.dump());
    zlib = useZlib.get<bool>();
  }
  const std::string name = type.is_string() ? type.get<std::string>() : type.dump();
  if (name == "raw") return std::nullopt;
  const std::pair<const char*, Compressor> known[] = {{"gzip", zlib ? Compressor::Zlib : Compressor::Gzip},
                                                      {"bzip2", Compressor::Bzip2},
                                                      {"xz", Compressor::Xz},
                                                      {"lz4", Compressor::Lz4Blocks},
                                                      {"blosc", Compressor::Blosc},
                                                      {"zstd", Compressor::Zstd}};
  for (const auto& [n, compressor] : known)
    if (name == n) return compressor;
  throw Error(where + ": compression '" + name +
              "' is not read (raw, gzip, bzip2, xz, lz4, blosc and zstd are)");
}

uint64_t bigEndian(const std::byte* p, size_t bytes) {
  uint64_t v = 0;
  for (size_t i = 0; i < bytes; ++i) v = v << 8 | std::to_integer<uint64_t>(p[i]);
  return v;
}

}  // namespace

bool isN5Dataset(std::string_view attributes, const std::string& where) {
  return parseObject(attributes, where).contains("dimensions");
}

N5Dataset parseN5Dataset(std::string_view attributes, const std::string& where) {
  const json j = parseObject(attributes, where);
  if (!j.contains("dimensions"))
    throw Error(where + ": no 'dimensions' (a group's attributes, not a dataset's)");
  if (!j.contains("blockSize")) throw Error(where + ": no 'blockSize'");
  N5Dataset d;
  d.shape = slowestFirst<uint64_t>(j.at("dimensions"), "dimensions", where, "a list of whole numbers");
  d.blockSize = slowestFirst<uint64_t>(j.at("blockSize"), "blockSize", where, "a list of whole numbers");
  if (d.blockSize.size() != d.shape.size())
    throw Error(where + ": 'blockSize' has " + std::to_string(d.blockSize.size()) +
                " axes and 'dimensions' " + std::to_string(d.shape.size()));
  if (std::ranges::count(d.blockSize, 0) > 0) throw Error(where + ": 'blockSize' has an axis of 0 samples");
  d.type = readDataType(j, where);
  // A block is read whole into memory: 2 GiB keeps one far from exhausting it and its sizes in int.
  uint64_t bytes = bytesPerSample(d.type);
  for (const uint64_t b : d.blockSize)
    if (b > kMaxBlockBytes || (bytes *= b) > kMaxBlockBytes)
      throw Error(where + ": blocks of more than 2 GiB are not read");
  d.compressor = readCompression(j, where);
  return d;
}

N5Calibration parseN5Calibration(std::string_view attributes, const std::string& where) {
  const json j = parseObject(attributes, where);
  N5Calibration c;
  if (j.contains("transform")) {  // COSEM: {"axes": ["z", "y", "x"], "ordering": "C", "scale", "translate"}
    const json& t = j.at("transform");
    if (!t.is_object()) throw Error(where + ": 'transform' is not an object: " + t.dump());
    // Lists in C order (slowest first) as they stand; in F order reversed, as N5's own.
    const json ordering = t.value("ordering", json("C"));
    if (ordering != "C" && ordering != "F")
      throw Error(where + ": 'transform' 'ordering' must be \"C\" or \"F\", got " + ordering.dump());
    const bool fortran = ordering == "F";
    const auto inOrder = [&](const char* key) {
      std::vector<double> v =
          slowestFirst<double>(t.at(key), key, where + " 'transform'", "a list of numbers");
      if (!fortran) std::reverse(v.begin(), v.end());
      return v;
    };
    if (t.contains("axes")) {
      const json& axes = t.at("axes");
      if (!axes.is_array() || !std::ranges::all_of(axes, [](const json& a) { return a.is_string(); }))
        throw Error(where + ": 'transform' 'axes' must be a list of names, got " + axes.dump());
      for (const json& a : axes) {
        std::string name = a.get<std::string>();
        std::ranges::transform(name, name.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
        c.axisNames.push_back(name);
      }
      if (fortran) std::reverse(c.axisNames.begin(), c.axisNames.end());
    }
    if (t.contains("scale")) c.scale = inOrder("scale");
    if (t.contains("translate")) c.translation = inOrder("translate");
    if (!c.axisNames.empty() && c.scale && c.scale->size() != c.axisNames.size())
      throw Error(where + ": 'transform' names " + std::to_string(c.axisNames.size()) + " axes and scales " +
                  std::to_string(c.scale->size()));
    c.attribute = "transform";
    return c;
  }
  if (j.contains("pixelResolution")) {  // N5 Viewer: [x, y, z] or {"dimensions": [x, y, z], "unit": "um"}
    const json& r = j.at("pixelResolution");
    c.scale = slowestFirst<double>(r.is_object() ? r.value("dimensions", json()) : r, "pixelResolution",
                                   where, "a list of numbers");
    c.attribute = "pixelResolution";
  } else if (j.contains("resolution")) {  // Paintera, BigCAT: [x, y, z]
    c.scale = slowestFirst<double>(j.at("resolution"), "resolution", where, "a list of numbers");
    c.attribute = "resolution";
  }
  if (j.contains("offset") && !c.attribute.empty())
    c.translation = slowestFirst<double>(j.at("offset"), "offset", where, "a list of numbers");
  return c;
}

std::optional<std::vector<double>> parseN5DownsamplingFactors(std::string_view attributes,
                                                              const std::string& where) {
  const json j = parseObject(attributes, where);
  if (!j.contains("downsamplingFactors")) return std::nullopt;
  return slowestFirst<double>(j.at("downsamplingFactors"), "downsamplingFactors", where, "a list of numbers");
}

std::optional<std::string> n5MultiscaleDataset(std::string_view attributes, const std::string& where) {
  const json j = parseObject(attributes, where);
  if (!j.contains("multiscales")) return std::nullopt;
  const json& m = j.at("multiscales");
  if (!m.is_array() || m.empty() || !m[0].is_object() || !m[0].contains("datasets") ||
      !m[0].at("datasets").is_array() || m[0].at("datasets").empty())
    throw Error(where + ": 'multiscales' lists no datasets");
  const json& first = m[0].at("datasets")[0];
  if (!first.is_object() || !first.contains("path") || !first.at("path").is_string())
    throw Error(where + ": the first multiscale dataset has no 'path': " + first.dump());
  return first.at("path").get<std::string>();
}

std::string parseN5BlockHeader(std::span<const std::byte> block, size_t rank, N5BlockHeader& header) {
  if (block.size() < 4) return "is too short for a block header (" + std::to_string(block.size()) + " bytes)";
  const uint64_t mode = bigEndian(block.data(), 2), axes = bigEndian(block.data() + 2, 2);
  if (mode == 2) return "is an object block (mode 2), not samples";
  if (mode > 2) return "has an unknown mode " + std::to_string(mode);
  if (axes != rank) return "has " + std::to_string(axes) + " axes; the dataset has " + std::to_string(rank);
  header.bytes = 4 + 4 * rank + (mode == 1 ? 4 : 0);
  if (block.size() < header.bytes)
    return "is too short for a block header of " + std::to_string(rank) + " axes (" +
           std::to_string(block.size()) + " bytes)";
  header.size.assign(rank, 0);
  uint64_t samples = 1;
  for (size_t a = 0; a < rank; ++a) {
    const uint64_t size = bigEndian(block.data() + 4 + 4 * a, 4);
    header.size[rank - 1 - a] = size;
    samples = size != 0 && samples > UINT64_MAX / size ? UINT64_MAX : samples * size;
  }
  if (mode == 1 && bigEndian(block.data() + 4 + 4 * rank, 4) != samples)
    return "holds " + std::to_string(bigEndian(block.data() + 4 + 4 * rank, 4)) + " samples in a block of " +
           std::to_string(samples);
  return "";
}

}  // namespace ropecast
