// VisibilityTracker: the CPU half of the occlusion feedback of Gobbetti et al. 2008, Sect. 6. Each frame it
// picks which leaves of the cut to query (through planTiles), takes the queries' answers when they come back,
// marks nodes visible or occluded, and tells the refiner which nodes not to refine, so that GPU slots and
// loads go to the visible part of the volume. The GL side (issuing the queries after tiles[0], collecting
// answers frames later) lives in render/.
//
// Owned by the render thread's frame renderer. Not thread-safe: the render thread only.
//
// A frame, in order: answer() for each query result that came back; propagate() with the last cut's
// non-empty leaves; refinement, asking isOccluded() before refining a node; plan() with the new cut's
// non-empty leaves; ray cast tiles[0], issue the planned queries, ray cast the other tiles. A frame that
// draws the last one's image again calls renew() instead of plan() and queries nothing.
//
// How marks age. A leaf's answer is occluded when fewer than thresholdPixels samples passed. An occluded mark
// holds until the node's next answer, and at most markLifetimeFrames after the frame its query was issued
// in; after that the node counts visible again. A node in the cut is queried again every round (every leaf of
// the cut once, over a few frames), so its mark stays fresh while it is in the cut (as long as a round and an
// answer's delay take fewer frames than markLifetimeFrames); a camera move that uncovers it is caught when
// its next query in the round answers. An inner node's mark comes from its leaves (propagate) and ages with
// the oldest answer below it, so a node collapsed because its children were occluded keeps its mark until it
// is queried itself or the mark expires. A change of isovalue or transfer function changes what occludes
// what: the caller calls reset(), which forgets every mark.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "occlusion/screen_rect.h"
#include "occlusion/tile_plan.h"
#include "store/octree_layout.h"

namespace ropecast {

struct VisibilityConfig {
  TilePlanConfig tiles;
  uint64_t thresholdPixels = 4;  // --visibility-threshold: fewer visible samples => occluded
  // An answer holds at most this many frames after the frame its query was issued in.
  uint64_t markLifetimeFrames = 64;
};

// A non-empty leaf of this frame's cut.
struct LeafToQuery {
  NodeKey key;
  BoxProjection projection;
  bool hitByRays = false;  // marked visible by markHit: counted, not queried
};

struct FrameQueryPlan {
  std::vector<ScreenRect> tiles;  // as TilePlan::tiles: tiles[0] first, then the queries, then the others
  std::vector<NodeKey> queries;   // leaves to query after tiles[0], each projecting entirely inside it
  std::vector<uint32_t> queriedIndices;  // the same leaves, as indices into the span given to plan()
};

// Over the leaves given to the last plan().
struct VisibilityCounts {
  uint64_t visible = 0, occluded = 0;
};

class VisibilityTracker {
 public:
  explicit VisibilityTracker(const VisibilityConfig& config);

  // Plans frame `frame`: tiles and which leaves to query. Candidates are the leaves not yet queried in the
  // current round (nearEye leaves, and leaves projecting outside the viewport, are never queried and count
  // visible; leaves hitByRays keep the mark markHit gave them and are not queried); when every leaf of the
  // cut has been queried in this round, a new round starts. A leaf whose rect straddles the splits stays in
  // the round for later frames, where fewer candidates remain, so that each round ends in a bounded number of
  // frames (at worst the remaining ones fit the budget and are planned at the top level with tiles[0] = the
  // whole viewport). With no candidates: one tile, the whole viewport, no queries. Also forgets expired
  // marks. `frame` must not decrease between calls.
  FrameQueryPlan plan(uint64_t frame, uint32_t width, uint32_t height, std::span<const LeafToQuery> leaves);

  // A query's answer, collected in a later frame: the node, the frame its query was issued in, samples
  // passed. An answer older than the node's current mark, or issued before the last reset(), is ignored.
  void answer(const NodeKey& key, uint64_t issuedFrame, uint64_t samplesPassed);
  // Instead of plan(), for a frame that draws the image of the last planned frame again (the same view and
  // cut, and marks that kept that cut): its queries would answer as the held marks say, so none is planned
  // and every live mark is renewed as if answered so at `frame`. The round stands as it was.
  void renew(uint64_t frame);
  // A leaf known hidden without a query (no ray reached it: the rays' feedback), left out of plan(): marked
  // as an answer of 0 samples to a query issued in `frame` would mark it, but counted in no round. Like a
  // query's answer, the mark holds until the leaf's next answer (handed to plan() again, it is queried).
  void markUnseen(const NodeKey& key, uint64_t frame);
  // A leaf known visible without a query: at least thresholdPixels rays of frame `frame` stopped in it (at
  // the isosurface, or by early ray termination), which puts as many samples of its box in front of the depth
  // its query would be drawn against (the rays' feedback). Marked as an answer of thresholdPixels samples to
  // a query issued in `frame` would mark it, and replaces a query's answer about the same frame; counted in
  // no round. plan() leaves it unqueried when its LeafToQuery says hitByRays.
  void markHit(const NodeKey& key, uint64_t frame);

  // Propagation to parents (Gobbetti et al. 2008, Sect. 6: an inner node is visible when any child is): given
  // the last cut's non-empty leaves, every inner node above them gets a mark from the visible samples of its
  // leaves together: occluded when their sum is below the threshold (a leaf never answered, or whose answer
  // expired at the last plan()'s frame, counts as visible on its own), with the age of the oldest answer
  // below it. The sum, not "any child": a node whose box shows a few pixels spread over children that each
  // show fewer than the threshold is visible, as its own query would say; with "any child" it would collapse,
  // be queried, answer visible, refine, and collapse again. A node collapsed because its leaves were occluded
  // keeps its mark until it is queried itself.
  void propagate(std::span<const NodeKey> nonEmptyLeaves);

  // Whether the refiner should treat the node as occluded at frame `frame`: it has an unexpired occluded
  // mark.
  bool isOccluded(const NodeKey& key, uint64_t frame) const;
  // Every node isOccluded() says is occluded at frame `frame`, into `out` (cleared first; in no particular
  // order): the nodes whose bricks the loader reuses first (FrameInput::hiddenNodes). One pass over the
  // marks.
  void occludedNodes(uint64_t frame, std::vector<NodeKey>& out) const;

  // Clears every mark and the round (a change of isovalue or transfer function changes what occludes what);
  // answers to queries issued before the next plan() are ignored. lastRoundFrames() and
  // answeredSince() start over.
  void reset();

  // Of the leaves handed to the last plan().
  VisibilityCounts counts(uint64_t frame) const;

  // Frames the last completed round took (every leaf of the cut queried once); 0 before the first round
  // ends. The query latency is this plus the frames an answer takes to come back.
  uint64_t lastRoundFrames() const { return lastRoundFrames_; }

  // True when every query of a round planned at frame `frame` or later has been answered, or when the last
  // plan(), at `frame` or later, had no leaf to query. Then the marks describe what the cut drawn since
  // `frame` hides: if the refinement with them kept that cut, the cut is a fixed point of the queries.
  bool answeredSince(uint64_t frame) const;

  uint64_t thresholdPixels() const { return config_.thresholdPixels; }
  // Marks held (leaves' answers and inner nodes' propagated marks), for tests and statistics.
  size_t markCount() const { return marks_.size(); }

 private:
  struct Mark {
    uint64_t issuedFrame = 0;  // the frame of the query, or of the oldest answer below an inner node
    bool occluded = false;
    uint64_t samples = 0;  // visible samples: the query's, or the sum below an inner node
  };
  // Not expired at `frame` (written without the sum, which a lifetime of UINT64_MAX would overflow).
  bool live(const Mark& m, uint64_t frame) const {
    return frame <= m.issuedFrame || frame - m.issuedFrame <= config_.markLifetimeFrames;
  }
  bool occludedAt(const NodeKey& key, uint64_t frame) const;
  // Whether `mark`, the node's, makes it occluded at `frame`.
  bool occludedBy(const NodeKey& key, const Mark& mark, uint64_t frame) const;
  void finishRound();
  // The node's mark from an answer of `samplesPassed` to a query issued in `issuedFrame`, unless it holds a
  // newer one.
  void setMark(const NodeKey& key, uint64_t issuedFrame, uint64_t samplesPassed);

  // A round of queries and how many of its answers came back; answeredRoundFrame_: the first frame of the
  // latest round whose answers all came back.
  struct RoundAnswers {
    uint64_t firstFrame = 0, lastFrame = 0;
    uint64_t issued = 0, answered = 0;
    bool finished = false;  // every leaf of the cut queried: no more queries join it
  };
  void countAnswer(uint64_t issuedFrame);
  void dropAnsweredRounds();

  VisibilityConfig config_;
  std::unordered_map<NodeKey, Mark, NodeKeyHash> marks_;

  std::vector<NodeKey> lastLeaves_;                       // of the last plan()
  std::unordered_set<NodeKey, NodeKeyHash> unqueryable_;  // of those: nearEye or outside the viewport
  uint64_t lastPlanFrame_ = 0;

  // The current round: leaves of the cut queried in it, and the plan() calls it has taken so far.
  std::unordered_set<NodeKey, NodeKeyHash> roundQueried_;
  uint64_t roundFrames_ = 0;
  uint64_t lastRoundFrames_ = 0;
  std::vector<RoundAnswers> rounds_;  // the current round, then finished ones with answers outstanding
  std::optional<uint64_t> answeredRoundFrame_;
  std::optional<uint64_t> nothingToQueryFrame_;  // the last plan()'s frame if it had no leaf to query

  // After reset(): answers issued before this frame are dropped (dropAll_ until the next plan() sets it).
  uint64_t firstValidFrame_ = 0;
  bool dropAll_ = false;
};

}  // namespace ropecast
