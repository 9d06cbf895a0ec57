// Refiner: the view- and transfer-function-dependent cut of the octree for one frame (Gobbetti et al. 2008,
// Sect. 4). From the root, a set of visible non-empty nodes sorted by decreasing projected voxel size is
// refined until each node is adequate, or the bricks of its children are not in core, or the GPU pool has no
// room for them, or the frame's upload budget is spent. Empty nodes (by the caller's predicate on the stored
// min/max, so changing the isovalue or the transfer function needs no I/O), nodes outside the data or the
// view frustum, and constant nodes are terminal. Hints from the previous frames' occlusion queries and ray
// feedback (NodeHints) stop refinement where nothing is seen and put the nodes the rays asked for first. The
// data path is reached only through BrickResidency, which the WorkingSet implements (and tests fake), so the
// refiner itself is pure CPU logic.
//
// Plain functions over plain data; any thread, given a BrickResidency used by that thread only.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/camera.h"
#include "core/render_params.h"
#include "core/world_box.h"
#include "store/brick_source.h"

namespace ropecast {

struct RefineView {
  Camera camera;
  uint32_t viewportWidth = 1;   // pixels
  uint32_t viewportHeight = 1;  // pixels
  // Target density: a node is adequate when one of its voxels covers at most 1 / voxelsPerPixel pixels
  // (1 = one voxel per pixel as in Gobbetti et al. 2008; 2 = finer, 0.5 = coarser).
  double voxelsPerPixel = 1.0;
  // The box the rays sample in (sampledWorldBox, core/render_params.h: the volume box cut to --crop): nodes
  // wholly outside it are culled like nodes outside the frustum, and a node's projected voxel size is
  // measured on its part inside it. Unbounded by default.
  WorldBox sampled = unboundedBox();
  // --clip-plane: nodes wholly on the side it cuts away are culled too, and from an eye on that side a node's
  // projected voxel size is measured no nearer than the plane. None by default.
  ClipPlane clipPlane;
  // --mode slice: the clip plane is the slice, the rays' only samples: nodes it does not cross are culled on
  // either side, and from any eye a node's projected voxel size is measured no nearer than the plane.
  bool slice = false;
};

// True when a node whose stored values span [storedMin, storedMax] cannot contribute to the image: for an
// isosurface, the range misses the isovalue; for DVR, !transferFunction.hasOpacity(storedMin, storedMax).
using EmptinessPredicate = std::function<bool(uint16_t storedMin, uint16_t storedMax)>;

enum class LeafContent : uint8_t {
  Empty,    // nothing to sample (empty, outside the data, the frustum or the crop box, behind the clip plane)
  Brick,    // sample the brick in `slot` of the GPU pool
  Missing,  // the root's brick is not in core yet (first frames of a cold start): render as empty
};

// Why a node is a leaf of the cut.
enum class LeafReason : uint8_t {
  Adequate,      // projected voxel size reached the target
  Finest,        // full-resolution node
  Empty,         // NodeKind::Empty or the emptiness predicate
  Outside,       // no data there (NodeKind::Outside)
  Culled,        // outside the view frustum, wholly outside RefineView::sampled (--crop), or wholly on the
                 // side RefineView::clipPlane cuts away
  Constant,      // every sample equal: children would look the same
  NotInCore,     // its children's bricks (or the root's) were requested and are not read yet
  PoolFull,      // the GPU pool cannot hold its children beside the rest of the cut, or a node before it
                 // could not (the pool goes to nodes in priority order)
  UploadBudget,  // this frame's upload budget cannot carry its children
  Occluded,      // NodeHint::Occluded
  Unused,        // NodeHint::Unused
};
const char* leafReasonName(LeafReason r);

// What the occlusion queries and the rays' feedback said about a node (render/ fills it from occlusion/ and
// the feedback readback).
enum class NodeHint : uint8_t {
  None,       // refine by priority, as without hints
  Occluded,   // hidden in the last answered occlusion queries: not refined (Gobbetti et al. 2008, Sect. 6)
  Unused,     // the rays' feedback answered for it and no ray used it: not refined (Crassin et al. 2009)
  Requested,  // a ray wanted finer data there: refined, with the Used nodes, before the rest
  // Sampled by the rays as far as they answered, or refined in the last frame and not called unused: ranked
  // with Requested, so that when the GPU pool is full a request does not displace bricks the rays are using
  // (a brick used in the last frame is not replaced; Crassin et al. 2009, Sect. 5). The two compete by
  // projected voxel size, which keeps the cut of a still view from alternating between two trees and makes
  // a full pool settle on the same cut whatever order its bricks came in.
  Used,
};
// Asked once per node the refinement or its read-ahead reaches (the root included), on the refining thread.
// Null: no hints.
using NodeHints = std::function<NodeHint(const NodeKey&)>;

struct PlannedLeaf {
  NodeKey key;
  LeafContent content = LeafContent::Empty;
  LeafReason reason = LeafReason::Empty;
  uint32_t slot = UINT32_MAX;  // GPU pool slot when content == Brick
  double voxelPixels = 0.0;    // projected voxel size that ordered it (0 when never measured)
};

// What the refiner asks of the data path.
class BrickResidency {
 public:
  enum class Outcome { Ready, NotInCore, PoolFull, UploadBudget };
  virtual ~BrickResidency() = default;
  // Either every node of `keys` gets a GPU slot holding (or being uploaded with) its brick, pinned for this
  // frame's tree, written to slotsOut (same order) and the result is Ready; or nothing changes in the tree
  // and the result says why (NotInCore also requests the missing bricks at `priority`). A refined node keeps
  // its slot pinned: the whole refined tree (inner nodes and the cut) stays on the GPU, so a converged tree
  // needs no upload in the next frame and zooming out needs none either. Called with an empty `keys` too (a
  // node whose children are all empty).
  virtual Outcome acquire(std::span<const NodeKey> keys, double priority, std::span<uint32_t> slotsOut) = 0;
  // How many bricks beyond those acquire() asked for may be read ahead (RefineResult::readAhead), asked once
  // after the refinement: the room left in the GPU pool and in the read requests. 0: no read-ahead.
  virtual size_t readAheadRoom() const { return 0; }
  // How many bricks may be read below the leaves the GPU pool had no room for
  // (RefineResult::poolFullReadAhead), asked once after a refinement that filled the pool. 0: none.
  virtual size_t poolFullReadAheadRoom() const { return 0; }
};

struct RefineResult {
  std::vector<PlannedLeaf> leaves;    // the cut: a tiling of the octree's root cube
  std::vector<NodeKey> refinedOrder;  // inner nodes, in the order they were refined
  // Data bricks the next refinements will ask for once those they wait for arrive, so that the reads need
  // not wait for frames: below each leaf waiting for its children (NotInCore, UploadBudget), the children of
  // every node that would then be refined (neither adequate nor finest, neither empty, culled, constant nor
  // hinted Occluded or Unused), level by level and by decreasing projected voxel size within a level, at most
  // BrickResidency::readAheadRoom(). Some may be resident already.
  std::vector<NodeKey> readAhead;
  // When the GPU pool filled: the data children of the PoolFull leaves, leaf by leaf in the order the
  // refinement reached them (priority), at most BrickResidency::poolFullReadAheadRoom(). They are what takes
  // the slots the next hints free (the bricks of nodes found occluded or unused are reused first), so with
  // them in core the frame that frees the slots fills them, instead of requesting them and waiting a frame
  // for the disk. Some may be in core already.
  std::vector<NodeKey> poolFullReadAhead;
  // No leaf waits for data or for upload budget: the next frame with the same input gives the same cut
  // (Occluded and Unused leaves wait for nothing the loader can do).
  bool complete = false;
};

// World-space box of a node, clipped to the data box [0, dims * spacing].
WorldBox nodeWorldBox(const OctreeLayout& layout, glm::dvec3 spacing, const NodeKey& key);
// The parts of a node's box that hold its data: the boxes of its children that are neither outside the
// volume nor empty (NodeKind::Empty or `isEmpty`), cut to `sampled` (the box the rays sample in, --crop), and
// leaving out those wholly outside it; the node's own box (cut to `sampled`) at the finest depth or when no
// child qualifies. What an occlusion query of the node tests: the box of an empty child would show where no
// ray meets the node's data. Drawn part by part under one query, the samples are the sum its children's
// answers gave, so a node collapsed because its data leaves were hidden answers hidden too (their bounding
// box, covering the gaps between them, could answer visible, refine the node, and hide its leaves again).
struct NodeDataParts {
  std::array<WorldBox, 8> boxes;
  uint32_t count = 0;
};
NodeDataParts nodeDataParts(const BrickSource& nodes, const EmptinessPredicate& isEmpty, const NodeKey& key,
                            const WorldBox& sampled);
// The parts' bounding box: where the node projects on the screen.
WorldBox boundingBox(const NodeDataParts& parts);

// Pixels covered by one voxel of the node's level, seen at the node's point nearest to the eye (distance
// clamped to half a full-resolution voxel, so a node containing the eye gets a very large value).
double projectedVoxelPixels(const OctreeLayout& layout, glm::dvec3 spacing, const NodeKey& key,
                            const RefineView& view);
// The same for many nodes of one view: what does not depend on the node is computed once.
class ProjectedVoxelSize {
 public:
  ProjectedVoxelSize(const OctreeLayout& layout, glm::dvec3 spacing, const RefineView& view);
  double operator()(const NodeKey& key) const;

 private:
  const OctreeLayout& layout_;
  glm::dvec3 spacing_;
  glm::dvec3 eye_;
  WorldBox sampled_;
  double planeDistance_;
  double minSpacing_, maxSpacing_;
  double tanHalfFov_;
  double viewportHeight_;
};

// The planes through the eye that bound what the view sees (behind, right, left, top, bottom), inward
// normals.
struct ViewFrustum {
  glm::dvec3 eye{0.0};
  std::array<glm::dvec3, 5> inwardNormals{};
};
ViewFrustum viewFrustum(const RefineView& view);

// False only when the box lies wholly on the side the plane cuts away, or beyond a face of its slab (touching
// counts as kept).
bool boxKeptByPlane(const WorldBox& box, const ClipPlane& plane);
// Whether the plane passes through the closed box (true for no plane).
bool boxMeetsPlane(const WorldBox& box, const ClipPlane& plane);

// False only when the box lies entirely outside the view frustum (behind the eye or beyond a side plane);
// conservative, so a visible box is never culled.
bool boxInFrustum(const WorldBox& box, const ViewFrustum& frustum);
inline bool boxInFrustum(const WorldBox& box, const RefineView& view) {
  return boxInFrustum(box, viewFrustum(view));
}

// Refinement order: Requested and Used nodes before all others, each group by decreasing projected voxel
// size. The root's brick is always acquired (a frame always needs the coarse cut); a hint stops a node's
// refinement after the Adequate and Finest tests, before its children are acquired or requested.
RefineResult refine(const BrickSource& nodes, const RefineView& view, const EmptinessPredicate& isEmpty,
                    BrickResidency& residency, const NodeHints& hints = {});

}  // namespace ropecast
