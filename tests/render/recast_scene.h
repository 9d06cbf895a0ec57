// The scene of the recast CPU tests (recast_plan_test, recast_tracker_test): a 256^3 volume of 32^3 bricks
// seen from an orbit, its cut every node of depth 2 but for those refined into their children. Test thread.
#pragma once

#include <algorithm>
#include <vector>

#include "render/recast_plan.h"

namespace ropecast::test {

struct RecastScene {
  static constexpr uint32_t kWidth = 160, kHeight = 120;
  OctreeLayout layout = OctreeLayout::forVolume({256, 256, 256}, 32);  // finest leaves at depth 3
  Camera camera = orbitCamera(30.0, 20.0, 1.6, glm::dvec3(0.0), glm::dvec3(256.0));

  // Every node of depth 2 a leaf holding a slot of its own, but for `refined` (depth 2) whose children hold
  // slots.
  std::vector<PlannedLeaf> cut(const std::vector<NodeKey>& refined = {}) const {
    std::vector<PlannedLeaf> leaves;
    for (uint32_t z = 0; z < 4; ++z)
      for (uint32_t y = 0; y < 4; ++y)
        for (uint32_t x = 0; x < 4; ++x) {
          const NodeKey key{2, {x, y, z}};
          if (std::find(refined.begin(), refined.end(), key) != refined.end()) {
            for (uint32_t octant = 0; octant < 8; ++octant)
              leaves.push_back({key.child(octant), LeafContent::Brick, LeafReason::Finest, 1000 + octant});
            continue;
          }
          leaves.push_back({key, LeafContent::Brick, LeafReason::Adequate, x + 4 * y + 16 * z});
        }
    return leaves;
  }
  // The view, without the cuts.
  RecastInput view() const {
    RecastInput in;
    in.camera = camera;
    in.width = kWidth;
    in.height = kHeight;
    in.layout = &layout;
    return in;
  }
};

}  // namespace ropecast::test
