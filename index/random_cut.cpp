// Random cuts by repeated random splits.
#include "index/random_cut.h"

#include <algorithm>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>

namespace ropecast {

Cut makeRandomCut(const RandomCutParams& params) {
  if (params.maxDepth > kCutMaxDepth)
    throw std::invalid_argument("makeRandomCut: maxDepth " + std::to_string(params.maxDepth) + " exceeds " +
                                std::to_string(kCutMaxDepth));
  std::mt19937_64 rng(params.seed);
  Cut cut;
  cut.leaves.push_back(CutLeaf{});
  // Leaves that may still be split, as indices into cut.leaves (swap-and-pop keeps the pick O(1)).
  std::vector<uint32_t> splittable;
  if (params.maxDepth > 0) splittable.push_back(0);
  while (cut.leaves.size() < params.targetLeaves && !splittable.empty()) {
    const size_t pick = std::uniform_int_distribution<size_t>(0, splittable.size() - 1)(rng);
    const uint32_t parentIndex = splittable[pick];
    std::swap(splittable[pick], splittable.back());
    splittable.pop_back();
    const CutLeaf parent = cut.leaves[parentIndex];
    for (uint32_t octant = 0; octant < 8; ++octant) {
      CutLeaf child;
      child.depth = parent.depth + 1;
      child.coord = parent.coord * 2u + glm::u32vec3(octant & 1u, (octant >> 1) & 1u, (octant >> 2) & 1u);
      // The first child reuses the parent's entry so the vector holds only leaves.
      uint32_t childIndex = parentIndex;
      if (octant == 0) {
        cut.leaves[parentIndex] = child;
      } else {
        childIndex = uint32_t(cut.leaves.size());
        cut.leaves.push_back(child);
      }
      if (child.depth < params.maxDepth) splittable.push_back(childIndex);
    }
  }
  std::bernoulli_distribution empty(std::clamp(params.emptyFraction, 0.0f, 1.0f));
  uint32_t nextSlot = 0;
  for (CutLeaf& leaf : cut.leaves) {
    leaf.kind = empty(rng) ? LeafKind::Empty : LeafKind::Data;
    leaf.brickSlot = leaf.kind == LeafKind::Data ? nextSlot++ : 0;
  }
  return cut;
}

}  // namespace ropecast
