#include "reference/volume_sampler.h"

#include <string>

#include "core/error.h"

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

double Level0Sampler::value(glm::dvec3 world) const {
  // Level-0 sample i is centered at q = i + 0.5 with q = x / s. The 2x2x2 samples from floor(q - 0.5) all lie
  // in the brick of the first one, borders included (kBrickBorder >= 1), and the borders replicate the
  // volume's edge samples, so one brick serves the whole trilinear fetch. Indices past the edges read
  // replicated samples.
  const glm::dvec3 c = world * invSpacing_ - 0.5;
  const glm::dvec3 fl = glm::floor(c);
  const glm::dvec3 f = c - fl;
  glm::u32vec3 brickCoord(0), texel(0);  // every axis is set below (zeroed for -Wmaybe-uninitialized)
  for (int axis = 0; axis < 3; ++axis) {
    const int64_t last = int64_t(dims_[axis]) - 1;
    const int64_t i0 = std::clamp<int64_t>(int64_t(fl[axis]), -1, last);  // beyond, both corners are the edge
    const uint32_t b = uint32_t(std::clamp<int64_t>(i0, 0, last)) / brickSize_;
    brickCoord[axis] = b;
    texel[axis] = uint32_t(i0 - int64_t(b) * brickSize_ + int64_t(kBrickBorder));
  }
  const std::byte* brick = cache_.brick(brickCoord);
  const size_t e = edge_, e2 = size_t(edge_) * edge_;
  const size_t base = texel.x + e * texel.y + e2 * texel.z;
  const auto t = [&](size_t dx, size_t dy, size_t dz) {
    return normalizedTexel(brick, type_, base + dx + e * dy + e2 * dz);
  };
  const double c00 = interpolate(t(0, 0, 0), t(1, 0, 0), f.x);
  const double c10 = interpolate(t(0, 1, 0), t(1, 1, 0), f.x);
  const double c01 = interpolate(t(0, 0, 1), t(1, 0, 1), f.x);
  const double c11 = interpolate(t(0, 1, 1), t(1, 1, 1), f.x);
  return interpolate(interpolate(c00, c10, f.y), interpolate(c01, c11, f.y), f.z);
}

}  // namespace ropecast
