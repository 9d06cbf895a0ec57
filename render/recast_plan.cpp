#include "render/recast_plan.h"

#include <algorithm>

#include "core/error.h"
#include "occlusion/screen_rect.h"

namespace ropecast {

namespace {

constexpr uint32_t kBlock = RecastPlan::kBlockSize;

// A range of blocks [x0, x1) x [y0, y1).
struct BlockRange {
  uint32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool empty() const { return x1 <= x0 || y1 <= y0; }
};

// The blocks to cast, one byte each, row-major.
class BlockMask {
 public:
  BlockMask(uint32_t width, uint32_t height)
      : blocksX_((width + kBlock - 1) / kBlock),
        blocksY_((height + kBlock - 1) / kBlock),
        cast_(size_t(blocksX_) * blocksY_, 0) {}

  // The blocks holding the rectangle's pixels, one pixel wider on every side (the GPU's ray-box tests round
  // otherwise than projectBox), clipped to the image.
  BlockRange blocksOf(const ScreenRect& r) const {
    if (r.empty()) return {};
    const auto clampX = [&](int32_t b) { return uint32_t(std::clamp<int32_t>(b, 0, int32_t(blocksX_))); };
    const auto clampY = [&](int32_t b) { return uint32_t(std::clamp<int32_t>(b, 0, int32_t(blocksY_))); };
    return {clampX((r.x0 - 1) / int32_t(kBlock)), clampY((r.y0 - 1) / int32_t(kBlock)),
            clampX(r.x1 / int32_t(kBlock) + 1), clampY(r.y1 / int32_t(kBlock) + 1)};
  }
  void add(const BlockRange& b) {
    for (uint32_t y = b.y0; y < b.y1; ++y) std::fill_n(&cast_[size_t(y) * blocksX_ + b.x0], b.x1 - b.x0, 1);
  }
  // How many of the range's blocks are cast: none, some or all.
  enum class Cover { None, Some, All };
  Cover cover(const BlockRange& b) const {
    size_t n = 0;
    for (uint32_t y = b.y0; y < b.y1; ++y)
      n += size_t(std::count(&cast_[size_t(y) * blocksX_ + b.x0], &cast_[size_t(y) * blocksX_ + b.x1], 1));
    const size_t all = size_t(b.x1 - b.x0) * (b.y1 - b.y0);
    return n == 0 ? Cover::None : n == all ? Cover::All : Cover::Some;
  }
  // The cast blocks as disjoint rectangles clipped to the image: runs along each row of blocks, a run
  // carried down while the next row has the same one.
  std::vector<PixelRect> rects(uint32_t width, uint32_t height) const {
    std::vector<BlockRange> open, done;
    for (uint32_t y = 0; y < blocksY_; ++y) {
      std::vector<BlockRange> next;
      for (uint32_t x = 0; x < blocksX_;) {
        if (!cast_[size_t(y) * blocksX_ + x]) {
          ++x;
          continue;
        }
        uint32_t end = x;
        while (end < blocksX_ && cast_[size_t(y) * blocksX_ + end]) ++end;
        const auto above = std::find_if(open.begin(), open.end(), [&](const BlockRange& r) {
          return r.x0 == x && r.x1 == end && r.y1 == y;
        });
        if (above != open.end()) {
          next.push_back({x, above->y0, end, y + 1});
          open.erase(above);
        } else {
          next.push_back({x, y, end, y + 1});
        }
        x = end;
      }
      done.insert(done.end(), open.begin(), open.end());
      open = std::move(next);
    }
    done.insert(done.end(), open.begin(), open.end());
    std::vector<PixelRect> out;
    out.reserve(done.size());
    for (const BlockRange& b : done) {
      const uint32_t x0 = b.x0 * kBlock, y0 = b.y0 * kBlock;
      out.push_back({x0, y0, std::min(b.x1 * kBlock, width) - x0, std::min(b.y1 * kBlock, height) - y0});
    }
    return out;
  }

 private:
  uint32_t blocksX_, blocksY_;
  std::vector<uint8_t> cast_;
};

}  // namespace

RecastPlan planRecast(const RecastInput& in) {
  if (!in.layout || !in.drawn || !in.leaves) throw Error("planRecast: layout, drawn and leaves are required");
  if (in.width == 0 || in.height == 0) throw Error("planRecast: empty image size");
  RecastPlan plan;
  BlockMask mask(in.width, in.height);
  const auto project = [&](const NodeKey& key) {
    const WorldBox box = nodeWorldBox(*in.layout, in.spacing, key);
    return projectBox(box.lo, box.hi, in.camera, in.width, in.height);
  };
  // The changed leaves' blocks; false when a box holds the eye (its rays cannot be bounded on the screen).
  const auto castBox = [&](const NodeKey& key) {
    const BoxProjection p = project(key);
    if (p.nearEye) return false;
    mask.add(mask.blocksOf(p.rect));
    return true;
  };

  std::unordered_set<NodeKey, NodeKeyHash> current;
  current.reserve(in.leaves->size());
  for (const PlannedLeaf& leaf : *in.leaves) {
    current.insert(leaf.key);
    const auto drawn = in.drawn->find(leaf.key);
    if (drawn != in.drawn->end() && drawn->second == drawnSlotOf(leaf)) continue;
    ++plan.changedLeaves;
    if (!castBox(leaf.key)) plan.whole = true;
  }
  for (const auto& [key, slot] : *in.drawn) {
    if (current.contains(key)) continue;
    ++plan.changedLeaves;
    if (!castBox(key)) plan.whole = true;
  }
  if (plan.whole) {
    plan.pixels = uint64_t(in.width) * in.height;
    return plan;
  }

  // The answered leaves, unchanged (a changed leaf's pixels are all cast), by how many of their blocks are.
  if (in.answered) {
    for (uint32_t i = 0; i < in.leaves->size(); ++i) {
      const PlannedLeaf& leaf = (*in.leaves)[i];
      if (leaf.content != LeafContent::Brick || !in.answered->contains(leaf.key)) continue;
      const BoxProjection p = project(leaf.key);
      const BlockMask::Cover cover = p.nearEye        ? BlockMask::Cover::Some
                                     : p.rect.empty() ? BlockMask::Cover::None
                                                      : mask.cover(mask.blocksOf(p.rect));
      if (cover != BlockMask::Cover::All) plan.keptIn.push_back(i);
      if (cover == BlockMask::Cover::None) plan.keptWhole.push_back(i);
    }
  }
  plan.rects = mask.rects(in.width, in.height);
  for (const PixelRect& r : plan.rects) plan.pixels += uint64_t(r.width) * r.height;
  return plan;
}

}  // namespace ropecast
