// Tests of store/procedural and the procedural VolumeSource: spec parsing and its errors, determinism, slab
// reads at any z (threaded generation equal to per-sample evaluation), the sphere's mid-range iso radius, the
// fields' defining features, and that proceduralRange bounds every value inside its box.
#include "store/procedural.h"

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "core/error.h"
#include "store/source_procedural.h"
#include "store/volume_source.h"
#include "tests/store/store_test_util.h"

namespace ropecast {
namespace {

using testing::errorOf;
using testing::readSlab;

constexpr ProceduralKind kAllKinds[] = {ProceduralKind::Sphere, ProceduralKind::Menger, ProceduralKind::Noise,
                                        ProceduralKind::MarschnerLobb};

TEST(Procedural, ParsesNamesAndSizes) {
  for (ProceduralKind kind : kAllKinds) {
    const std::string name(proceduralKindName(kind));
    EXPECT_EQ(parseProceduralKind(name), kind);
    const ProceduralField field = parseProceduralField(name + ":37");
    EXPECT_EQ(field.kind, kind);
    EXPECT_EQ(field.size, 37u);
  }
  const auto source = openVolumeSource("procedural:marschner-lobb:41");
  EXPECT_EQ(source->info().dims, glm::u32vec3(41));
  EXPECT_EQ(source->info().type, SampleType::UInt8);
  EXPECT_EQ(source->info().valueMin, 0.0);
  EXPECT_EQ(source->info().valueMax, 255.0);
  EXPECT_EQ(source->info().description, "procedural:marschner-lobb:41");
}

TEST(Procedural, BadSpecsNameTheProblemAndListValidNames) {
  for (const std::string spec :
       {"procedural:cube:64", "procedural:sphere:0", "procedural:sphere:-3", "procedural:sphere:12x",
        "procedural:sphere:", "procedural:sphere", "procedural:sphere:99999999999", "procedural:"}) {
    const std::string message = errorOf(spec);
    EXPECT_NE(message.find(spec), std::string::npos) << message;
    EXPECT_NE(message.find("sphere, menger, noise, marschner-lobb"), std::string::npos) << message;
    EXPECT_THROW(openVolumeSource(spec), UsageError) << spec;  // exit 2 in the CLI, as a bad option
  }
  EXPECT_NE(errorOf("procedural:cube:64").find("unknown name 'cube'"), std::string::npos);
  EXPECT_NE(errorOf("procedural:sphere:0").find("bad SIZE '0'"), std::string::npos);
}

TEST(Procedural, SlabsAreDeterministicAndMatchTheField) {
  for (ProceduralKind kind : kAllKinds) {
    const ProceduralField field{kind, 45};
    const std::string spec = "procedural:" + std::string(proceduralKindName(kind)) + ":45";
    auto a = openVolumeSource(spec);
    auto b = openVolumeSource(spec);
    const auto whole = readSlab<uint8_t>(*a, 0, 45);
    EXPECT_EQ(whole, readSlab<uint8_t>(*b, 0, 45)) << spec;
    // Slabs at arbitrary z, in any order, equal the same slices of the whole volume and the per-sample field.
    for (uint32_t z0 : {44u, 17u, 0u, 30u}) {
      const uint32_t count = std::min(7u, 45 - z0);
      const auto slab = readSlab<uint8_t>(*a, z0, count);
      ASSERT_TRUE(std::equal(slab.begin(), slab.end(), whole.begin() + size_t(z0) * 45 * 45)) << spec;
    }
    for (uint32_t z = 0; z < 45; z += 11)
      for (uint32_t y = 0; y < 45; y += 4)
        for (uint32_t x = 0; x < 45; x += 3)
          ASSERT_EQ(whole[(size_t(z) * 45 + y) * 45 + x], proceduralSample(field, x, y, z)) << spec;
    // A volume with no variation would pass all of the above.
    EXPECT_NE(*std::min_element(whole.begin(), whole.end()), *std::max_element(whole.begin(), whole.end()))
        << spec;
  }
}

TEST(Procedural, ThreadCountDoesNotChangeTheData) {
  const ProceduralField field{ProceduralKind::Noise, 96};
  std::vector<uint8_t> one(size_t(96) * 96 * 20), many(one.size());
  generateProceduralSlab(field, 40, 20, std::as_writable_bytes(std::span(one)), 1);
  generateProceduralSlab(field, 40, 20, std::as_writable_bytes(std::span(many)), 5);
  EXPECT_EQ(one, many);
}

TEST(Procedural, HugeSizesReadSlabsWithoutMaterializing) {
  auto source = openVolumeSource("procedural:sphere:8192");
  EXPECT_EQ(source->info().sampleCount(), uint64_t(8192) * 8192 * 8192);
  const auto slice = readSlab<uint8_t>(*source, 4096, 1);
  const ProceduralField field{ProceduralKind::Sphere, 8192};
  for (uint32_t y : {0u, 1234u, 4096u, 8191u})
    for (uint32_t x : {0u, 77u, 4095u, 8191u})
      EXPECT_EQ(slice[size_t(y) * 8192 + x], proceduralSample(field, x, y, 4096));
  EXPECT_EQ(slice[size_t(4096) * 8192 + 4096], 255);
  EXPECT_THROW(readSlab<uint8_t>(*source, 8191, 2), Error);
}

TEST(Procedural, SphereMidIsovalueIsAtRadiusPoint4Size) {
  const uint32_t size = 100;
  const ProceduralField field{ProceduralKind::Sphere, size};
  const glm::dvec3 center(50.0);
  std::mt19937 rng(7);
  std::normal_distribution<double> gauss;
  for (int i = 0; i < 100; ++i) {
    const glm::dvec3 dir = glm::normalize(glm::dvec3(gauss(rng), gauss(rng), gauss(rng)));
    EXPECT_NEAR(proceduralValue(field, center + dir * 40.0), 127.5, 1e-9);
    EXPECT_GT(proceduralValue(field, center + dir * 39.5), 127.5);
    EXPECT_LT(proceduralValue(field, center + dir * 40.5), 127.5);
  }
  EXPECT_DOUBLE_EQ(proceduralValue(field, center), 255.0);
  // The samples above the isovalue fill a ball of radius 0.4*size.
  auto source = openVolumeSource("procedural:sphere:100");
  const auto all = readSlab<uint8_t>(*source, 0, size);
  const double inside = double(std::count_if(all.begin(), all.end(), [](uint8_t v) { return v >= 128; }));
  const double ball = 4.0 / 3.0 * std::numbers::pi * 40.0 * 40.0 * 40.0;
  EXPECT_NEAR(inside / ball, 1.0, 0.01);
}

TEST(Procedural, MengerHasHolesAtEveryLevel) {
  const ProceduralField field{ProceduralKind::Menger, 81};  // 4 levels, smallest hole 1 sample
  EXPECT_EQ(proceduralSample(field, 0, 0, 0), 255);
  EXPECT_EQ(proceduralSample(field, 40, 40, 40), 0);  // level 1: the central cross
  EXPECT_EQ(proceduralSample(field, 40, 40, 0), 0);
  EXPECT_EQ(proceduralSample(field, 40, 0, 0), 255);
  EXPECT_EQ(proceduralSample(field, 13, 13, 0), 0);  // level 2
  EXPECT_EQ(proceduralSample(field, 4, 4, 0), 0);    // level 3
  EXPECT_EQ(proceduralSample(field, 1, 1, 0), 0);    // level 4
  EXPECT_EQ(proceduralSample(field, 1, 0, 0), 255);
  // Solid fraction of a depth-4 sponge: (20/27)^4.
  auto source = openVolumeSource("procedural:menger:81");
  const auto all = readSlab<uint8_t>(*source, 0, 81);
  const double solid = double(std::count(all.begin(), all.end(), 255)) / double(all.size());
  EXPECT_NEAR(solid, std::pow(20.0 / 27.0, 4), 1e-12);
  EXPECT_EQ(std::count(all.begin(), all.end(), 0) + std::count(all.begin(), all.end(), 255),
            int64_t(all.size()));
  // 80 < 81: only 3 levels, so the 1-sample holes of level 4 are solid.
  EXPECT_EQ(proceduralSample({ProceduralKind::Menger, 80}, 1, 1, 0), 255);
}

TEST(Procedural, NoiseIsAHypertextureAroundASphere) {
  const uint32_t size = 128;
  const ProceduralField field{ProceduralKind::Noise, size};
  EXPECT_EQ(proceduralSample(field, 64, 64, 64), 255);  // deep inside the shape
  EXPECT_EQ(proceduralSample(field, 0, 0, 0), 0);       // far outside
  EXPECT_EQ(proceduralSample(field, 64, 64, 0), 0);     // the faces stay empty
  // Along a ray through the surface the density is not a plain ramp: the noise displaces it differently per
  // ray.
  std::vector<double> crossing;
  for (int ray = 0; ray < 16; ++ray) {
    const double angle = ray * std::numbers::pi / 8.0;
    const glm::dvec3 dir(std::cos(angle), std::sin(angle), 0.0);
    for (double r = 0.0; r < 64.0; r += 0.25) {
      if (proceduralValue(field, glm::dvec3(64.0) + dir * r) < 127.5) {
        crossing.push_back(r);
        break;
      }
    }
  }
  ASSERT_EQ(crossing.size(), 16u);
  const auto [lo, hi] = std::minmax_element(crossing.begin(), crossing.end());
  EXPECT_GT(*hi - *lo, 2.0);
  EXPECT_NEAR((*hi + *lo) / 2.0, 0.3 * size, 0.1 * size);
}

TEST(Procedural, MarschnerLobbMatchesTheFormula) {
  const uint32_t size = 64;
  const ProceduralField field{ProceduralKind::MarschnerLobb, size};
  auto reference = [](double x, double y, double z) {
    const double r = std::sqrt(x * x + y * y);
    const double rhoR = std::cos(2.0 * std::numbers::pi * 6.0 * std::cos(std::numbers::pi * r / 2.0));
    return (1.0 - std::sin(std::numbers::pi * z / 2.0) + 0.25 * (1.0 + rhoR)) / (2.0 * 1.25);
  };
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int i = 0; i < 200; ++i) {
    const glm::dvec3 x(unit(rng), unit(rng), unit(rng));
    EXPECT_NEAR(proceduralValue(field, (x + 1.0) / 2.0 * double(size)), 255.0 * reference(x.x, x.y, x.z),
                1e-9);
  }
  EXPECT_NEAR(proceduralValue(field, glm::dvec3(32.0)), 255.0 * 0.6, 1e-9);
}

TEST(Procedural, RangeBoundsEveryValueInItsBox) {
  std::mt19937 rng(11);
  for (ProceduralKind kind : kAllKinds) {
    for (uint32_t size : {27u, 64u, 200u}) {
      const ProceduralField field{kind, size};
      std::uniform_real_distribution<double> position(-2.0, size + 2.0);
      std::uniform_real_distribution<double> extent(0.0, 1.0);
      int narrower = 0;
      for (int box = 0; box < 300; ++box) {
        // Boxes from single points to the whole volume, biased to small ones like fine octree nodes.
        const glm::dvec3 lo(position(rng), position(rng), position(rng));
        const double edge = std::pow(extent(rng), 3.0) * size;
        const PositionBox b{lo, lo + glm::dvec3(edge, edge * extent(rng), edge)};
        const ValueRange range = proceduralRange(field, b);
        ASSERT_LE(range.min, range.max);
        if (range.max - range.min < 255.0) ++narrower;
        std::uniform_real_distribution<double> u(0.0, 1.0);
        for (int i = 0; i < 60; ++i) {
          // Corners and random interior points.
          const glm::dvec3 t =
              i < 8 ? glm::dvec3(i & 1, (i >> 1) & 1, (i >> 2) & 1) : glm::dvec3(u(rng), u(rng), u(rng));
          const glm::dvec3 p = b.lo + t * (b.hi - b.lo);
          const double v = proceduralValue(field, p);
          ASSERT_GE(v, range.min) << proceduralKindName(kind) << " size " << size;
          ASSERT_LE(v, range.max) << proceduralKindName(kind) << " size " << size;
        }
      }
      // A bound of [0, 255] everywhere is conservative but useless.
      EXPECT_GT(narrower, 50) << proceduralKindName(kind) << " size " << size;
    }
  }
}

TEST(Procedural, RangeBoundsTheSamplesOfABrick) {
  // As a procedural octree node would use it: the box of sample centers of a 16^3 brick.
  for (ProceduralKind kind : kAllKinds) {
    const ProceduralField field{kind, 64};
    for (uint32_t bz = 0; bz < 64; bz += 16) {
      for (uint32_t by = 0; by < 64; by += 16) {
        for (uint32_t bx = 0; bx < 64; bx += 16) {
          const ValueRange range =
              proceduralRange(field, {glm::dvec3(bx, by, bz) + 0.5, glm::dvec3(bx, by, bz) + 15.5});
          uint8_t lo = 255, hi = 0;
          for (uint32_t z = bz; z < bz + 16; ++z)
            for (uint32_t y = by; y < by + 16; ++y)
              for (uint32_t x = bx; x < bx + 16; ++x) {
                const uint8_t s = proceduralSample(field, x, y, z);
                lo = std::min(lo, s);
                hi = std::max(hi, s);
              }
          ASSERT_LE(range.min, lo) << proceduralKindName(kind);
          ASSERT_GE(range.max, hi) << proceduralKindName(kind);
        }
      }
    }
  }
  // Exact cases: a box inside the sponge's central hole, a box far out of the sphere.
  const ValueRange hole = proceduralRange({ProceduralKind::Menger, 81}, {glm::dvec3(30.0), glm::dvec3(50.0)});
  EXPECT_EQ(hole.max, 0.0);
  const ValueRange corner =
      proceduralRange({ProceduralKind::Sphere, 100}, {glm::dvec3(0.0), glm::dvec3(2.0)});
  EXPECT_EQ(corner.max, 0.0);
}

}  // namespace
}  // namespace ropecast
