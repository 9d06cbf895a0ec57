// Slices resampled where their positions place them: a stack tilted as a gantry tilts it, and one with a
// slice missing, land on a regular grid whose every sample holds a linear field's value at its own point
// (linear interpolation keeps a linear field exact); samples no slice reaches hold the bottom slice's
// smallest value; stacks close to regular are left as they are.
#include "store/placed_stack.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>

#include "core/error.h"
#include "store/array_source.h"
#include "tests/store/store_test_util.h"

namespace ropecast {
namespace {

using testing::readSlab;

constexpr glm::u32vec3 kSliceDims{9, 7, 1};
constexpr glm::dvec3 kSpacing{0.5, 0.75, 1.0};  // in-plane; z is the caller's
const glm::dvec3 kBottom{-3.0, 4.0, 10.0};

// A linear field over the world.
double field(glm::dvec3 p) {
  return 2.0 * p.x + 3.0 * p.y - 5.0 * p.z + 100.0;
}

// The frame of slices acquired with the gantry tilted by `degrees` about x: rows along x, columns tilted
// toward z, the normal their cross product.
AxisDirections tiltedFrame(double degrees) {
  const double t = degrees * std::numbers::pi / 180.0;
  const glm::dvec3 rows(1, 0, 0), columns(0, std::cos(t), std::sin(t));
  return AxisDirections(rows, columns, glm::cross(rows, columns));
}

// Slices at `positions` in `axes`, each sample the field at its own point, in `type`.
template <typename T>
std::unique_ptr<VolumeSource> slicesAt(const std::vector<glm::dvec3>& positions, const AxisDirections& axes,
                                       SampleType type) {
  VolumeInfo info;
  info.dims = {kSliceDims.x, kSliceDims.y, uint32_t(positions.size())};
  info.spacing = kSpacing;
  info.type = type;
  info.axes = axes;
  info.origin = positions.front();
  info.description = "slices";
  std::vector<T> samples;
  for (const glm::dvec3& position : positions)
    for (uint32_t j = 0; j < kSliceDims.y; ++j)
      for (uint32_t i = 0; i < kSliceDims.x; ++i) {
        const double value = field(position + axes * glm::dvec3(i * kSpacing.x, j * kSpacing.y, 0.0));
        samples.push_back(std::is_integral_v<T> ? T(std::round(value)) : T(value));
      }
  return std::make_unique<ArraySource>(ArraySource::fromSamples<T>(info, samples));
}

// Positions `step` apart along world z (the table's travel), one per entry of `steps` (in steps).
std::vector<glm::dvec3> tablePositions(const std::vector<double>& steps, double step) {
  std::vector<glm::dvec3> positions;
  for (const double k : steps) positions.push_back(kBottom + glm::dvec3(0.0, 0.0, k * step));
  return positions;
}

// The smallest field value of the bottom slice: what the grid holds where no slice reaches.
double bottomSmallest(const std::vector<glm::dvec3>& positions, const AxisDirections& axes) {
  double smallest = INFINITY;
  for (uint32_t j = 0; j < kSliceDims.y; ++j)
    for (uint32_t i = 0; i < kSliceDims.x; ++i)
      smallest =
          std::min(smallest, field(positions[0] + axes * glm::dvec3(i * kSpacing.x, j * kSpacing.y, 0.0)));
  return smallest;
}

// Checks every sample of `placed` (resampled from slices at `positions` in `axes`) against the field at its
// point where every slice it is read from holds its taps, and against `outside` where none reaches it;
// returns how many were checked of each.
template <typename T>
std::pair<size_t, size_t> expectFieldOnGrid(VolumeSource& placed, const SliceGrid& grid,
                                            const AxisDirections& axes, double outside, double tolerance) {
  const VolumeInfo& info = placed.info();
  const std::vector<T> samples = readSlab<T>(placed, 0, info.dims.z);
  size_t inside = 0, outsideChecked = 0;
  for (uint32_t m = 0; m < info.dims.z; ++m) {
    // The slices grid slice m may be read from: those within a grid slice of it.
    std::vector<glm::dvec3> from;
    for (size_t k = 0; k < grid.slices.size(); ++k)
      if (std::abs(grid.slices[k].z - m) <= 1.0 + 1e-9) from.push_back(grid.slices[k]);
    EXPECT_FALSE(from.empty()) << "grid slice " << m;
    for (uint32_t j = 0; j < info.dims.y; ++j)
      for (uint32_t i = 0; i < info.dims.x; ++i) {
        bool allIn = true, allOut = true;
        for (const glm::dvec3& s : from) {
          const double u = i - s.x, v = j - s.y;
          allIn = allIn && u >= 0 && v >= 0 && u <= kSliceDims.x - 1 && v <= kSliceDims.y - 1;
          allOut = allOut && (u <= -1 || v <= -1 || u >= kSliceDims.x || v >= kSliceDims.y);
        }
        const double value = double(samples[(size_t(m) * info.dims.y + j) * info.dims.x + i]);
        const glm::dvec3 point = *info.origin + axes * (glm::dvec3(i, j, m) * info.spacing);
        if (allIn) {
          EXPECT_NEAR(value, field(point), tolerance) << i << "," << j << "," << m;
          ++inside;
        } else if (allOut) {
          EXPECT_NEAR(value, outside, tolerance) << i << "," << j << "," << m;
          ++outsideChecked;
        }
      }
  }
  return {inside, outsideChecked};
}

TEST(PlacedStack, ATiltedStackIsResampledWhereItsSlicesLie) {
  const AxisDirections axes = tiltedFrame(20.0);
  const std::vector<glm::dvec3> positions = tablePositions({0, 1, 2, 3, 4, 5}, 1.25);
  std::unique_ptr<VolumeSource> stacked = slicesAt<float>(positions, axes, SampleType::Float32);
  const SlicePlan plan = planSlices(stacked->info(), positions, "the slices");
  ASSERT_TRUE(plan.grid);
  const SliceGrid grid = *plan.grid;
  // The table travels 1.25 a slice: 1.25 cos 20 along the normal, 1.25 sin 20 along the columns (0.57
  // samples).
  EXPECT_NEAR(*plan.averageGap, 1.25 * std::cos(20.0 * std::numbers::pi / 180.0), 1e-12);
  EXPECT_EQ(grid.dims, glm::u32vec3(9, 7 + 3, 6));  // moved 2.85 samples down the columns in all
  EXPECT_EQ(grid.spacing, glm::dvec3(kSpacing.x, kSpacing.y, *plan.averageGap));
  ASSERT_EQ(plan.notes.size(), 1u);
  EXPECT_NE(plan.notes[0].find("the slices lie off their normal, by up to 2.9 samples"), std::string::npos)
      << plan.notes[0];
  EXPECT_NE(plan.notes[0].find("gantry tilted 20 degrees"), std::string::npos) << plan.notes[0];
  EXPECT_NE(plan.notes[0].find("9x10x6"), std::string::npos) << plan.notes[0];

  const std::unique_ptr<VolumeSource> placed = resampleSlices(std::move(stacked), grid);
  EXPECT_EQ(placed->info().dims, grid.dims);
  EXPECT_EQ(placed->info().spacing, grid.spacing);
  EXPECT_EQ(*placed->info().origin, grid.origin);
  EXPECT_EQ(placed->info().axes, axes);
  const auto [inside, outside] =
      expectFieldOnGrid<float>(*placed, grid, axes, bottomSmallest(positions, axes), 1e-3);
  EXPECT_GT(inside, 6u * 9 * 5);
  EXPECT_GT(outside, 6u * 9 * 1);
}

TEST(PlacedStack, AMissingSliceIsFilledBetweenItsNeighbours) {
  const AxisDirections axes(1.0);
  const std::vector<glm::dvec3> positions = tablePositions({0, 1, 2, 4, 5}, 2.5);
  std::unique_ptr<VolumeSource> stacked = slicesAt<float>(positions, axes, SampleType::Float32);
  const SlicePlan plan = planSlices(stacked->info(), positions, "the slices");
  ASSERT_TRUE(plan.grid);
  EXPECT_EQ(plan.grid->dims, glm::u32vec3(9, 7, 6));
  EXPECT_DOUBLE_EQ(plan.grid->spacing.z, 2.5);
  EXPECT_EQ(plan.grid->origin, kBottom);
  ASSERT_EQ(plan.notes.size(), 1u);
  EXPECT_NE(plan.notes[0].find("vary from 2.5 to 5 (a missing slice?)"), std::string::npos) << plan.notes[0];
  const SliceGrid grid = *plan.grid;
  const std::unique_ptr<VolumeSource> placed = resampleSlices(std::move(stacked), grid);
  const auto [inside, outside] = expectFieldOnGrid<float>(*placed, grid, axes, 0.0, 1e-3);
  EXPECT_EQ(inside, 6u * 9 * 7);
  EXPECT_EQ(outside, 0u);
}

TEST(PlacedStack, TiltAndAMissingSliceTogetherInIntegers) {
  const AxisDirections axes = tiltedFrame(-15.0);
  const std::vector<glm::dvec3> positions = tablePositions({0, 1, 2, 3, 5, 6, 7}, 2.0);
  std::unique_ptr<VolumeSource> stacked = slicesAt<int16_t>(positions, axes, SampleType::Int16);
  const SlicePlan plan = planSlices(stacked->info(), positions, "the slices");
  ASSERT_TRUE(plan.grid);
  EXPECT_EQ(plan.grid->dims.z, 8u);
  const SliceGrid grid = *plan.grid;
  const std::unique_ptr<VolumeSource> placed = resampleSlices(std::move(stacked), grid);
  // The slices' values are rounded, and so are the grid's: within one.
  const auto [inside, outside] =
      expectFieldOnGrid<int16_t>(*placed, grid, axes, std::round(bottomSmallest(positions, axes)), 1.0);
  EXPECT_GT(inside, 8u * 9 * 3);
  EXPECT_GT(outside, 8u * 9);
}

TEST(PlacedStack, SlicesCloseToARegularStackStayAsTheyAre) {
  const AxisDirections axes = tiltedFrame(0.0);
  // Rounded positions: gaps 2.495 to 2.51, and moves of a fifth of a sample within the plane.
  std::vector<glm::dvec3> positions = tablePositions({0, 1, 2, 3}, 2.5);
  positions[1] += glm::dvec3(0.1, 0.0, -0.005);
  positions[2] += glm::dvec3(0.0, -0.15, 0.005);
  std::unique_ptr<VolumeSource> stacked = slicesAt<float>(positions, axes, SampleType::Float32);
  SlicePlan plan = planSlices(stacked->info(), positions, "the slices");
  EXPECT_FALSE(plan.grid);
  EXPECT_DOUBLE_EQ(*plan.averageGap, 2.5);
  EXPECT_TRUE(plan.notes.empty());

  // Gaps that vary by more than a percent (and less than half again) are stacked at their average, noted.
  positions = tablePositions({0, 1, 2.2, 3}, 2.5);
  plan = planSlices(slicesAt<float>(positions, axes, SampleType::Float32)->info(), positions, "the slices");
  EXPECT_FALSE(plan.grid);
  ASSERT_EQ(plan.notes.size(), 1u);
  EXPECT_NE(plan.notes[0].find("vary from 2 to 3; they are stacked 2.5 apart, the average"),
            std::string::npos)
      << plan.notes[0];

  // One slice: nothing to place.
  positions.resize(1);
  plan = planSlices(slicesAt<float>(positions, axes, SampleType::Float32)->info(), positions, "the slices");
  EXPECT_FALSE(plan.averageGap);
  EXPECT_FALSE(plan.grid);
}

TEST(PlacedStack, SlicesTooFarOffTheirNormalAreStackedStraight) {
  const AxisDirections axes = tiltedFrame(80.0);  // no gantry tilts this far: the grid would be huge
  const std::vector<glm::dvec3> positions = tablePositions({0, 1, 2, 3, 4, 5, 6, 7}, 3.0);
  const SlicePlan plan =
      planSlices(slicesAt<float>(positions, axes, SampleType::Float32)->info(), positions, "the slices");
  EXPECT_FALSE(plan.grid);
  ASSERT_EQ(plan.notes.size(), 1u);
  EXPECT_NE(plan.notes[0].find("too far for a regular grid; they are stacked straight"), std::string::npos)
      << plan.notes[0];
}

// Axis vectors whose third alone is off the slices' normal: the slices' frame, and where they lie.
TEST(PlacedStack, SkewedAxesArePlacedInTheSlicesFrame) {
  VolumeInfo info;
  info.dims = {9, 7, 4};
  info.spacing = {3.0, 3.0, 3.0};  // the lengths a source would otherwise take
  info.origin = glm::dvec3(10.0, 20.0, 30.0);
  std::optional<SliceGrid> grid;
  const std::array<glm::dvec3, 3> skewed = {glm::dvec3(0.5, 0, 0), glm::dvec3(0, 0.75, 0),
                                            glm::dvec3(0, 0.75, 2)};
  VolumeInfo placed = info;
  ASSERT_TRUE(placeSkewedSlices(placed, skewed, "the slices", grid));
  EXPECT_EQ(placed.axes, AxisDirections(1.0));
  EXPECT_EQ(placed.spacing, glm::dvec3(0.5, 0.75, 2.0));
  EXPECT_EQ(placed.origin, info.origin);
  ASSERT_EQ(placed.notes.size(), 1u);
  EXPECT_NE(placed.notes[0].find("the slices lie off their normal, by up to 3 samples"), std::string::npos)
      << placed.notes[0];
  ASSERT_TRUE(grid);
  EXPECT_EQ(grid->dims, glm::u32vec3(9, 7 + 3, 4));  // a row down per slice

  // Slices stacked down the normal: a mirroring frame, whose normal points the way they stack.
  VolumeInfo down = info;
  ASSERT_TRUE(placeSkewedSlices(down, {skewed[0], skewed[1], glm::dvec3(0, 0.75, -2)}, "the slices", grid));
  EXPECT_TRUE(mirrors(down.axes));
  EXPECT_EQ(down.axes[2], glm::dvec3(0, 0, -1));
  // Rows and columns not at right angles, or slices in their own plane: left as they were.
  VolumeInfo untouched = info;
  EXPECT_FALSE(placeSkewedSlices(untouched, {glm::dvec3(1, 0, 0), glm::dvec3(0.5, 1, 0), glm::dvec3(0, 0, 1)},
                                 "the slices", grid));
  EXPECT_FALSE(placeSkewedSlices(untouched, {glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(1, 1, 0)},
                                 "the slices", grid));
  EXPECT_EQ(untouched.spacing, info.spacing);
  EXPECT_TRUE(untouched.notes.empty());
}

TEST(PlacedStack, PositionsMustMatchTheSlices) {
  const std::vector<glm::dvec3> positions = tablePositions({0, 1, 2}, 1.0);
  const auto stacked = slicesAt<float>(positions, AxisDirections(1.0), SampleType::Float32);
  const std::vector<glm::dvec3> two(positions.begin(), positions.begin() + 2);
  try {
    planSlices(stacked->info(), two, "the slices");
    FAIL() << "two positions for three slices were taken";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "slices: 2 slice positions for 3 slices");
  }
}

}  // namespace
}  // namespace ropecast
