#include "store/zarr_metadata.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/header_text.h"

namespace ropecast {
namespace {

using nlohmann::json;

json parseJson(std::string_view text, const std::string& where) {
  try {
    return json::parse(text);
  } catch (const json::exception& e) {
    throw Error(where + ": not JSON (" + e.what() + ")");
  }
}

std::vector<uint64_t> readSizes(const json& j, const char* key, const std::string& where) {
  if (!j.contains(key)) throw Error(where + ": no '" + key + "'");
  const json& v = j.at(key);
  if (!v.is_array() || v.empty())
    throw Error(where + ": '" + key + "' must be a list of whole numbers, got " + v.dump());
  std::vector<uint64_t> sizes;
  for (const json& n : v) {
    if (!n.is_number_unsigned())
      throw Error(where + ": '" + key + "' must be a list of whole numbers, got " + v.dump());
    sizes.push_back(n.get<uint64_t>());
  }
  return sizes;
}

// numpy's type strings: byte order ('<', '>', '|'), kind, bytes.
void readDtype(const json& j, const std::string& where, ZarrArray& a) {
  if (!j.contains("dtype")) throw Error(where + ": no 'dtype'");
  const json& d = j.at("dtype");
  if (!d.is_string())
    throw Error(where + ": 'dtype' " + d.dump() + " is not one type (records are not read)");
  const std::string s = d.get<std::string>();
  const auto refuse = [&](const std::string& why) {
    throw Error(where + ": 'dtype' " + d.dump() + ": " + why +
                "; read are 8-, 16- and 32-bit integers and 32- and 64-bit floats");
  };
  if (s.size() != 3 || (s[0] != '<' && s[0] != '>' && s[0] != '|')) refuse("not a numpy type string");
  a.bigEndian = s[0] == '>';
  const char kind = s[1];
  const int bytes = s[2] - '0';
  if (kind == 'u' || kind == 'i') {
    if (bytes == 1)
      a.type = kind == 'u' ? SampleType::UInt8 : SampleType::Int8;
    else if (bytes == 2)
      a.type = kind == 'u' ? SampleType::UInt16 : SampleType::Int16;
    else if (bytes == 4)
      a.type = kind == 'u' ? SampleType::UInt32 : SampleType::Int32;
    else
      refuse(std::to_string(bytes * 8) + "-bit integers");
  } else if (kind == 'f') {
    if (bytes == 4)
      a.type = SampleType::Float32;
    else if (bytes == 8)
      a.type = SampleType::Float64;
    else
      refuse(std::to_string(bytes * 8) + "-bit floats");
  } else if (kind == 'b') {
    refuse("booleans");
  } else if (kind == 'c') {
    refuse("complex numbers");
  } else {
    refuse("not a number type");
  }
}

// numcodecs' LZMA formats: 1 .xz (its default), 2 .lzma, 3 raw (whose filters only the metadata would give).
void checkLzmaFormat(const json& configuration, const std::string& where) {
  const json format = configuration.value("format", json(1));
  if (!format.is_number_integer() || (format.get<int64_t>() != 1 && format.get<int64_t>() != 2))
    throw Error(where + ": compressor lzma of format " + format.dump() +
                " is not read (1, .xz, and 2, .lzma, are; 3 is raw LZMA data)");
}

void readCompressor(const json& j, const std::string& where, ZarrArray& a) {
  const json c = j.value("compressor", json());
  if (c.is_null()) return;
  if (!c.is_object() || !c.contains("id") || !c.at("id").is_string())
    throw Error(where + ": 'compressor' " + c.dump() + " has no 'id'");
  const std::string id = c.at("id").get<std::string>();
  if (id == "blosc")
    a.codecs = {ZarrCodec::Blosc};
  else if (id == "zlib")
    a.codecs = {ZarrCodec::Zlib};
  else if (id == "gzip")
    a.codecs = {ZarrCodec::Gzip};
  else if (id == "zstd")
    a.codecs = {ZarrCodec::Zstd};
  else if (id == "lz4")
    a.codecs = {ZarrCodec::Lz4};
  else if (id == "bz2")
    a.codecs = {ZarrCodec::Bz2};
  else if (id == "lzma") {
    checkLzmaFormat(c, where);
    a.codecs = {ZarrCodec::Lzma};
  } else
    throw Error(where + ": compressor '" + id +
                "' is not read (blosc, zlib, gzip, zstd, lz4, lzma and bz2 are)");
}

// v3's data type names.
SampleType readDataType(const json& j, const std::string& where) {
  const json d = j.value("data_type", json());
  const std::string name = d.is_string() ? d.get<std::string>() : d.dump();
  const std::pair<const char*, SampleType> known[] = {
      {"uint8", SampleType::UInt8},     {"int8", SampleType::Int8},      {"uint16", SampleType::UInt16},
      {"int16", SampleType::Int16},     {"uint32", SampleType::UInt32},  {"int32", SampleType::Int32},
      {"float32", SampleType::Float32}, {"float64", SampleType::Float64}};
  for (const auto& [n, type] : known)
    if (name == n) return type;
  throw Error(where + ": 'data_type' " + d.dump() +
              " is not read; read are 8-, 16- and 32-bit integers and 32- and 64-bit floats");
}

// The name of a v3 codec, and its configuration (an empty object when it has none).
std::pair<std::string, json> codecOf(const json& c, const std::string& where) {
  if (c.is_string()) return {c.get<std::string>(), json::object()};
  if (!c.is_object() || !c.contains("name") || !c.at("name").is_string())
    throw Error(where + ": a codec without a name: " + c.dump());
  json configuration = c.value("configuration", json::object());
  if (!configuration.is_object())
    throw Error(where + ": codec " + c.at("name").dump() + " has a 'configuration' that is not an object");
  return {c.at("name").get<std::string>(), std::move(configuration)};
}

bool bigEndianOf(const json& configuration, const std::string& where) {
  const json endian = configuration.value("endian", json("little"));
  if (endian != json("little") && endian != json("big"))
    throw Error(where + ": the 'bytes' codec's 'endian' " + endian.dump() + " is neither little nor big");
  return endian == json("big");
}

void readSharding(const json& configuration, const std::string& where, ZarrArray& a);

// numcodecs' compressors as v3 codecs (numcodecs.zarr3, which zarr-python 3 writes: "numcodecs.zlib", ...),
// their configurations those of v2's compressors; nullopt for another name.
std::optional<ZarrCodec> numcodecsCodec(const std::string& name, const json& configuration,
                                        const std::string& where) {
  const std::pair<const char*, ZarrCodec> known[] = {
      {"numcodecs.zlib", ZarrCodec::Zlib}, {"numcodecs.gzip", ZarrCodec::Gzip},
      {"numcodecs.zstd", ZarrCodec::Zstd}, {"numcodecs.blosc", ZarrCodec::Blosc},
      {"numcodecs.lz4", ZarrCodec::Lz4},   {"numcodecs.lzma", ZarrCodec::Lzma},
      {"numcodecs.bz2", ZarrCodec::Bz2}};
  for (const auto& [n, codec] : known) {
    if (name != n) continue;
    if (codec == ZarrCodec::Lzma) checkLzmaFormat(configuration, where);
    return codec;
  }
  return std::nullopt;
}

// A v3 codec chain: one array-to-bytes codec (bytes, or sharding_indexed outside a shard; no array-to-array
// codec is read), then bytes-to-bytes codecs. Sets the codecs and byte order of `a`, or of its shards' inner
// chunks.
void readCodecs(const json& chain, const std::string& where, ZarrArray& a, bool inner) {
  if (!chain.is_array() || chain.empty()) throw Error(where + ": 'codecs' must be a list of codecs");
  std::vector<ZarrCodec>& codecs = inner ? a.sharding->codecs : a.codecs;
  for (size_t i = 0; i < chain.size(); ++i) {
    const auto [name, configuration] = codecOf(chain.at(i), where);
    if (i == 0) {
      if (name == "bytes")
        (inner ? a.sharding->bigEndian : a.bigEndian) = bigEndianOf(configuration, where);
      else if (name == "sharding_indexed" && !inner)
        readSharding(configuration, where, a);
      else
        throw Error(where + ": codec '" + name + "' is not read" +
                    (name == "transpose"          ? " (a transposed array)"
                     : name == "sharding_indexed" ? " (shards in shards)"
                                                  : " first (bytes and sharding_indexed are)"));
    } else if (name == "blosc") {
      codecs.push_back(ZarrCodec::Blosc);
    } else if (name == "gzip") {
      codecs.push_back(ZarrCodec::Gzip);
    } else if (name == "zstd") {
      codecs.push_back(ZarrCodec::Zstd);
    } else if (name == "crc32c") {
      codecs.push_back(ZarrCodec::Crc32c);
    } else if (const std::optional<ZarrCodec> numcodec = numcodecsCodec(name, configuration, where)) {
      codecs.push_back(*numcodec);
    } else {
      throw Error(
          where + ": codec '" + name +
          "' is not read (blosc, gzip, zstd, crc32c, and numcodecs' zlib, gzip, zstd, blosc, lz4, lzma "
          "and bz2 are)");
    }
  }
  if (std::count_if(codecs.begin(), codecs.end(), [](ZarrCodec c) { return c != ZarrCodec::Crc32c; }) > 1)
    throw Error(where + ": more than one compressor in a chain of codecs is not read");
}

void readSharding(const json& configuration, const std::string& where, ZarrArray& a) {
  a.sharding.emplace();
  a.sharding->chunks = readSizes(configuration, "chunk_shape", where);
  if (a.sharding->chunks.size() != a.chunks.size())
    throw Error(where + ": the shards' 'chunk_shape' has " + std::to_string(a.sharding->chunks.size()) +
                " axes and the array " + std::to_string(a.chunks.size()));
  for (size_t i = 0; i < a.chunks.size(); ++i)
    if (a.sharding->chunks[i] == 0 || a.chunks[i] % a.sharding->chunks[i] != 0)
      throw Error(where + ": the shards' inner chunks do not divide the shards");
  readCodecs(configuration.value("codecs", json()), where, a, true);
  for (const json& c : configuration.value("index_codecs", json::array())) {
    const auto [name, indexConfiguration] = codecOf(c, where);
    if (name == "crc32c")
      a.sharding->indexChecksum = true;
    else if (name != "bytes" || bigEndianOf(indexConfiguration, where))
      throw Error(where + ": shard index codec '" + name +
                  "' is not read (little-endian bytes and crc32c are)");
  }
  const json location = configuration.value("index_location", json("end"));
  if (location != json("end") && location != json("start"))
    throw Error(where + ": 'index_location' " + location.dump() + " is neither start nor end");
  a.sharding->indexAtEnd = location == json("end");
}

// A chunk is read whole into memory: 2 GiB keeps one far from exhausting it and its sizes in int.
void checkChunkSizes(const std::vector<uint64_t>& chunks, SampleType type, const std::string& where) {
  uint64_t bytes = bytesPerSample(type);
  for (uint64_t c : chunks) {
    if (c == 0) throw Error(where + ": a chunk shape holds 0");
    if (c > (uint64_t(1) << 31) || (bytes *= c) > (uint64_t(1) << 31))
      throw Error(where + ": chunks of more than 2 GiB are not read");
  }
}

double readFill(const json& j, const std::string& where) {
  const json f = j.value("fill_value", json());
  if (f.is_null()) return 0.0;
  if (f.is_number()) return f.get<double>();
  if (f.is_string()) {
    const std::string s = f.get<std::string>();
    if (s == "NaN") return std::numeric_limits<double>::quiet_NaN();
    if (s == "Infinity") return std::numeric_limits<double>::infinity();
    if (s == "-Infinity") return -std::numeric_limits<double>::infinity();
  }
  throw Error(where + ": 'fill_value' " + f.dump() + " is not a number");
}

}  // namespace

uint64_t ZarrArray::chunkSamples() const {
  uint64_t n = 1;
  for (uint64_t c : chunks) n *= c;
  return n;
}

ZarrArray parseZarrArray(std::string_view text, const std::string& where) {
  const json j = parseJson(text, where);
  if (!j.is_object()) throw Error(where + ": not a JSON object");
  if (j.value("zarr_format", json()) != json(2))
    throw Error(where + ": 'zarr_format' is " + j.value("zarr_format", json()).dump() + ", expected 2");
  ZarrArray a;
  a.shape = readSizes(j, "shape", where);
  a.chunks = readSizes(j, "chunks", where);
  if (a.chunks.size() != a.shape.size())
    throw Error(where + ": 'chunks' has " + std::to_string(a.chunks.size()) + " axes and 'shape' " +
                std::to_string(a.shape.size()));
  readDtype(j, where, a);
  checkChunkSizes(a.chunks, a.type, where);
  readCompressor(j, where, a);
  a.fillValue = readFill(j, where);
  const json order = j.value("order", json("C"));
  if (order != json("C") && order != json("F"))
    throw Error(where + ": 'order' " + order.dump() + " is neither \"C\" nor \"F\"");
  a.fortranOrder = order == json("F");
  const json filters = j.value("filters", json());
  if (!filters.is_null() && !(filters.is_array() && filters.empty()))
    throw Error(where + ": 'filters' " + filters.dump() + " are not read");
  const json separator = j.value("dimension_separator", json("."));
  if (separator != json(".") && separator != json("/"))
    throw Error(where + ": 'dimension_separator' " + separator.dump() + " is neither \".\" nor \"/\"");
  a.separator = separator.get<std::string>()[0];
  return a;
}

std::string zarrV3NodeType(std::string_view text, const std::string& where) {
  const json j = parseJson(text, where);
  const json type = j.is_object() ? j.value("node_type", json()) : json();
  return type.is_string() ? type.get<std::string>() : "";
}

ZarrArray parseZarrV3Array(std::string_view text, const std::string& where) {
  const json j = parseJson(text, where);
  if (!j.is_object()) throw Error(where + ": not a JSON object");
  if (j.value("zarr_format", json()) != json(3))
    throw Error(where + ": 'zarr_format' is " + j.value("zarr_format", json()).dump() + ", expected 3");
  if (j.value("node_type", json()) != json("array"))
    throw Error(where + ": 'node_type' is " + j.value("node_type", json()).dump() + ", expected \"array\"");
  ZarrArray a;
  a.shape = readSizes(j, "shape", where);
  const json grid = j.value("chunk_grid", json());
  if (!grid.is_object() || grid.value("name", json()) != json("regular"))
    throw Error(where + ": 'chunk_grid' " + grid.dump() + " is not a regular grid");
  a.chunks = readSizes(grid.value("configuration", json::object()), "chunk_shape", where);
  if (a.chunks.size() != a.shape.size())
    throw Error(where + ": 'chunk_shape' has " + std::to_string(a.chunks.size()) + " axes and 'shape' " +
                std::to_string(a.shape.size()));
  a.type = readDataType(j, where);
  checkChunkSizes(a.chunks, a.type, where);
  readCodecs(j.value("codecs", json()), where, a, false);
  a.fillValue = readFill(j, where);
  const json encoding = j.value("chunk_key_encoding", json{{"name", "default"}});
  const json configuration = encoding.is_object() ? encoding.value("configuration", json::object()) : json();
  if (!configuration.is_object())
    throw Error(where + ": 'chunk_key_encoding' " + encoding.dump() +
                " is not an object with a configuration");
  const json name = encoding.value("name", json());
  const json separator = configuration.value("separator", json());
  if (name != json("default") && name != json("v2"))
    throw Error(where + ": 'chunk_key_encoding' " + encoding.dump() + " is not read (default and v2 are)");
  if (separator.is_null())
    a.separator = name == json("default") ? '/' : '.';
  else if (separator == json(".") || separator == json("/"))
    a.separator = separator.get<std::string>()[0];
  else
    throw Error(where + ": the chunk key separator " + separator.dump() + " is neither . nor /");
  if (name == json("default")) a.keyPrefix = std::string("c") + a.separator;
  const json names = j.value("dimension_names", json());
  if (names.is_array() && names.size() == a.shape.size() &&
      std::all_of(names.begin(), names.end(), [](const json& n) { return n.is_string(); }))
    for (const json& n : names) a.dimensionNames.push_back(lowerAscii(n.get<std::string>()));
  return a;
}

std::optional<OmeMultiscale> parseOmeMultiscale(std::string_view text, const std::string& where,
                                                std::string_view datasetPath) {
  json j = parseJson(text, where);
  // OME-NGFF 0.5 keeps its metadata in a v3 group's attributes, under "ome".
  if (j.is_object() && j.contains("attributes") && j.at("attributes").is_object() &&
      j.at("attributes").contains("ome"))
    j = json(j.at("attributes").at("ome"));
  if (!j.is_object() || !j.contains("multiscales")) return std::nullopt;

  const json& all = j.at("multiscales");
  if (!all.is_array() || all.empty() || !all.at(0).is_object())
    throw Error(where + ": 'multiscales' is not a list of images");
  const json& m = all.at(0);
  const json datasets = m.value("datasets", json());
  const auto hasPath = [](const json& d) {
    return d.is_object() && d.contains("path") && d.at("path").is_string();
  };
  if (!datasets.is_array() || datasets.empty() || !hasPath(datasets.at(0)))
    throw Error(where + ": 'multiscales' names no dataset with a 'path'");
  size_t level = 0;
  if (!datasetPath.empty()) {
    while (level < datasets.size() &&
           !(hasPath(datasets.at(level)) && datasets.at(level).at("path") == datasetPath))
      ++level;
    if (level == datasets.size()) return std::nullopt;
  }
  const json& dataset = datasets.at(level);
  OmeMultiscale ome;
  ome.datasetPath = dataset.at("path").get<std::string>();
  for (const json& axis : m.value("axes", json::array())) {
    const std::string name =
        axis.is_string() ? axis.get<std::string>()
        : axis.is_object() && axis.contains("name") && axis.at("name").is_string()
            ? axis.at("name").get<std::string>()
            : throw Error(where + ": an axis of 'multiscales' has no name: " + axis.dump());
    ome.axisNames.push_back(lowerAscii(name));
  }
  // Scales and translations: the dataset's, then the image's own (OME-NGFF 0.4 allows both), each a scale
  // first.
  const auto transformOf = [&](const json& owner, const char* type) -> std::optional<std::vector<double>> {
    for (const json& t : owner.value("coordinateTransformations", json::array())) {
      if (!t.is_object() || t.value("type", json()) != json(type)) continue;
      const json s = t.value(type, json());
      std::vector<double> values;
      for (const json& v : s.is_array() ? s : json::array()) {
        if (!v.is_number()) throw Error(where + ": a '" + type + "' holds " + v.dump() + ", not a number");
        values.push_back(v.get<double>());
      }
      if (!ome.axisNames.empty() && values.size() != ome.axisNames.size())
        throw Error(where + ": a '" + type + "' has " + std::to_string(values.size()) + " values for " +
                    std::to_string(ome.axisNames.size()) + " axes");
      return values;
    }
    return std::nullopt;
  };
  // Labels are for messages alone: an omero block that names no channel, or not every one, is passed over.
  const json omero = j.value("omero", json());
  if (omero.is_object() && omero.contains("channels") && omero.at("channels").is_array()) {
    for (const json& channel : omero.at("channels")) {
      const json label = channel.is_object() ? channel.value("label", json()) : json();
      if (!label.is_string() || label.get<std::string>().empty()) {
        ome.channelLabels.clear();
        break;
      }
      ome.channelLabels.push_back(label.get<std::string>());
    }
  }
  ome.scale = transformOf(dataset, "scale");
  ome.translation = transformOf(dataset, "translation");
  const auto imageScale = transformOf(m, "scale");
  const auto imageTranslation = transformOf(m, "translation");
  for (const auto& image : {imageScale, imageTranslation, ome.translation})
    if (image && ome.scale && image->size() != ome.scale->size())
      throw Error(where + ": the image's and its dataset's transformations have different lengths");
  if (imageScale) {
    if (!ome.scale) ome.scale = std::vector<double>(imageScale->size(), 1.0);
    for (size_t i = 0; i < imageScale->size(); ++i) {
      (*ome.scale)[i] *= (*imageScale)[i];
      if (ome.translation) (*ome.translation)[i] *= (*imageScale)[i];
    }
  }
  if (imageTranslation) {
    if (!ome.translation) ome.translation = std::vector<double>(imageTranslation->size(), 0.0);
    if (ome.translation->size() != imageTranslation->size())
      throw Error(where + ": the image's and its dataset's transformations have different lengths");
    for (size_t i = 0; i < imageTranslation->size(); ++i) (*ome.translation)[i] += (*imageTranslation)[i];
  }
  return ome;
}

}  // namespace ropecast
