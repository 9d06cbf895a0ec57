// Volume samplers of the CPU ray casters (reference/cpu_raycaster): trilinear interpolation of one resolution
// level, normalized to v = stored / storedMax, in double, exactly as docs/RENDERING.md "Spaces" and "Rays" 4
// fix it.
//   BrickSampler: one stored brick (border included) of a node at its level: the CPU twin of the GL pool
//   fetch. Level0BrickCache + Level0Sampler: level-0 data of a BrickSource fetched brick by brick on first
//   use, for the brute-force reference renderer (no octree).
// Pure CPU, GL-free. Samplers are immutable and may be used by any thread. Level0BrickCache is thread-safe:
// any thread may fetch; bricks are kept until the cache is destroyed (the reference renders volumes that fit
// in RAM).
#pragma once

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#include "store/brick_source.h"

namespace ropecast {

// The stored value of a brick texel, normalized to [0, 1] (R8 / R16 UNORM).
inline double normalizedTexel(const std::byte* brick, SampleType storedType, size_t index) {
  if (storedType == SampleType::UInt8) return double(reinterpret_cast<const uint8_t*>(brick)[index]) / 255.0;
  return double(reinterpret_cast<const uint16_t*>(brick)[index]) / 65535.0;
}

// a + (b - a) w, not a (1 - w) + b w: equal corners give their value exactly, so a flat region at the
// isovalue shows no sign change (docs/RENDERING.md), as the GPU's filtering shows none.
inline double interpolate(double a, double b, double w) {
  return a + (b - a) * w;
}

// Trilinear weights of a continuous texel coordinate p (texel i centered at i + 0.5), with clamp-to-edge
// indices in [0, edge).
struct TrilinearAxis {
  uint32_t i0, i1;
  double f;
  static TrilinearAxis at(double p, uint32_t edge) {
    const double c = p - 0.5;
    const double fl = std::floor(c);
    const int64_t i = int64_t(fl);
    const int64_t last = int64_t(edge) - 1;
    return {uint32_t(std::clamp<int64_t>(i, 0, last)), uint32_t(std::clamp<int64_t>(i + 1, 0, last)), c - fl};
  }
};

// One node's brick at resolution level L. World point x maps to texel coordinate
// x / (s * 2^L) - coord * B + kBrickBorder (docs/RENDERING.md "Level grid").
class BrickSampler {
 public:
  BrickSampler(const std::byte* brick, SampleType storedType, const OctreeLayout& layout, const NodeKey& node,
               glm::dvec3 spacing)
      : brick_(brick), type_(storedType), edge_(layout.storedBrickEdge()) {
    const double levelScale = std::ldexp(1.0, int(layout.levelOfDepth(node.depth)));
    invCell_ = 1.0 / (spacing * levelScale);
    offset_ = double(kBrickBorder) - glm::dvec3(node.coord) * double(layout.brickSize);
  }

  // The continuous texel coordinate of a world point (texel i centered at i + 0.5), and the brick's edge.
  glm::dvec3 texel(glm::dvec3 world) const { return world * invCell_ + offset_; }
  uint32_t edge() const { return edge_; }

  double value(glm::dvec3 world) const {
    const glm::dvec3 p = texel(world);
    const TrilinearAxis ax = TrilinearAxis::at(p.x, edge_), ay = TrilinearAxis::at(p.y, edge_),
                        az = TrilinearAxis::at(p.z, edge_);
    const size_t e = edge_, e2 = size_t(edge_) * edge_;
    const auto t = [&](uint32_t x, uint32_t y, uint32_t z) {
      return normalizedTexel(brick_, type_, x + e * y + e2 * z);
    };
    const double c00 = interpolate(t(ax.i0, ay.i0, az.i0), t(ax.i1, ay.i0, az.i0), ax.f);
    const double c10 = interpolate(t(ax.i0, ay.i1, az.i0), t(ax.i1, ay.i1, az.i0), ax.f);
    const double c01 = interpolate(t(ax.i0, ay.i0, az.i1), t(ax.i1, ay.i0, az.i1), ax.f);
    const double c11 = interpolate(t(ax.i0, ay.i1, az.i1), t(ax.i1, ay.i1, az.i1), ax.f);
    return interpolate(interpolate(c00, c10, ay.f), interpolate(c01, c11, ay.f), az.f);
  }

 private:
  const std::byte* brick_;
  SampleType type_;
  uint32_t edge_;
  glm::dvec3 invCell_;
  glm::dvec3 offset_;
};

// Level-0 bricks of a BrickSource, read on first use and kept. Lookup is lock-free once a brick is present.
class Level0BrickCache {
 public:
  explicit Level0BrickCache(const BrickSource& source);
  ~Level0BrickCache();
  Level0BrickCache(const Level0BrickCache&) = delete;
  Level0BrickCache& operator=(const Level0BrickCache&) = delete;

  const BrickSource& source() const { return source_; }
  // The brick of level-0 node `coord` (must be inside); reads it on first use. Throws what readBrick throws.
  const std::byte* brick(glm::u32vec3 coord) const;
  size_t bricksRead() const { return bricksRead_.load(); }

 private:
  const BrickSource& source_;
  glm::u32vec3 nodes_;  // inside nodes per axis at the finest depth
  std::unique_ptr<std::atomic<const std::byte*>[]> slots_;
  mutable std::vector<std::unique_ptr<std::byte[]>> owned_;  // guarded by mutex_
  mutable std::mutex mutex_;
  mutable std::atomic<size_t> bricksRead_{0};
};

// Trilinear level-0 sampling of the whole volume: sample indices are clamped to the volume (edge replication,
// as the store's borders do), so it matches BrickSampler on level-0 bricks everywhere.
class Level0Sampler {
 public:
  explicit Level0Sampler(const Level0BrickCache& cache);
  double value(glm::dvec3 world) const;

 private:
  const Level0BrickCache& cache_;
  SampleType type_;
  uint32_t brickSize_, edge_;
  glm::u32vec3 dims_;
  glm::dvec3 invSpacing_;
};

}  // namespace ropecast
