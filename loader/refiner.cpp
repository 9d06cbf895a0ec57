#include "loader/refiner.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <queue>
#include <tuple>
#include <utility>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

namespace ropecast {

const char* leafReasonName(LeafReason r) {
  static constexpr const char* kNames[] = {"adequate",      "finest",   "empty",       "outside",
                                           "culled",        "constant", "not-in-core", "pool-full",
                                           "upload-budget", "occluded", "unused"};
  static_assert(std::size(kNames) == size_t(LeafReason::Unused) + 1, "a name per LeafReason");
  return size_t(r) < std::size(kNames) ? kNames[size_t(r)] : "?";
}

WorldBox nodeWorldBox(const OctreeLayout& layout, glm::dvec3 spacing, const NodeKey& key) {
  const double edgeSamples = double(layout.brickSize) * double(uint64_t(1) << layout.levelOfDepth(key.depth));
  const glm::dvec3 dataHi = glm::dvec3(layout.dims) * spacing;
  WorldBox b;
  b.lo = glm::min(glm::dvec3(key.coord) * edgeSamples * spacing, dataHi);
  b.hi = glm::min(glm::dvec3(key.coord + 1u) * edgeSamples * spacing, dataHi);
  return b;
}

NodeDataParts nodeDataParts(const BrickSource& nodes, const EmptinessPredicate& isEmpty, const NodeKey& key,
                            const WorldBox& sampled) {
  const OctreeLayout& layout = nodes.info().layout;
  const glm::dvec3 spacing = nodes.info().volume.spacing;
  NodeDataParts parts;
  if (key.depth < layout.maxDepth) {
    for (uint32_t o = 0; o < 8; ++o) {
      const NodeKey child = key.child(o);
      if (!layout.isInside(child)) continue;
      const NodeInfo info = nodes.node(child);
      if (info.kind == NodeKind::Outside || info.kind == NodeKind::Empty) continue;
      if (isEmpty && isEmpty(info.minValue, info.maxValue)) continue;
      const WorldBox part = intersection(nodeWorldBox(layout, spacing, child), sampled);
      if (hasVolume(part)) parts.boxes[parts.count++] = part;
    }
  }
  if (parts.count == 0)
    parts.boxes[parts.count++] = intersection(nodeWorldBox(layout, spacing, key), sampled);
  return parts;
}

WorldBox boundingBox(const NodeDataParts& parts) {
  WorldBox box = parts.boxes[0];
  for (uint32_t i = 1; i < parts.count; ++i) {
    box.lo = glm::min(box.lo, parts.boxes[i].lo);
    box.hi = glm::max(box.hi, parts.boxes[i].hi);
  }
  return box;
}

namespace {
// How far the eye is at least from everything drawn: from the side a clip plane cuts away, or beyond a slab's
// face, the plane's (or the face's) distance; from a slice, the plane's on either side.
double keptDistance(const RefineView& view) {
  const ClipPlane& plane = view.clipPlane;
  if (!plane.enabled()) return 0.0;
  const double along = glm::dot(plane.normal, view.camera.eye);
  if (view.slice) return std::abs(plane.offset() - along);
  return std::max({0.0, plane.keptFrom() - along, along - plane.keptTo()});
}
}  // namespace

ProjectedVoxelSize::ProjectedVoxelSize(const OctreeLayout& layout, glm::dvec3 spacing, const RefineView& view)
    : layout_(layout),
      spacing_(spacing),
      eye_(view.camera.eye),
      sampled_(view.sampled),
      planeDistance_(keptDistance(view)),
      minSpacing_(std::min({spacing.x, spacing.y, spacing.z})),
      maxSpacing_(std::max({spacing.x, spacing.y, spacing.z})),
      tanHalfFov_(std::tan(glm::radians(view.camera.fovYDeg) * 0.5)),
      viewportHeight_(double(view.viewportHeight)) {}

double ProjectedVoxelSize::operator()(const NodeKey& key) const {
  const WorldBox whole = nodeWorldBox(layout_, spacing_, key);
  const WorldBox inside = intersection(whole, sampled_);
  const WorldBox& box = hasVolume(inside) ? inside : whole;
  const glm::dvec3 nearest = glm::clamp(eye_, box.lo, box.hi);
  const double distance = std::max({glm::length(nearest - eye_), planeDistance_, 0.5 * minSpacing_});
  const double voxelWorld = double(uint64_t(1) << layout_.levelOfDepth(key.depth)) * maxSpacing_;
  return voxelWorld / (2.0 * distance * tanHalfFov_) * viewportHeight_;
}

double projectedVoxelPixels(const OctreeLayout& layout, glm::dvec3 spacing, const NodeKey& key,
                            const RefineView& view) {
  return ProjectedVoxelSize(layout, spacing, view)(key);
}

ViewFrustum viewFrustum(const RefineView& view) {
  const CameraFrame f = cameraFrame(view.camera);
  const double ty = std::tan(glm::radians(view.camera.fovYDeg) * 0.5);
  const double tx = ty * double(view.viewportWidth) / double(std::max(view.viewportHeight, 1u));
  return {view.camera.eye,
          {f.forward, f.forward * tx - f.right, f.forward * tx + f.right, f.forward * ty - f.up,
           f.forward * ty + f.up}};
}

namespace {
// The least and the largest dot(n, x) over the box: at its corners nearest and farthest along n.
std::pair<double, double> rangeAlong(const WorldBox& box, glm::dvec3 n) {
  const glm::dvec3 nearest(n.x >= 0 ? box.lo.x : box.hi.x, n.y >= 0 ? box.lo.y : box.hi.y,
                           n.z >= 0 ? box.lo.z : box.hi.z);
  const glm::dvec3 farthest(n.x >= 0 ? box.hi.x : box.lo.x, n.y >= 0 ? box.hi.y : box.lo.y,
                            n.z >= 0 ? box.hi.z : box.lo.z);
  return {glm::dot(n, nearest), glm::dot(n, farthest)};
}
}  // namespace

bool boxKeptByPlane(const WorldBox& box, const ClipPlane& plane) {
  if (!plane.enabled()) return true;
  const auto [least, largest] = rangeAlong(box, plane.normal);
  return largest >= plane.keptFrom() && least <= plane.keptTo();
}

bool boxMeetsPlane(const WorldBox& box, const ClipPlane& plane) {
  if (!plane.enabled()) return true;
  const auto [least, largest] = rangeAlong(box, plane.normal);
  return least <= plane.offset() && largest >= plane.offset();
}

bool boxInFrustum(const WorldBox& box, const ViewFrustum& frustum) {
  for (const glm::dvec3& n : frustum.inwardNormals) {
    // The box corner farthest along n: if even it is behind the plane, the whole box is.
    const glm::dvec3 corner(n.x >= 0 ? box.hi.x : box.lo.x, n.y >= 0 ? box.hi.y : box.lo.y,
                            n.z >= 0 ? box.hi.z : box.lo.z);
    if (glm::dot(n, corner - frustum.eye) < 0.0) return false;
  }
  return true;
}

namespace {

struct Candidate {
  NodeKey key;
  double voxelPixels;
  uint32_t slot;
  NodeHint hint;
};

// Nodes the rays asked for or use first, then larger projected voxels first; ties in a fixed node order so
// the cut does not depend on history.
bool wantedByRays(NodeHint h) {
  return h == NodeHint::Requested || h == NodeHint::Used;
}
struct LowerPriority {
  bool operator()(const Candidate& a, const Candidate& b) const {
    const bool aWanted = wantedByRays(a.hint), bWanted = wantedByRays(b.hint);
    if (aWanted != bWanted) return bWanted;
    if (a.voxelPixels != b.voxelPixels) return a.voxelPixels < b.voxelPixels;
    return std::tie(b.key.depth, b.key.coord.z, b.key.coord.y, b.key.coord.x) <
           std::tie(a.key.depth, a.key.coord.z, a.key.coord.y, a.key.coord.x);
  }
};

enum class Class { NoBrick, ConstantBrick, DataBrick };

struct Classified {
  Class cls;
  LeafReason reason;  // for NoBrick
};

class RefineRun {
 public:
  RefineRun(const BrickSource& nodes, const RefineView& view, const EmptinessPredicate& isEmpty,
            BrickResidency& residency, const NodeHints& hints)
      : nodes_(nodes),
        layout_(nodes.info().layout),
        spacing_(nodes.info().volume.spacing),
        isEmpty_(isEmpty),
        residency_(residency),
        hints_(hints),
        frustum_(viewFrustum(view)),
        sampled_(view.sampled),
        clipPlane_(view.clipPlane),
        slice_(view.slice),
        voxelPixels_(layout_, spacing_, view),
        adequatePixels_(1.0 / std::max(view.voxelsPerPixel, 1e-9)) {}

  RefineResult run() {
    const NodeKey root{};
    const Classified c = classify(root);
    const double rootPixels = pixels(root);
    if (c.cls == Class::NoBrick) {
      leaf(root, LeafContent::Empty, c.reason, UINT32_MAX, 0.0);
    } else {
      uint32_t slot = UINT32_MAX;
      const auto outcome = residency_.acquire(std::span(&root, 1), rootPixels, std::span(&slot, 1));
      if (outcome != BrickResidency::Outcome::Ready) {
        leaf(root, LeafContent::Missing, reasonOf(outcome), UINT32_MAX, rootPixels);
      } else if (c.cls == Class::ConstantBrick) {
        leaf(root, LeafContent::Brick, LeafReason::Constant, slot, rootPixels);
      } else {
        heap_.push({root, rootPixels, slot, hintOf(root)});
      }
    }
    while (!heap_.empty()) {
      const Candidate n = heap_.top();
      heap_.pop();
      refineOrStop(n);
    }
    readAhead(residency_.readAheadRoom());
    if (poolFull_) readBelowPoolFull(residency_.poolFullReadAheadRoom());
    result_.complete = complete_;
    return std::move(result_);
  }

 private:
  void refineOrStop(const Candidate& n) {
    if (n.voxelPixels <= adequatePixels_) return leaf(n, LeafReason::Adequate);
    if (n.key.depth >= layout_.maxDepth) return leaf(n, LeafReason::Finest);
    if (n.hint == NodeHint::Occluded) return leaf(n, LeafReason::Occluded);
    if (n.hint == NodeHint::Unused) return leaf(n, LeafReason::Unused);

    std::array<NodeKey, 8> children;
    std::array<Classified, 8> classes;
    std::array<NodeKey, 8> withBrick;
    std::array<uint32_t, 8> slots;
    size_t brickCount = 0;
    for (uint32_t o = 0; o < 8; ++o) {
      children[o] = n.key.child(o);
      classes[o] = classify(children[o]);
      if (classes[o].cls != Class::NoBrick) withBrick[brickCount++] = children[o];
    }
    // The pool goes to nodes in priority order: once a node's children do not fit, no node after it takes
    // slots, though one with fewer data children would fit. Otherwise which node fits the rest depends on the
    // hints' order, which the next frame's feedback changes, and a full pool swaps nodes every frame.
    if (poolFull_ && brickCount > 0) return leaf(n, LeafReason::PoolFull);
    const auto outcome = residency_.acquire(std::span(withBrick.data(), brickCount), n.voxelPixels,
                                            std::span(slots.data(), brickCount));
    if (outcome == BrickResidency::Outcome::PoolFull) poolFull_ = true;
    if (outcome != BrickResidency::Outcome::Ready) return leaf(n, reasonOf(outcome));

    result_.refinedOrder.push_back(n.key);
    size_t b = 0;
    for (uint32_t o = 0; o < 8; ++o) {
      const NodeKey& k = children[o];
      if (classes[o].cls == Class::NoBrick) {
        leaf(k, LeafContent::Empty, classes[o].reason, UINT32_MAX, 0.0);
        continue;
      }
      const uint32_t slot = slots[b++];
      const double px = pixels(k);
      if (classes[o].cls == Class::ConstantBrick) {
        leaf(k, LeafContent::Brick, LeafReason::Constant, slot, px);
      } else {
        heap_.push({k, px, slot, hintOf(k)});
      }
    }
  }

  // RefineResult::readAhead: a breadth-first walk below the waiting leaves, as the next frames would refine
  // with every brick in core, so that a cold start reads the tree in about one wave instead of one per level.
  void readAhead(size_t room) {
    if (room == 0) return;
    struct Wanted {
      NodeKey key;
      double voxelPixels;
    };
    std::vector<Wanted> wanted;  // nodes whose bricks are being read: the waiting leaves' children
    for (const PlannedLeaf& l : result_.leaves) {
      if (l.reason != LeafReason::NotInCore && l.reason != LeafReason::UploadBudget) continue;
      if (l.content == LeafContent::Missing) {
        wanted.push_back({l.key, l.voxelPixels});
        continue;
      }
      for (uint32_t o = 0; o < 8; ++o) {
        const NodeKey c = l.key.child(o);
        if (classify(c).cls == Class::DataBrick) wanted.push_back({c, pixels(c)});
      }
    }
    std::vector<NodeKey>& ahead = result_.readAhead;
    while (!wanted.empty() && ahead.size() < room) {
      std::stable_sort(wanted.begin(), wanted.end(),
                       [](const Wanted& a, const Wanted& b) { return a.voxelPixels > b.voxelPixels; });
      std::vector<Wanted> next;
      for (const Wanted& w : wanted) {
        if (ahead.size() >= room) break;
        if (w.voxelPixels <= adequatePixels_ || w.key.depth >= layout_.maxDepth) continue;
        const NodeHint hint = hintOf(w.key);
        if (hint == NodeHint::Occluded || hint == NodeHint::Unused) continue;
        for (uint32_t o = 0; o < 8 && ahead.size() < room; ++o) {
          const NodeKey c = w.key.child(o);
          if (classify(c).cls != Class::DataBrick) continue;  // constant bricks need no read
          ahead.push_back(c);
          next.push_back({c, pixels(c)});
        }
      }
      wanted = std::move(next);
    }
  }

  // RefineResult::poolFullReadAhead.
  void readBelowPoolFull(size_t room) {
    std::vector<NodeKey>& ahead = result_.poolFullReadAhead;
    for (const PlannedLeaf& l : result_.leaves) {
      if (ahead.size() >= room) break;
      if (l.reason != LeafReason::PoolFull) continue;
      for (uint32_t o = 0; o < 8 && ahead.size() < room; ++o) {
        const NodeKey c = l.key.child(o);
        if (classify(c).cls == Class::DataBrick) ahead.push_back(c);
      }
    }
  }

  Classified classify(const NodeKey& k) const {
    const NodeInfo info = layout_.isInside(k) ? nodes_.node(k) : NodeInfo{};
    if (info.kind == NodeKind::Outside) return {Class::NoBrick, LeafReason::Outside};
    if (info.kind == NodeKind::Empty || (isEmpty_ && isEmpty_(info.minValue, info.maxValue))) {
      return {Class::NoBrick, LeafReason::Empty};
    }
    const WorldBox box = nodeWorldBox(layout_, spacing_, k);
    if (!hasVolume(intersection(box, sampled_)) || !boxKeptByPlane(box, clipPlane_) ||
        (slice_ && !boxMeetsPlane(box, clipPlane_)) || !boxInFrustum(box, frustum_))
      return {Class::NoBrick, LeafReason::Culled};
    return {info.kind == NodeKind::Constant ? Class::ConstantBrick : Class::DataBrick, LeafReason::Adequate};
  }

  double pixels(const NodeKey& k) const { return voxelPixels_(k); }
  NodeHint hintOf(const NodeKey& k) const { return hints_ ? hints_(k) : NodeHint::None; }

  static LeafReason reasonOf(BrickResidency::Outcome o) {
    switch (o) {
      case BrickResidency::Outcome::NotInCore:
        return LeafReason::NotInCore;
      case BrickResidency::Outcome::PoolFull:
        return LeafReason::PoolFull;
      case BrickResidency::Outcome::UploadBudget:
        return LeafReason::UploadBudget;
      case BrickResidency::Outcome::Ready:
        break;
    }
    return LeafReason::Adequate;
  }

  void leaf(const Candidate& n, LeafReason reason) {
    leaf(n.key, LeafContent::Brick, reason, n.slot, n.voxelPixels);
  }
  void leaf(const NodeKey& k, LeafContent content, LeafReason reason, uint32_t slot, double px) {
    if (reason == LeafReason::NotInCore || reason == LeafReason::UploadBudget) complete_ = false;
    result_.leaves.push_back({k, content, reason, slot, px});
  }

  const BrickSource& nodes_;
  const OctreeLayout& layout_;
  glm::dvec3 spacing_;
  const EmptinessPredicate& isEmpty_;
  BrickResidency& residency_;
  const NodeHints& hints_;
  ViewFrustum frustum_;
  WorldBox sampled_;
  ClipPlane clipPlane_;
  bool slice_;
  ProjectedVoxelSize voxelPixels_;
  double adequatePixels_;
  std::priority_queue<Candidate, std::vector<Candidate>, LowerPriority> heap_;
  RefineResult result_;
  bool complete_ = true;
  bool poolFull_ = false;  // a node's children did not fit in the GPU pool
};

}  // namespace

RefineResult refine(const BrickSource& nodes, const RefineView& view, const EmptinessPredicate& isEmpty,
                    BrickResidency& residency, const NodeHints& hints) {
  return RefineRun(nodes, view, isEmpty, residency, hints).run();
}

}  // namespace ropecast
