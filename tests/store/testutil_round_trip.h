// Test helpers for round trips of a source through convert -> Store -> extract: level 0 read back through the
// store's mapping and as extract writes it, a source spec converted and verified, and what a round trip must
// keep of each sample. Shared by the raw/NRRD and the image-stack round trips. Test code only; one thread.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include <gtest/gtest.h>

#include "store/converter.h"
#include "store/extract.h"
#include "store/store.h"
#include "store/verify.h"
#include "tests/store/store_test_util.h"

namespace ropecast::testing {

// Level 0 in data units: the stored values of the finest bricks through the store's mapping.
inline std::vector<double> level0Data(const Store& store) {
  const BrickSourceInfo& info = store.info();
  const OctreeLayout& layout = info.layout;
  const uint32_t b = layout.brickSize, edge = layout.storedBrickEdge();
  const glm::u32vec3 dims = layout.levelDims(0), nodes = layout.insideNodes(layout.maxDepth);
  std::vector<double> data(size_t(dims.x) * dims.y * dims.z);
  std::vector<std::byte> brick(store.brickBytes());
  for (uint32_t cz = 0; cz < nodes.z; ++cz)
    for (uint32_t cy = 0; cy < nodes.y; ++cy)
      for (uint32_t cx = 0; cx < nodes.x; ++cx) {
        store.readBrick({layout.maxDepth, {cx, cy, cz}}, brick);
        const std::vector<uint16_t> stored = widen(brick, info.storedType);
        for (uint32_t z = cz * b; z < std::min((cz + 1) * b, dims.z); ++z)
          for (uint32_t y = cy * b; y < std::min((cy + 1) * b, dims.y); ++y)
            for (uint32_t x = cx * b; x < std::min((cx + 1) * b, dims.x); ++x) {
              const size_t in =
                  (size_t(z - cz * b + kBrickBorder) * edge + (y - cy * b + kBrickBorder)) * edge +
                  (x - cx * b + kBrickBorder);
              data[(size_t(z) * dims.y + y) * dims.x + x] = info.mapping.toData(stored[in]);
            }
      }
  return data;
}

// Level 0 as extract writes it, in the original type T.
template <typename T>
std::vector<T> extractedLevel0(const Store& store) {
  const std::vector<std::byte> bytes = extractLevelBytes(store, 0);
  std::vector<T> values(bytes.size() / sizeof(T));
  std::memcpy(values.data(), bytes.data(), values.size() * sizeof(T));
  return values;
}

// The source `spec` converted (8^3 bricks) into dir/NAME.store, NAME its last path component, verified and
// opened.
inline std::unique_ptr<Store> convertAndOpen(const TempDir& dir, const std::string& spec,
                                             const SourceOptions& sourceOptions = {}) {
  const auto source = openVolumeSource(spec, sourceOptions);
  const std::filesystem::path output = dir / (std::filesystem::path(spec).filename().string() + ".store");
  ConvertOptions options;
  options.brickSize = 8;
  convertVolume(*source, output, options);
  auto store = Store::open(output);
  const VerifyReport report = verifyStore(*store);
  EXPECT_TRUE(report.ok()) << spec << ": " << (report.problems.empty() ? "" : report.problems.front());
  return store;
}

// What a round trip must keep of each sample: exactly (step 0), or within half a quantization step in the
// store and, extracted to an integer type, rounded to the nearest integer as well.
template <typename T>
void expectKept(const Store& store, const std::vector<T>& values, SampleType type, bool exact,
                const std::string& what) {
  EXPECT_EQ(store.info().volume.type, type) << what;
  EXPECT_EQ(store.info().storedType, storedTypeFor(type)) << what;
  const double step = store.info().mapping.scale;
  EXPECT_EQ(step == 1.0, exact) << what << ": scale " << step;
  const std::vector<double> data = level0Data(store);
  const std::vector<T> extracted = extractedLevel0<T>(store);
  ASSERT_EQ(data.size(), values.size()) << what;
  ASSERT_EQ(extracted.size(), values.size()) << what;
  const double rounding = std::is_integral_v<T> ? 0.5 : 0.0;
  for (size_t i = 0; i < values.size(); ++i) {
    const double v = double(values[i]);
    if (exact) {
      ASSERT_EQ(data[i], v) << what << ": sample " << i;
      ASSERT_EQ(extracted[i], values[i]) << what << ": sample " << i;
    } else {
      ASSERT_LE(std::abs(data[i] - v), 0.5 * step * (1 + 1e-9)) << what << ": sample " << i;
      ASSERT_LE(std::abs(double(extracted[i]) - v), 0.5 * step * (1 + 1e-9) + rounding)
          << what << ": sample " << i;
    }
  }
}

}  // namespace ropecast::testing
