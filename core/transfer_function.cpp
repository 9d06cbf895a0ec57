#include "core/transfer_function.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/input_file.h"
#include "core/json_keys.h"

namespace ropecast {

namespace {

// Presets as [position, r, g, b, a]. CT presets are in Hounsfield units; the MRI and linear ones in fractions
// of the data range (0 = min, 1 = max).
struct PresetPoint {
  double position, r, g, b, a;
};

constexpr double kHounsfieldMin = -1024.0;
constexpr double kHounsfieldMax = 3071.0;

const std::vector<PresetPoint> kCtBone = {
    {kHounsfieldMin, 0.0, 0.0, 0.0, 0.0}, {200.0, 0.85, 0.75, 0.6, 0.0},        {400.0, 0.95, 0.9, 0.8, 0.15},
    {1000.0, 1.0, 0.98, 0.92, 0.5},       {kHounsfieldMax, 1.0, 1.0, 1.0, 0.6},
};
const std::vector<PresetPoint> kCtSoft = {
    {kHounsfieldMin, 0.0, 0.0, 0.0, 0.0}, {-200.0, 0.55, 0.25, 0.15, 0.0}, {-50.0, 0.85, 0.55, 0.45, 0.01},
    {80.0, 0.9, 0.4, 0.35, 0.03},         {300.0, 0.95, 0.9, 0.85, 0.1},   {1500.0, 1.0, 1.0, 1.0, 0.3},
    {kHounsfieldMax, 1.0, 1.0, 1.0, 0.3},
};
const std::vector<PresetPoint> kMri = {
    {0.0, 0.0, 0.0, 0.0, 0.0},    {0.1, 0.3, 0.1, 0.05, 0.0}, {0.3, 0.8, 0.5, 0.4, 0.02},
    {0.6, 0.95, 0.85, 0.7, 0.06}, {1.0, 1.0, 1.0, 1.0, 0.12},
};
const std::vector<PresetPoint> kLinear = {
    {0.0, 0.0, 0.0, 0.0, 0.0},
    {0.1, 0.2, 0.1, 0.05, 0.0},
    {1.0, 1.0, 0.95, 0.85, 0.1},
};
// A gray ramp, opaque from a fifth of the range: a maximum intensity projection shows one value per pixel.
const std::vector<PresetPoint> kGray = {
    {0.0, 0.0, 0.0, 0.0, 0.0},
    {0.1, 0.0, 0.0, 0.0, 0.0},
    {0.2, 0.111, 0.111, 0.111, 1.0},
    {1.0, 1.0, 1.0, 1.0, 1.0},
};
// Black to white over the range, opaque everywhere: a slice shows every value, as a radiology window (placed
// with --tf-range) does.
const std::vector<PresetPoint> kWindow = {
    {0.0, 0.0, 0.0, 0.0, 1.0},
    {1.0, 1.0, 1.0, 1.0, 1.0},
};

// Signed 16- and 32-bit integers are taken as CT data, and floats that reach below -500; the other types
// (unsigned, or int8's [-128, 127]) are not.
bool isHounsfieldData(const TfDataRange& d) {
  switch (d.sourceType) {
    case SampleType::Int16:
    case SampleType::Int32:
      return true;
    case SampleType::Float32:
    case SampleType::Float64:
      return d.minValue <= -500.0;
    case SampleType::UInt8:
    case SampleType::Int8:
    case SampleType::UInt16:
    case SampleType::UInt32:
      return false;
  }
  return false;
}

TransferFunction fromPresetPoints(const std::vector<PresetPoint>& pts,
                                  double (*place)(double, const TfDataRange&), const TfDataRange& data) {
  std::vector<TfPoint> out;
  for (const PresetPoint& p : pts) out.push_back({place(p.position, data), {p.r, p.g, p.b, p.a}});
  return TransferFunction(std::move(out));
}

double placeFraction(double f, const TfDataRange& d) {
  return d.minValue + f * (d.maxValue - d.minValue);
}
double placeHounsfield(double hu, const TfDataRange& d) {
  if (isHounsfieldData(d)) return hu;
  return placeFraction((hu - kHounsfieldMin) / (kHounsfieldMax - kHounsfieldMin), d);
}

std::string readWholeFile(const std::string& path) {
  return readTextInput(path, "TransferFunction: transfer function file '" + path + "'");
}

}  // namespace

TransferFunction::TransferFunction(std::vector<TfPoint> points) : points_(std::move(points)) {
  if (points_.empty()) throw Error("TransferFunction: needs at least one control point");
  for (size_t i = 0; i < points_.size(); ++i) {
    const TfPoint& p = points_[i];
    if (!std::isfinite(p.value))
      throw Error("TransferFunction: point " + std::to_string(i) + " has a non-finite value");
    for (int c = 0; c < 4; ++c)
      if (!(p.rgba[c] >= 0.0 && p.rgba[c] <= 1.0))
        throw Error("TransferFunction: point " + std::to_string(i) + " has r, g, b, a outside [0, 1]");
    if (i > 0 && p.value < points_[i - 1].value)
      throw Error("TransferFunction: points must be sorted by value; point " + std::to_string(i) + " (" +
                  formatNumber(p.value) + ") comes after " + formatNumber(points_[i - 1].value));
  }
}

TransferFunction TransferFunction::fromJson(std::string_view text, const std::string& sourceName) {
  const std::string where = "transfer function '" + sourceName + "'";
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {  // parse_error, or out_of_range for a number like 1e999
    throw Error(where + ": not valid JSON (" + e.what() + ")");
  }
  if (const std::string key = duplicateJsonKey(text); !key.empty())
    throw Error(where + ": the key \"" + key + "\" is given twice in one object (only the last would count)");
  if (!j.is_object() || !j.contains("points"))
    throw Error(where + ": expected an object {\"points\": [[value, r, g, b, a], ...]}");
  for (const auto& [key, value] : j.items())  // a key meant to change the function would be ignored
    if (key != "points")
      throw Error(where + ": unknown key \"" + key + "\"; a transfer function has \"points\" only");
  const nlohmann::json& pts = j["points"];
  if (!pts.is_array() || pts.empty()) throw Error(where + ": \"points\" must be a non-empty array");
  std::vector<TfPoint> points;
  for (size_t i = 0; i < pts.size(); ++i) {
    const nlohmann::json& p = pts[i];
    if (!p.is_array() || p.size() != 5 ||
        !std::all_of(p.begin(), p.end(), [](auto& x) { return x.is_number(); }))
      throw Error(where + ": point " + std::to_string(i) + " must be [value, r, g, b, a] (5 numbers)");
    points.push_back({p[0].get<double>(),
                      {p[1].get<double>(), p[2].get<double>(), p[3].get<double>(), p[4].get<double>()}});
  }
  try {
    return TransferFunction(std::move(points));
  } catch (const Error& e) {
    throw Error(where + ": " + e.what());
  }
}

TransferFunction TransferFunction::fromFile(const std::string& path) {
  return fromJson(readWholeFile(path), path);
}

std::vector<std::string> TransferFunction::presetNames() {
  return {"ct-bone", "ct-soft", "mri", "linear", "gray", "window"};
}

bool TransferFunction::isPreset(std::string_view name) {
  const std::vector<std::string> names = presetNames();
  return std::find(names.begin(), names.end(), name) != names.end();
}

namespace {
std::string presetList() {
  std::string known;
  for (const std::string& n : TransferFunction::presetNames()) known += (known.empty() ? "" : ", ") + n;
  return known;
}
}  // namespace

TransferFunction TransferFunction::preset(std::string_view name, const TfDataRange& data) {
  if (name == "ct-bone") return fromPresetPoints(kCtBone, placeHounsfield, data);
  if (name == "ct-soft") return fromPresetPoints(kCtSoft, placeHounsfield, data);
  if (name == "mri") return fromPresetPoints(kMri, placeFraction, data);
  if (name == "linear") return fromPresetPoints(kLinear, placeFraction, data);
  if (name == "gray") return fromPresetPoints(kGray, placeFraction, data);
  if (name == "window") return fromPresetPoints(kWindow, placeFraction, data);
  throw Error("TransferFunction: unknown preset '" + std::string(name) + "' (expected one of " +
              presetList() + ")");
}

TransferFunction TransferFunction::fromSpec(const std::string& spec, const TfDataRange& data) {
  if (spec.empty()) return preset(kDefaultPreset, data);
  if (isPreset(spec)) return preset(spec, data);
  if (!std::filesystem::exists(spec))
    throw Error("--tf: '" + spec + "' is neither a preset (" + presetList() + ") nor an existing file");
  if (std::filesystem::is_directory(spec))
    throw Error("--tf: '" + spec + "' is a folder; expected a preset or a transfer function file (JSON)");
  return fromFile(spec);
}

TransferFunction TransferFunction::stretchedOver(double lo, double hi) const {
  if (!(lo < hi) || !std::isfinite(lo) || !std::isfinite(hi))
    throw Error("--tf-range " + formatNumber(lo) + "," + formatNumber(hi) +
                ": expected LO,HI with LO < HI, both finite (data units)");
  const double first = points_.front().value, last = points_.back().value;
  std::vector<TfPoint> points = points_;
  double previous = lo;
  for (TfPoint& p : points) {
    // Halved, as in evaluate, and mixed rather than added to: nothing overflows. Rounding may not reorder.
    const double f = last > first ? (0.5 * p.value - 0.5 * first) / (0.5 * last - 0.5 * first) : 0.5;
    p.value = std::clamp(std::max(previous, (1.0 - f) * lo + f * hi), lo, hi);
    previous = p.value;
  }
  return TransferFunction(std::move(points));
}

glm::dvec4 TransferFunction::evaluate(double x) const {
  if (x < points_.front().value) return points_.front().rgba;
  if (x >= points_.back().value) return points_.back().rgba;
  // First point with value > x; x lies in [points[hi-1].value, points[hi].value).
  const auto it = std::upper_bound(points_.begin(), points_.end(), x,
                                   [](double v, const TfPoint& p) { return v < p.value; });
  const TfPoint& b = *it;
  const TfPoint& a = *(it - 1);
  // b.value > x >= a.value, so no division by zero; halved (exactly), the differences cannot overflow when
  // the points lie more than the largest double apart.
  const double f = (0.5 * x - 0.5 * a.value) / (0.5 * b.value - 0.5 * a.value);
  return a.rgba + f * (b.rgba - a.rgba);
}

TfTable TfTable::bake(const TransferFunction& tf, const ValueMapping& mapping, uint32_t storedMax,
                      uint32_t entries) {
  if (entries < 2) throw Error("TfTable::bake: needs at least 2 entries");
  if (storedMax == 0) throw Error("TfTable::bake: storedMax must be positive (255 or 65535)");
  TfTable t;
  t.storedMax_ = storedMax;
  t.rgba_.resize(entries);
  t.opaquePrefix_.resize(entries + 1);
  t.opaquePrefix_[0] = 0;
  for (uint32_t i = 0; i < entries; ++i) {
    const double v = double(i) / double(entries - 1);
    t.rgba_[i] = glm::vec4(tf.evaluate(mapping.toData(v * storedMax)));
    t.opaquePrefix_[i + 1] = t.opaquePrefix_[i] + (t.rgba_[i].a > 0.0f ? 1u : 0u);
  }
  return t;
}

glm::dvec4 TfTable::lookup(double v) const {
  const uint32_t n = entryCount();
  const double x = std::clamp(v, 0.0, 1.0) * double(n - 1);
  const uint32_t i0 = std::min(uint32_t(x), n - 2);
  const double f = x - double(i0);
  return glm::dvec4(rgba_[i0]) * (1.0 - f) + glm::dvec4(rgba_[i0 + 1]) * f;
}

bool TfTable::hasOpacity(uint32_t storedMin, uint32_t storedMaxValue) const {
  const int64_t n = entryCount();
  const double scale = double(n - 1) / double(storedMax_);
  // Entries touched by lookups of values in [storedMin, storedMax]: floor(lo) .. ceil(hi), one more each
  // side.
  const int64_t first = std::clamp<int64_t>(int64_t(std::floor(storedMin * scale)) - 1, 0, n - 1);
  const int64_t last = std::clamp<int64_t>(int64_t(std::ceil(storedMaxValue * scale)) + 1, 0, n - 1);
  if (last < first) return false;
  return opaquePrefix_[last + 1] - opaquePrefix_[first] > 0;
}

}  // namespace ropecast
