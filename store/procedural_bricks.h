// ProceduralBricks: a BrickSource over a procedural field (store/procedural.h) of SIZE^3, so that
// `ropecast render procedural:NAME:SIZE` needs no store, for SIZE up to 8192 and beyond. Stored type uint8,
// identity mapping. Owned by loader/; the loader's I/O workers call it like a store.
//
// node() never generates data: its min/max come from the field's conservative proceduralRange() over the
// node's whole box (its borders included, which also covers every descendant). A node whose range is a single
// value is Constant. readBrick() generates the brick at the node's level by point sampling the field at that
// level's sample centers: level-L sample g sits at level-0 position (g + 0.5) * 2^L, the center of the
// 2^L-wide box the store's box filter would average. Point sampling a coarse level aliases where the field
// has detail finer than 2^L samples (menger, noise); that is accepted for coarse levels, which are only shown
// when a voxel of them covers about a pixel. Borders replicate the edge sample at the volume edge (sample
// indices clamped to the level's dims), exactly like the store, so a brick's border equals its neighbor's
// interior.
//
// Threads: every method may be called from any number of threads at once (no mutable state).
#pragma once

#include <memory>
#include <string>

#include "store/brick_source.h"
#include "store/procedural.h"

namespace ropecast {

class ProceduralBricks : public BrickSource {
 public:
  explicit ProceduralBricks(const ProceduralField& field, uint32_t brickSize = kDefaultBrickSize,
                            glm::dvec3 spacing = glm::dvec3(1.0));

  const BrickSourceInfo& info() const override { return info_; }
  NodeInfo node(const NodeKey& key) const override;
  void readBrick(const NodeKey& key, std::span<std::byte> out) const override;

  const ProceduralField& field() const { return field_; }
  // The box (level-0 sample coordinates, clamped to the volume) that node() bounds for `key`.
  PositionBox nodeBox(const NodeKey& key) const;

 private:
  ProceduralField field_;
  BrickSourceInfo info_;
};

// `spec` is "procedural:NAME:SIZE" or "NAME:SIZE". Throws ropecast::Error naming the spec if it is malformed.
std::unique_ptr<ProceduralBricks> openProceduralBricks(const std::string& spec,
                                                       uint32_t brickSize = kDefaultBrickSize);

}  // namespace ropecast
