#include "store/placed_stack.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <type_traits>

#include <glm/geometric.hpp>

#include "core/error.h"

namespace ropecast {

namespace {

// Offsets and grid positions this close to a whole sample are taken as whole: rounding in the positions a
// file prints must not blur slices that lie on the grid.
constexpr double kWholeSample = 1e-3;

class ResampledSlices final : public VolumeSource {
 public:
  ResampledSlices(std::unique_ptr<VolumeSource> stacked, SliceGrid grid)
      : stacked_(std::move(stacked)), grid_(std::move(grid)) {
    const VolumeInfo& from = stacked_->info();
    if (grid_.slices.size() != from.dims.z)
      throw Error(from.description + ": " + std::to_string(grid_.slices.size()) + " slice positions for " +
                  std::to_string(from.dims.z) + " slices");
    info_ = from;
    info_.dims = grid_.dims;
    info_.spacing = grid_.spacing;
    if (from.origin) info_.origin = grid_.origin;
    const std::vector<double>& bottom = slice(0);
    outside_ = *std::min_element(bottom.begin(), bottom.end());
  }

  const VolumeInfo& info() const override { return info_; }

 private:
  void readSlices(uint32_t z0, uint32_t count, std::span<std::byte> out) override {
    const size_t pixels = size_t(info_.dims.x) * info_.dims.y;
    std::vector<double> values(pixels);
    for (uint32_t m = 0; m < count; ++m) {
      const double z = double(z0 + m);
      // The slices around grid slice z: the last one at or below it, and the next (zero weight when it lies
      // on the grid).
      size_t below = 0;
      while (below + 1 < grid_.slices.size() && grid_.slices[below + 1].z <= z + kWholeSample) ++below;
      const size_t above = std::min(below + 1, grid_.slices.size() - 1);
      const double gap = grid_.slices[above].z - grid_.slices[below].z;
      double weight = gap > 0.0 ? std::clamp((z - grid_.slices[below].z) / gap, 0.0, 1.0) : 0.0;
      if (weight < kWholeSample) weight = 0.0;
      std::fill(values.begin(), values.end(), 0.0);
      addSlice(below, 1.0 - weight, values);
      if (weight > 0.0) addSlice(above, weight, values);
      forSampleType(info_.type, [&](auto zero) {
        using T = decltype(zero);
        T* to = reinterpret_cast<T*>(out.data() + m * info_.sliceBytes());
        for (size_t i = 0; i < pixels; ++i) {
          if constexpr (std::is_integral_v<T>)
            to[i] = T(std::clamp(std::round(values[i]), double(std::numeric_limits<T>::lowest()),
                                 double(std::numeric_limits<T>::max())));
          else
            to[i] = T(values[i]);
        }
      });
    }
  }

  // Adds slice k, moved to where it lies in the grid, times `weight` to `values` (a grid slice): bilinear
  // between its samples, the value outside it where a tap leaves it.
  void addSlice(size_t k, double weight, std::vector<double>& values) {
    const std::vector<double>& samples = slice(k);
    const glm::u32vec3 from = stacked_->info().dims;
    // Grid sample (i, j) reads the slice at (i - x, j - y): whole parts and the fractions between taps.
    const auto split = [](double at, int64_t& whole, double& fraction) {
      whole = int64_t(std::floor(at));
      fraction = at - double(whole);
      if (fraction < kWholeSample) fraction = 0.0;
      if (fraction > 1.0 - kWholeSample) whole += 1, fraction = 0.0;
    };
    int64_t wholeX, wholeY;
    double fractionX, fractionY;
    split(-grid_.slices[k].x, wholeX, fractionX);
    split(-grid_.slices[k].y, wholeY, fractionY);
    const auto tap = [&](int64_t x, int64_t y) {
      if (x < 0 || y < 0 || x >= int64_t(from.x) || y >= int64_t(from.y)) return outside_;
      return samples[size_t(y) * from.x + size_t(x)];
    };
    for (uint32_t j = 0; j < info_.dims.y; ++j)
      for (uint32_t i = 0; i < info_.dims.x; ++i) {
        const int64_t x = int64_t(i) + wholeX, y = int64_t(j) + wholeY;
        double value = (1.0 - fractionY) *
                       ((1.0 - fractionX) * tap(x, y) + (fractionX > 0.0 ? fractionX * tap(x + 1, y) : 0.0));
        if (fractionY > 0.0)
          value += fractionY * ((1.0 - fractionX) * tap(x, y + 1) +
                                (fractionX > 0.0 ? fractionX * tap(x + 1, y + 1) : 0.0));
        values[size_t(j) * info_.dims.x + i] += weight * value;
      }
  }

  // Slice k of the stack as numbers; the two read last are kept (grid slices, read in order, each take the
  // two around them).
  const std::vector<double>& slice(size_t k) {
    for (Kept& kept : kept_)
      if (kept.index == k) return kept.values;
    Kept& replaced = kept_[replacedNext_];  // the one read before the other
    replacedNext_ ^= 1;
    replaced.index = kNone;  // until read whole
    const VolumeInfo& from = stacked_->info();
    bytes_.resize(from.sliceBytes());
    stacked_->readSlab(uint32_t(k), 1, bytes_);
    replaced.values.resize(size_t(from.dims.x) * from.dims.y);
    forSampleType(from.type, [&](auto zero) {
      using T = decltype(zero);
      const T* samples = reinterpret_cast<const T*>(bytes_.data());
      for (size_t i = 0; i < replaced.values.size(); ++i) replaced.values[i] = double(samples[i]);
    });
    replaced.index = k;
    return replaced.values;
  }

  static constexpr size_t kNone = std::numeric_limits<size_t>::max();
  struct Kept {
    size_t index = kNone;
    std::vector<double> values;
  };

  std::unique_ptr<VolumeSource> stacked_;
  SliceGrid grid_;
  VolumeInfo info_;
  double outside_ = 0.0;
  Kept kept_[2];
  size_t replacedNext_ = 0;
  std::vector<std::byte> bytes_;
};

}  // namespace

SlicePlan planSlices(const VolumeInfo& stacked, std::span<const glm::dvec3> positions,
                     const std::string& what) {
  if (positions.size() != stacked.dims.z)
    throw Error(stacked.description + ": " + std::to_string(positions.size()) + " slice positions for " +
                std::to_string(stacked.dims.z) + " slices");
  SlicePlan plan;
  const size_t n = positions.size();
  if (n < 2) return plan;

  // Each slice's place against the bottom one: in-plane in samples, across in world units.
  const glm::dvec3 rows = stacked.axes[0], columns = stacked.axes[1], normal = stacked.axes[2];
  std::vector<glm::dvec3> local(n);
  for (size_t k = 0; k < n; ++k) {
    const glm::dvec3 d = positions[k] - positions[0];
    local[k] = {glm::dot(d, rows) / stacked.spacing.x, glm::dot(d, columns) / stacked.spacing.y,
                glm::dot(d, normal)};
  }
  const double extent = local[n - 1].z;
  plan.averageGap = extent / double(n - 1);
  double smallest = std::numeric_limits<double>::infinity(), largest = 0.0, shear = 0.0;
  for (size_t k = 1; k < n; ++k) {
    const double gap = local[k].z - local[k - 1].z;
    smallest = std::min(smallest, gap);
    largest = std::max(largest, gap);
    shear = std::max({shear, std::abs(local[k].x), std::abs(local[k].y)});
  }
  const bool sheared = shear >= kShearSamplesResampled;
  const bool uneven = largest > kGapRatioResampled * smallest;
  const std::string gapsText =
      "the gaps between " + what + " vary from " + formatNumber(smallest) + " to " + formatNumber(largest);
  const glm::dvec2 lastMove(local[n - 1].x * stacked.spacing.x, local[n - 1].y * stacked.spacing.y);
  const double tiltDegrees = std::atan2(glm::length(lastMove), extent) * 180.0 / std::numbers::pi;
  const std::string shearText = what + " lie off their normal, by up to " +
                                formatNumber(std::round(shear * 10) / 10) + " samples (as a gantry tilted " +
                                formatNumber(std::round(tiltDegrees * 10) / 10) + " degrees places them)";
  const std::string averageText = "stacked " + formatNumber(*plan.averageGap) + " apart, the average";
  if (!sheared && !uneven) {
    if (largest - smallest > 0.01 * *plan.averageGap)
      plan.notes.push_back(gapsText + "; they are " + averageText);
    return plan;
  }

  SliceGrid grid;
  double lowX = 0.0, highX = 0.0, lowY = 0.0, highY = 0.0;
  if (sheared)
    for (const glm::dvec3& p : local) {
      lowX = std::min(lowX, p.x), highX = std::max(highX, p.x);
      lowY = std::min(lowY, p.y), highY = std::max(highY, p.y);
    }
  const double firstX = std::floor(lowX + kWholeSample), firstY = std::floor(lowY + kWholeSample);
  const double spanX = std::ceil(highX - kWholeSample) - firstX,
               spanY = std::ceil(highY - kWholeSample) - firstY;
  const double slices = uneven ? std::round(extent / smallest) + 1.0 : double(n);
  const double samples = (stacked.dims.x + spanX) * (stacked.dims.y + spanY) * slices;
  if (samples > kMostGrowthResampled * double(stacked.sampleCount()) ||
      std::max({stacked.dims.x + spanX, stacked.dims.y + spanY, slices}) > kMaxDimsPerAxis) {
    if (sheared) plan.notes.push_back(shearText + ", too far for a regular grid; they are stacked straight");
    if (largest - smallest > 0.01 * *plan.averageGap)
      plan.notes.push_back(gapsText + "; they are " + averageText);
    return plan;
  }
  grid.dims = {uint32_t(stacked.dims.x + spanX), uint32_t(stacked.dims.y + spanY), uint32_t(slices)};
  grid.spacing = {stacked.spacing.x, stacked.spacing.y, uneven ? extent / (slices - 1.0) : *plan.averageGap};
  grid.origin = positions[0] + rows * (firstX * stacked.spacing.x) + columns * (firstY * stacked.spacing.y);
  for (size_t k = 0; k < n; ++k)
    grid.slices.push_back({sheared ? local[k].x - firstX : 0.0, sheared ? local[k].y - firstY : 0.0,
                           uneven ? local[k].z / grid.spacing.z : double(k)});
  std::string why = sheared ? shearText : "";
  if (uneven) why += (sheared ? ", and " : "") + gapsText + " (a missing slice?)";
  plan.notes.push_back(why + "; they are resampled where they lie, onto a regular grid of " +
                       formatDims(grid.dims) + " samples " + formatNumber(grid.spacing.z) +
                       " apart across (samples no slice reaches take the bottom slice's smallest value)");
  plan.grid = std::move(grid);
  return plan;
}

bool placeSkewedSlices(VolumeInfo& info, const std::array<glm::dvec3, 3>& vectors, const std::string& what,
                       std::optional<SliceGrid>& grid) {
  const double x = glm::length(vectors[0]), y = glm::length(vectors[1]), z = glm::length(vectors[2]);
  if (!(x > 0.0 && y > 0.0 && z > 0.0) || !std::isfinite(x + y + z)) return false;
  const glm::dvec3 rows = vectors[0] / x, columns = vectors[1] / y;
  if (std::abs(glm::dot(rows, columns)) > 1e-3) return false;
  glm::dvec3 normal = glm::normalize(glm::cross(rows, columns));
  const double across = glm::dot(normal, vectors[2]);
  if (!(std::abs(across) > 1e-6 * z)) return false;
  if (across < 0.0) normal = -normal;  // the slices stack along the normal: a mirroring frame
  VolumeInfo placed = info;
  placed.axes = AxisDirections(rows, columns, normal);
  placed.spacing = {x, y, std::abs(across)};
  const glm::dvec3 first = info.origin.value_or(glm::dvec3(0.0));
  std::vector<glm::dvec3> positions;
  for (uint32_t k = 0; k < info.dims.z; ++k) positions.push_back(first + double(k) * vectors[2]);
  SlicePlan plan = planSlices(placed, positions, what);
  if (plan.averageGap) placed.spacing.z = *plan.averageGap;
  placed.notes.insert(placed.notes.end(), plan.notes.begin(), plan.notes.end());
  grid = std::move(plan.grid);
  info = std::move(placed);
  return true;
}

std::unique_ptr<VolumeSource> resampleSlices(std::unique_ptr<VolumeSource> stacked, SliceGrid grid) {
  return std::make_unique<ResampledSlices>(std::move(stacked), std::move(grid));
}

}  // namespace ropecast
