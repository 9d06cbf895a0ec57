// RayFeedback: what the rays said about the nodes they met (Crassin et al. 2009, Sect. 5-6), turned into
// refinement hints. The ray caster marks, per frame, the data leaves of the cut it sampled (used) and, at
// most one per ray, a leaf coarser than the ray wanted there (requested); the lists come back one or more
// frames later as indices into that frame's cut (render/feedback_buffer.h). This class keeps each frame's cut
// until its answer arrives, maps the indices to nodes, and answers per node:
//   Requested  requested in the latest answer that covered the node: refined before the rest;
//   Used       a node of the answered cut whose data a ray sampled (a leaf, or an inner node with such a
//              leaf below), or an inner node of the tree on the GPU now (the last frame's; the caller says)
//              that no answer calls unused: ranked with Requested, so the bricks the rays are using are not
//              given up for requests when the pool is full, and a used leaf that no ray requested (each ray
//              requests one leaf, the first it met too coarse) is not left behind nodes of smaller voxels
//              either. The tree now, not the answered one: answers come a frame or two late, and hints about
//              an older tree would let even and odd frames settle on different cuts;
//   Unused     a data leaf of the answered cut that no ray sampled, or an inner node of it with no used data
//              leaf below: not refined by priority alone;
//   None       not in the answered tree, or the answer is too old.
// An answer holds until a newer answer covers the node, at most answerLifetimeFrames frames after the frame
// it describes (the view may have moved since). usedNodes() are the leaves the latest answer saw used: their
// bricks are kept in the GPU pool first (LRU by use, loader/slot_table.h). hitByRays() says which leaves
// enough rays stopped in (at the isosurface, or by early ray termination): visible without an occlusion
// query.
//
// Plain CPU state, owned by the frame renderer: render thread only.
#pragma once

#include <cstdint>
#include <deque>
#include <span>
#include <unordered_map>
#include <vector>

#include "loader/refiner.h"
#include "store/octree_layout.h"

namespace ropecast {

struct RayFeedbackConfig {
  uint64_t answerLifetimeFrames = 8;
};

class RayFeedback {
 public:
  explicit RayFeedback(const RayFeedbackConfig& config = {}) : config_(config) {}

  // The cut frame `frame` was cast with, by cut index; dataLeaf[i] says whether leaf i held a brick.
  void rememberCut(uint64_t frame, std::vector<NodeKey> leaves, std::vector<uint8_t> dataLeaf);
  // The answer of frame `frame` (indices into its remembered cut). Answers come in frame order; cuts older
  // than it are forgotten. An answer for a frame whose cut is not remembered is ignored (returns false).
  // hitLeaves: the leaves in which the frame's hit threshold of rays stopped (FeedbackReadback::hitLeaves).
  bool answer(uint64_t frame, std::span<const uint32_t> usedLeaves, std::span<const uint32_t> requestedLeaves,
              std::span<const uint32_t> hitLeaves = {});

  // innerNodeNow: the node is an inner node of the tree on the GPU now (the caller keeps that tree).
  NodeHint hint(const NodeKey& key, uint64_t frame, bool innerNodeNow = false) const;
  // Whether the latest live answer about the leaf listed it among the hits.
  bool hitByRays(const NodeKey& key, uint64_t frame) const;
  const std::vector<NodeKey>& usedNodes() const { return usedNodes_; }
  // The frame of the latest answer, if any.
  bool answered() const { return answered_; }
  uint64_t answeredFrame() const { return answeredFrame_; }
  // For a frame cast without feedback because it draws the last frame's converged image again: its rays would
  // say what the held answers say, so those are renewed as if given about `frame` (answeredFrame() stays the
  // frame the rays last answered about; a later answer about an earlier frame does not replace them).
  void renew(uint64_t frame);
  // Forgets every answer and remembered cut (a change of isovalue or transfer function).
  void reset();

 private:
  struct NodeAnswer {
    uint64_t frame = 0;
    NodeHint hint = NodeHint::None;
    bool hit = false;
  };
  struct RememberedCut {
    uint64_t frame = 0;
    std::vector<NodeKey> leaves;
    std::vector<uint8_t> dataLeaf;
  };

  // The node's answer, unless it holds a newer one (renewed after the frame this one describes).
  void setAnswer(const NodeKey& key, NodeAnswer answer);
  // Not expired at `frame` (a renewed answer may be newer than `frame`).
  bool live(const NodeAnswer& answer, uint64_t frame) const {
    return frame <= answer.frame || frame - answer.frame <= config_.answerLifetimeFrames;
  }

  RayFeedbackConfig config_;
  std::deque<RememberedCut> cuts_;
  std::unordered_map<NodeKey, NodeAnswer, NodeKeyHash> answers_;
  std::vector<NodeKey> usedNodes_;
  bool answered_ = false;
  uint64_t answeredFrame_ = 0;
};

}  // namespace ropecast
