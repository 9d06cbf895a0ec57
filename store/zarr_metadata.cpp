#include "store/zarr_metadata.h"

#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>

#include "core/error.h"

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

void readCompressor(const json& j, const std::string& where, ZarrArray& a) {
  const json c = j.value("compressor", json());
  if (c.is_null()) return;
  if (!c.is_object() || !c.contains("id") || !c.at("id").is_string())
    throw Error(where + ": 'compressor' " + c.dump() + " has no 'id'");
  const std::string id = c.at("id").get<std::string>();
  if (id == "blosc")
    a.compressor = ZarrCompressor::Blosc;
  else if (id == "zlib")
    a.compressor = ZarrCompressor::Zlib;
  else if (id == "gzip")
    a.compressor = ZarrCompressor::Gzip;
  else if (id == "zstd")
    a.compressor = ZarrCompressor::Zstd;
  else
    throw Error(where + ": compressor '" + id + "' is not read (blosc, zlib, gzip and zstd are)");
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
  // A chunk is read whole into memory: 2 GiB keeps one far from exhausting it and its sizes in int.
  uint64_t chunkBytes = 1;
  for (uint64_t c : a.chunks) {
    if (c == 0) throw Error(where + ": 'chunks' holds 0");
    if (c > (uint64_t(1) << 31) || (chunkBytes *= c) > (uint64_t(1) << 31))
      throw Error(where + ": chunks of more than 2 GiB are not read");
  }
  readDtype(j, where, a);
  if (chunkBytes * bytesPerSample(a.type) > (uint64_t(1) << 31))
    throw Error(where + ": chunks of more than 2 GiB are not read");
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

std::optional<OmeMultiscale> parseOmeMultiscale(std::string_view text, const std::string& where) {
  const json j = parseJson(text, where);
  if (!j.is_object() || !j.contains("multiscales")) return std::nullopt;
  const json& all = j.at("multiscales");
  if (!all.is_array() || all.empty() || !all.at(0).is_object())
    throw Error(where + ": 'multiscales' is not a list of images");
  const json& m = all.at(0);
  const json datasets = m.value("datasets", json());
  if (!datasets.is_array() || datasets.empty() || !datasets.at(0).is_object() ||
      !datasets.at(0).contains("path") || !datasets.at(0).at("path").is_string())
    throw Error(where + ": 'multiscales' names no dataset with a 'path'");
  OmeMultiscale ome;
  ome.datasetPath = datasets.at(0).at("path").get<std::string>();
  for (const json& axis : m.value("axes", json::array())) {
    std::string name = axis.is_string() ? axis.get<std::string>()
                       : axis.is_object() && axis.contains("name") && axis.at("name").is_string()
                           ? axis.at("name").get<std::string>()
                           : throw Error(where + ": an axis of 'multiscales' has no name: " + axis.dump());
    for (char& c : name) c = char(std::tolower(static_cast<unsigned char>(c)));
    ome.axisNames.push_back(name);
  }
  // Scales: the dataset's, times the image's own (OME-NGFF 0.4 allows both).
  const auto scaleOf = [&](const json& owner) -> std::optional<std::vector<double>> {
    for (const json& t : owner.value("coordinateTransformations", json::array())) {
      if (!t.is_object() || t.value("type", json()) != json("scale")) continue;
      const json s = t.value("scale", json());
      std::vector<double> values;
      for (const json& v : s.is_array() ? s : json::array()) {
        if (!v.is_number()) throw Error(where + ": a 'scale' holds " + v.dump() + ", not a number");
        values.push_back(v.get<double>());
      }
      if (!ome.axisNames.empty() && values.size() != ome.axisNames.size())
        throw Error(where + ": a 'scale' has " + std::to_string(values.size()) + " values for " +
                    std::to_string(ome.axisNames.size()) + " axes");
      return values;
    }
    return std::nullopt;
  };
  ome.scale = scaleOf(datasets.at(0));
  if (const auto image = scaleOf(m)) {
    if (!ome.scale) ome.scale = std::vector<double>(image->size(), 1.0);
    if (ome.scale->size() != image->size())
      throw Error(where + ": the image's 'scale' and its dataset's have different lengths");
    for (size_t i = 0; i < image->size(); ++i) (*ome.scale)[i] *= (*image)[i];
  }
  return ome;
}

}  // namespace ropecast
