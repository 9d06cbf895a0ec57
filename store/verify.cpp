#include "store/verify.h"

#include <algorithm>
#include <cstring>
#include <memory>
#include <optional>
#include <unordered_map>
#include <unordered_set>

#include <glm/common.hpp>

#include "core/error.h"

namespace ropecast {

namespace {

using Brick = std::vector<uint16_t>;  // decoded brick, widened to 16 bits

class Verifier {
 public:
  Verifier(const Store& store, size_t maxProblems) : store_(store), layout_(store.info().layout) {
    maxProblems_ = maxProblems;
  }

  VerifyReport run(const std::function<void(uint64_t, uint64_t)>& progress) {
    const uint64_t total = layout_.insideNodeCount();
    // Finest depth first so a bad child is reported before the parent that the same damage makes look wrong.
    for (uint32_t depth = layout_.maxDepth + 1; depth-- > 0;) {
      const glm::u32vec3 nodes = layout_.insideNodes(depth);
      for (uint32_t z = 0; z < nodes.z; ++z) {
        evict(depth, z >= 1 ? z - 1 : 0);
        evict(depth + 1, 2 * z);
        for (uint32_t y = 0; y < nodes.y; ++y)
          for (uint32_t x = 0; x < nodes.x; ++x) {
            checkNode({depth, {x, y, z}});
            ++report_.nodesChecked;
            if (progress && report_.nodesChecked % 256 == 0) progress(report_.nodesChecked, total);
          }
      }
      cache_.clear();
      lastKey_ = NodeKey{~0u, {}};
    }
    checkValueRange();
    if (const uint64_t extra = store_.bytesAfterNodeTable(); extra > 0)
      problem(std::to_string(extra) +
              " bytes after the node table, which ends a store: the file was appended to or damaged");
    if (progress) progress(report_.nodesChecked, total);
    return report_;
  }

 private:
  void problem(const std::string& what) {
    ++report_.problemCount;
    if (report_.problems.size() < maxProblems_) report_.problems.push_back(what);
  }
  void problem(const NodeKey& key, const std::string& what) {
    problem("node " + Store::describeNode(key) + ": " + what);
  }

  // The metadata's valueRange (data units; the default isovalue and transfer function come from it) is the
  // root's range mapped to data units, or for the types mapped over their range (float32, float64, uint32,
  // int32) that range, which holds the root's range: within half a quantization step, or exactly where the
  // mapping is exact.
  void checkValueRange() {
    const StoreMetadata& m = store_.metadata();
    const NodeInfo root = store_.node({0, {0, 0, 0}});
    if (root.kind == NodeKind::Empty || !m.volume.valueMin || !m.volume.valueMax) return;
    const double lo = m.mapping.toData(root.minValue), hi = m.mapping.toData(root.maxValue);
    const double tolerance = isExactMapping(m.volume.type, m.mapping) ? 0.0 : 0.5 * m.mapping.scale;
    const bool matches = mapsOverValueRange(m.volume.type)
                             ? lo >= *m.volume.valueMin - tolerance && hi <= *m.volume.valueMax + tolerance
                             : lo == *m.volume.valueMin && hi == *m.volume.valueMax;
    if (!matches)
      problem("metadata valueRange [" + std::to_string(*m.volume.valueMin) + ", " +
              std::to_string(*m.volume.valueMax) + "] does not match the root's range [" +
              std::to_string(lo) + ", " + std::to_string(hi) + "] in data units");
  }

  // The node's decoded brick, or nullptr for Empty nodes and bricks that failed to decode (reported once).
  const Brick* brick(const NodeKey& key) {
    const uint64_t index = layout_.nodeIndex(key);
    if (auto it = cache_.find(index); it != cache_.end()) return it->second.get();
    if (failed_.count(index) || store_.node(key).kind == NodeKind::Empty) return nullptr;
    std::vector<std::byte> bytes(store_.brickBytes());
    try {
      store_.readBrick(key, bytes);
    } catch (const Error& e) {
      failed_.insert(index);
      ++report_.problemCount;
      if (report_.problems.size() < maxProblems_) report_.problems.push_back(e.what());
      return nullptr;
    }
    auto decoded = std::make_unique<Brick>(layout_.storedBrickSamples());
    if (store_.info().storedType == SampleType::UInt8)
      std::transform(bytes.begin(), bytes.end(), decoded->begin(), [](std::byte b) { return uint16_t(b); });
    else
      std::memcpy(decoded->data(), bytes.data(), bytes.size());
    return cache_.emplace(index, std::move(decoded)).first->second.get();
  }

  // Drops cached bricks of `depth` whose z coordinate is below `zMin`.
  void evict(uint32_t depth, uint32_t zMin) {
    if (depth > layout_.maxDepth) return;
    lastKey_ = NodeKey{~0u, {}};  // the memo may point at an evicted brick
    std::erase_if(cache_, [&](const auto& entry) {
      const NodeKey k = layout_.nodeAt(entry.first);
      return k.depth == depth && k.coord.z < zMin;
    });
  }

  // The level sample at `g` (already inside the level's dims) from the node at `depth` that owns it; nullopt
  // when that node is Empty or damaged.
  std::optional<uint16_t> sampleAt(uint32_t depth, glm::u32vec3 g) {
    const uint32_t b = layout_.brickSize, edge = layout_.storedBrickEdge();
    const NodeKey owner{depth, g / b};
    if (!(owner == lastKey_) || lastBrick_ == nullptr) {
      lastKey_ = owner;
      lastBrick_ = brick(owner);
      if (lastBrick_ == nullptr) {
        lastKey_ = NodeKey{~0u, {}};
        return std::nullopt;
      }
    }
    const glm::u32vec3 l = g - owner.coord * b + kBrickBorder;
    return (*lastBrick_)[(size_t(l.z) * edge + l.y) * edge + l.x];
  }

  void checkNode(const NodeKey& key) {
    const NodeInfo node = store_.node(key);
    const StoreMetadata& meta = store_.metadata();
    if (node.kind == NodeKind::Constant && node.minValue != node.maxValue)
      problem(key, "Constant node with min " + std::to_string(node.minValue) + " != max " +
                       std::to_string(node.maxValue));
    if (node.kind == NodeKind::Empty &&
        !(meta.discardBelow && store_.info().mapping.toData(node.maxValue) < *meta.discardBelow))
      problem(key, "Empty node whose max " + std::to_string(node.maxValue) + " is not below --discard-below");

    // Children's ranges inside the parent's, and the parent's range their union with its own brick's.
    uint16_t unionMin = 0xFFFF, unionMax = 0;
    if (key.depth < layout_.maxDepth)
      for (uint32_t octant = 0; octant < 8; ++octant) {
        const NodeKey child = key.child(octant);
        if (!layout_.isInside(child)) continue;
        const NodeInfo c = store_.node(child);
        if (c.minValue < node.minValue || c.maxValue > node.maxValue)
          problem(key, "child " + Store::describeNode(child) + " range [" + std::to_string(c.minValue) +
                           ", " + std::to_string(c.maxValue) + "] not inside the node's [" +
                           std::to_string(node.minValue) + ", " + std::to_string(node.maxValue) + "]");
        unionMin = std::min(unionMin, c.minValue);
        unionMax = std::max(unionMax, c.maxValue);
      }
    if (node.kind == NodeKind::Empty) return;

    const Brick* own = brick(key);
    if (own == nullptr) return;  // damaged: already reported
    const auto [ownMin, ownMax] = std::minmax_element(own->begin(), own->end());
    unionMin = std::min(unionMin, *ownMin);
    unionMax = std::max(unionMax, *ownMax);
    if (unionMin != node.minValue || unionMax != node.maxValue) {
      problem(key, "range [" + std::to_string(node.minValue) + ", " + std::to_string(node.maxValue) +
                       "] differs from its brick's and children's [" + std::to_string(unionMin) + ", " +
                       std::to_string(unionMax) + "]");
      return;
    }
    checkBorders(key, *own);
    if (key.depth < layout_.maxDepth) checkFilter(key, *own);
  }

  // Every sample outside the node's own interior (border, or padding beyond the volume) equals its owner's.
  void checkBorders(const NodeKey& key, const Brick& own) {
    const uint32_t b = layout_.brickSize, edge = layout_.storedBrickEdge();
    const glm::u32vec3 dims = layout_.levelDims(layout_.levelOfDepth(key.depth));
    const glm::ivec3 origin = glm::ivec3(key.coord * b) - int(kBrickBorder);
    for (uint32_t k = 0; k < edge; ++k)
      for (uint32_t j = 0; j < edge; ++j)
        for (uint32_t i = 0; i < edge; ++i) {
          const glm::ivec3 g = origin + glm::ivec3(i, j, k);
          const glm::u32vec3 gc = glm::u32vec3(glm::clamp(g, glm::ivec3(0), glm::ivec3(dims) - 1));
          const bool interior = glm::ivec3(gc) == g && gc / b == key.coord;
          if (interior) continue;
          const auto expected = sampleAt(key.depth, gc);
          const uint16_t value = own[(size_t(k) * edge + j) * edge + i];
          if (expected && *expected != value) {
            problem(key, "border sample (" + std::to_string(i) + ", " + std::to_string(j) + ", " +
                             std::to_string(k) + ") is " + std::to_string(value) + ", its neighbor " +
                             Store::describeNode({key.depth, gc / b}) + " has " + std::to_string(*expected));
            return;
          }
        }
  }

  // Every interior sample equals the rounded mean of the 2x2x2 finer samples it covers.
  void checkFilter(const NodeKey& key, const Brick& own) {
    const uint32_t b = layout_.brickSize, edge = layout_.storedBrickEdge();
    const uint32_t level = layout_.levelOfDepth(key.depth);
    const glm::u32vec3 dims = layout_.levelDims(level), fine = layout_.levelDims(level - 1);
    const glm::u32vec3 lo = key.coord * b, hi = glm::min(lo + b, dims);
    for (uint32_t z = lo.z; z < hi.z; ++z)
      for (uint32_t y = lo.y; y < hi.y; ++y)
        for (uint32_t x = lo.x; x < hi.x; ++x) {
          uint32_t sum = 0;
          bool known = true;
          for (uint32_t o = 0; o < 8 && known; ++o) {
            const glm::u32vec3 f =
                glm::min(glm::u32vec3(2 * x + (o & 1), 2 * y + ((o >> 1) & 1), 2 * z + (o >> 2)), fine - 1u);
            const auto v = sampleAt(key.depth + 1, f);
            known = v.has_value();
            sum += v.value_or(0);
          }
          if (!known) continue;
          const glm::u32vec3 l = glm::u32vec3(x, y, z) - lo + kBrickBorder;
          const uint16_t value = own[(size_t(l.z) * edge + l.y) * edge + l.x];
          if (value != (sum + 4) / 8) {
            problem(key, "sample (" + std::to_string(x) + ", " + std::to_string(y) + ", " +
                             std::to_string(z) + ") of level " + std::to_string(level) + " is " +
                             std::to_string(value) + ", the mean of its children's samples is " +
                             std::to_string((sum + 4) / 8));
            return;
          }
        }
  }

  const Store& store_;
  const OctreeLayout& layout_;
  size_t maxProblems_;
  VerifyReport report_;
  std::unordered_map<uint64_t, std::unique_ptr<Brick>> cache_;
  std::unordered_set<uint64_t> failed_;  // bricks that failed to read: each is reported once per run
  NodeKey lastKey_{~0u, {}};
  const Brick* lastBrick_ = nullptr;
};

}  // namespace

VerifyReport verifyStore(const Store& store, size_t maxProblems,
                         const std::function<void(uint64_t, uint64_t)>& progress) {
  return Verifier(store, maxProblems).run(progress);
}

}  // namespace ropecast
