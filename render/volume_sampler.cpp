#include "render/volume_sampler.h"

#include <string>

#include "loader/error.h"

namespace ropecast {

Level0BrickCache::Level0BrickCache(const BrickSource& source)
    : source_(source), nodes_(source.info().layout.insideNodes(source.info().layout.maxDepth)) {
  const size_t count = size_t(nodes_.x) * nodes_.y * nodes_.z;
  slots_ = std::make_unique<std::atomic<const std::byte*>[]>(count);
  for (size_t i = 0; i < count; ++i) slots_[i].store(nullptr, std::memory_order_relaxed);
}

Level0BrickCache::~Level0BrickCache() = default;

const std::byte* Level0BrickCache::brick(glm::u32vec3 c) const {
  if (c.x >= nodes_.x || c.y >= nodes_.y || c.z >= nodes_.z)
    throw Error("Level0BrickCache::brick: node (" + std::to_string(c.x) + ", " + std::to_string(c.y) + ", " +
                std::to_string(c.z) + ") is outside the volume");
  std::atomic<const std::byte*>& slot = slots_[c.x + size_t(nodes_.x) * (c.y + size_t(nodes_.y) * c.z)];
  if (const std::byte* b = slot.load(std::memory_order_acquire)) return b;
  std::lock_guard lock(mutex_);
  if (const std::byte* b = slot.load(std::memory_order_acquire))
    return b;  // another thread read it meanwhile
  const size_t bytes = source_.brickBytes();
  auto data = std::make_unique<std::byte[]>(bytes);
  source_.readBrick({source_.info().layout.maxDepth, c}, std::span(data.get(), bytes));
  const std::byte* b = data.get();
  owned_.push_back(std::move(data));
  slot.store(b, std::memory_order_release);
  ++bricksRead_;
  return b;
}

Level0Sampler::Level0Sampler(const Level0BrickCache& cache)
    : cache_(cache),
      type_(cache.source().info().storedType),
      brickSize_(cache.source().info().layout.brickSize),
      edge_(cache.source().info().layout.storedBrickEdge()),
      dims_(cache.source().info().layout.dims),
      invSpacing_(1.0 / cache.source().info().volume.spacing) {}

Level0Sampler::AxisFetch Level0Sampler::fetch(int64_t i, int axis) const {
  const uint32_t g = uint32_t(std::clamp<int64_t>(i, 0, int64_t(dims_[axis]) - 1));
  const uint32_t b = g / brickSize_;
  return {b, g - b * brickSize_ + kBrickBorder};
}

double Level0Sampler::value(glm::dvec3 world) const {
  // Level-0 sample i is centered at q = i + 0.5 with q = x / s.
  const glm::dvec3 c = world * invSpacing_ - 0.5;
  const glm::dvec3 fl = glm::floor(c);
  const glm::dvec3 f = c - fl;
  AxisFetch a[3][2];
  for (int axis = 0; axis < 3; ++axis) {
    a[axis][0] = fetch(int64_t(fl[axis]), axis);
    a[axis][1] = fetch(int64_t(fl[axis]) + 1, axis);
  }
  const size_t e = edge_, e2 = size_t(edge_) * edge_;
  double corner[2][2][2];
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x) {
        const std::byte* brick = cache_.brick({a[0][x].brick, a[1][y].brick, a[2][z].brick});
        corner[z][y][x] =
            normalizedTexel(brick, type_, a[0][x].texel + e * a[1][y].texel + e2 * a[2][z].texel);
      }
  const double c00 = corner[0][0][0] * (1 - f.x) + corner[0][0][1] * f.x;
  const double c10 = corner[0][1][0] * (1 - f.x) + corner[0][1][1] * f.x;
  const double c01 = corner[1][0][0] * (1 - f.x) + corner[1][0][1] * f.x;
  const double c11 = corner[1][1][0] * (1 - f.x) + corner[1][1][1] * f.x;
  const double c0 = c00 * (1 - f.y) + c10 * f.y;
  const double c1 = c01 * (1 - f.y) + c11 * f.y;
  return c0 * (1 - f.z) + c1 * f.z;
}

}  // namespace ropecast
