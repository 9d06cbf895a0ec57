// TransferFunction: a 1D transfer function in data units (value -> straight RGBA, piecewise linear between
// control points), read from a small JSON file or chosen by preset name; and TfTable, the table baked from it
// over normalized stored values as docs/RENDERING.md fixes it, with an O(1) "can this value range be
// visible?" test the loader uses to treat nodes as empty without reading them. Plain data and pure functions;
// any thread (a baked table is immutable and may be shared by threads).
//
// File format (docs/TRANSFER_FUNCTIONS.md): {"points": [[value, r, g, b, a], ...]} with values in data units,
// non-decreasing (two points at the same value make a step), colors and alpha in [0, 1]. Alpha is the opacity
// of one level-0 voxel (the renderers correct it for their step length).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec4.hpp>

#include "core/sample_type.h"

namespace ropecast {

struct TfPoint {
  double value = 0.0;  // data units
  glm::dvec4 rgba{0.0};
};

// The data range presets are placed in (data units), and what the data is, so CT presets can stay in
// Hounsfield.
struct TfDataRange {
  SampleType sourceType = SampleType::UInt8;
  double minValue = 0.0;
  double maxValue = 255.0;
};

class TransferFunction {
 public:
  TransferFunction() = default;
  // Points must be non-empty, sorted by value (non-decreasing), rgba in [0, 1]; throws ropecast::Error
  // otherwise.
  explicit TransferFunction(std::vector<TfPoint> points);

  // Parses the JSON text; `sourceName` (a file name) is named in error messages.
  static TransferFunction fromJson(std::string_view text, const std::string& sourceName);
  static TransferFunction fromFile(const std::string& path);
  // A preset by name (see presetNames()), placed for the given data (docs/TRANSFER_FUNCTIONS.md).
  static TransferFunction preset(std::string_view name, const TfDataRange& data);
  static std::vector<std::string> presetNames();
  static bool isPreset(std::string_view name);
  // The preset `--tf` defaults to: for direct volume rendering, which composites many faint samples; for a
  // maximum intensity projection, which shows one value per pixel, opaque; for a slice, which shows every
  // value of its plane.
  static constexpr std::string_view kDefaultPreset = "linear";
  static constexpr std::string_view kMipDefaultPreset = "gray";
  static constexpr std::string_view kSliceDefaultPreset = "window";
  // `--tf T`: a preset name, else a file path. An empty spec gives kDefaultPreset.
  static TransferFunction fromSpec(const std::string& spec, const TfDataRange& data);

  // `--tf-range LO,HI`, a window: the points moved linearly so that the first lies at lo and the last at hi
  // (a preset placed by fractions of the data range is then placed over [lo, hi] instead); points that all
  // lie at one value move to the middle. Throws ropecast::Error unless lo < hi, both finite.
  TransferFunction stretchedOver(double lo, double hi) const;

  const std::vector<TfPoint>& points() const { return points_; }
  // Piecewise linear; constant beyond the first and last points. At a step (equal values), the later point
  // wins.
  glm::dvec4 evaluate(double dataValue) const;

 private:
  std::vector<TfPoint> points_;
};

// The baked table: entry i at normalized stored value v = i / (N - 1). Immutable once built.
class TfTable {
 public:
  static constexpr uint32_t kDefaultEntries = 4096;

  // Entry i holds tf(mapping.toData(i / (N - 1) * storedMax)); storedMax is 255 or 65535.
  static TfTable bake(const TransferFunction& tf, const ValueMapping& mapping, uint32_t storedMax,
                      uint32_t entries = kDefaultEntries);

  uint32_t entryCount() const { return uint32_t(rgba_.size()); }
  uint32_t storedMax() const { return storedMax_; }
  const std::vector<glm::vec4>& entries() const { return rgba_; }  // float RGBA, what the GL texture holds

  // Linear lookup at normalized stored value v (clamped to [0, 1]) exactly as the GL 1D texture with LINEAR
  // filtering and texcoord (v * (N - 1) + 0.5) / N does it, in double.
  glm::dvec4 lookup(double v) const;

  // Whether any value in the stored range [storedMin, storedMax] can get a non-zero opacity from lookup().
  // O(1) from a prefix count of non-zero alpha entries. Conservative: it covers the two table entries each
  // interpolated value mixes plus one entry of slack on each side for GPU coordinate rounding, so a false
  // answer guarantees zero opacity, a true answer may be wrong only next to a transparent/opaque boundary.
  bool hasOpacity(uint32_t storedMin, uint32_t storedMax) const;

 private:
  std::vector<glm::vec4> rgba_;
  std::vector<uint32_t> opaquePrefix_;  // opaquePrefix_[i] = number of entries j < i with alpha > 0
  uint32_t storedMax_ = 255;
};

}  // namespace ropecast
