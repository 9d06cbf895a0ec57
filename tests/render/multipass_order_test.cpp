// sortFrontToBack (render/multipass_pass.h), the order of the multi-pass renderer's blocks: for eyes outside
// and inside the volume, every two leaves that share a face come with the one on the eye's side of that face
// first, on a cut of mixed depths. (Two boxes no ray from the eye passes through both may come in any order.)
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "loader/refiner.h"
#include "render/multipass_pass.h"

namespace ropecast {
namespace {

// Depth 1 everywhere but in octant (1, 0, 1), refined to depth 2, and its child (2, 1, 3) to depth 3.
std::vector<MultipassLeaf> mixedCut() {
  std::vector<MultipassLeaf> leaves;
  for (uint32_t i = 0; i < 8; ++i) {
    const glm::u32vec3 c(i & 1, (i >> 1) & 1, (i >> 2) & 1);
    if (c != glm::u32vec3(1, 0, 1)) {
      leaves.push_back({NodeKey{1, c}, i});
      continue;
    }
    for (uint32_t j = 0; j < 8; ++j) {
      const glm::u32vec3 d = c * 2u + glm::u32vec3(j & 1, (j >> 1) & 1, (j >> 2) & 1);
      if (d != glm::u32vec3(2, 1, 3)) {
        leaves.push_back({NodeKey{2, d}, 8 + j});
        continue;
      }
      for (uint32_t k = 0; k < 8; ++k)
        leaves.push_back({NodeKey{3, d * 2u + glm::u32vec3(k & 1, (k >> 1) & 1, (k >> 2) & 1)}, 16 + k});
    }
  }
  return leaves;
}

TEST(MultipassOrder, NeighboursComeFrontToBackForEveryEye) {
  const OctreeLayout layout = OctreeLayout::forVolume({64, 64, 64}, 8);
  ASSERT_EQ(layout.maxDepth, 3u);
  const glm::dvec3 spacing(1.0, 0.5, 2.0);
  const glm::dvec3 boxMax = glm::dvec3(layout.dims) * spacing;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.5, 1.5);
  for (int trial = 0; trial < 200; ++trial) {
    const glm::dvec3 eye = glm::dvec3(u(rng), u(rng), u(rng)) * boxMax;
    std::vector<MultipassLeaf> leaves = mixedCut();
    sortFrontToBack(leaves, layout, spacing, eye);
    for (size_t i = 0; i < leaves.size(); ++i)
      for (size_t j = 0; j < leaves.size(); ++j) {
        const WorldBox a = nodeWorldBox(layout, spacing, leaves[i].key);
        const WorldBox b = nodeWorldBox(layout, spacing, leaves[j].key);
        for (int axis = 0; axis < 3; ++axis) {
          // a below b on this axis, touching, overlapping on the two others: the plane is a.hi = b.lo.
          if (a.hi[axis] != b.lo[axis]) continue;
          bool overlap = true;
          for (int o = 1; o < 3; ++o) {
            const int x = (axis + o) % 3;
            overlap = overlap && a.lo[x] < b.hi[x] && b.lo[x] < a.hi[x];
          }
          if (!overlap || eye[axis] == a.hi[axis]) continue;
          const bool aFirst = eye[axis] < a.hi[axis];
          EXPECT_EQ(i < j, aFirst) << "trial " << trial << ": leaves " << i << " and " << j << " on axis "
                                   << axis;
        }
      }
  }
}

}  // namespace
}  // namespace ropecast
