// OcclusionQueries: the GL side of the visibility feedback (Gobbetti et al. 2008, Sect. 6). issue() counts,
// for each node, the samples of its boxes (up to 8) that pass the depth test where the ray caster left the
// depth at which each ray stopped: what a GL_SAMPLES_PASSED query per node counts (front faces only, so a
// pixel counts once per box; no color or depth writes; depth clamped so a box reaching the near plane is not
// clipped away), for every node of the frame in one instanced draw whose fragment shader adds to a counter
// per node (shaders/occlusion_box.frag). A query object per node would cost a begin, a draw and an end
// each, which with thousands of nodes a frame costs more than drawing their boxes. The counters are copied
// into a persistently mapped buffer and fenced; collect() takes, in a later frame, the frames whose fence has
// signaled and leaves the others pending: it never waits. Planning which nodes to query is occlusion/'s
// (VisibilityTracker); this class only asks and hears back.
//
// Owns GL objects: render thread only, with the GlContext current.
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/camera.h"
#include "loader/refiner.h"
#include "render/gl_fence.h"
#include "render/raycast_uniforms.h"
#include "shaders/occlusion_layout.h"
#include "store/octree_layout.h"

namespace ropecast {

class ShaderProgram;

// One query: the node and the boxes drawn under it (world space), their samples counted together.
struct QueryBox {
  NodeKey key;
  NodeDataParts parts;
};

struct QueryAnswer {
  NodeKey key;
  uint64_t issuedFrame = 0;
  uint64_t samplesPassed = 0;
};

class OcclusionQueries {
 public:
  // A null probe asks GL whether a frame's counts have arrived.
  explicit OcclusionQueries(std::unique_ptr<FenceProbe> probe = nullptr);
  ~OcclusionQueries();
  OcclusionQueries(const OcclusionQueries&) = delete;
  OcclusionQueries& operator=(const OcclusionQueries&) = delete;

  // Frames of queries in flight at most: with that many whose fences have not signaled (a GPU far behind, or
  // a driver that never signals), issue() draws nothing, so memory and GPU work stay bounded; the queries
  // it skips are never answered, and the tracker plans their nodes again in a later round.
  static constexpr size_t kMaxBatchesInFlight = 8;

  // Issues one query per QueryBox into the bound framebuffer (width x height, the ray caster's image),
  // projected as the ray caster's rays see them, `depth` as the ray caster mapped it. Changes the program,
  // vertex array, viewport, depth test and the storage buffers bound at kOcclusionBoxBinding and
  // kOcclusionCountBinding; leaves writes enabled. Skipped with kMaxBatchesInFlight batches pending.
  void issue(std::span<const QueryBox> boxes, const Camera& camera, uint32_t width, uint32_t height,
             DepthRange depth, uint64_t frame);

  // The answers available now, in the order they were issued; the rest stay pending. Never waits.
  std::vector<QueryAnswer> collect();
  // Forgets the pending queries (their answers would describe another isovalue or transfer function).
  void dropPending();
  // Queries issued whose answers collect() has not returned.
  size_t pendingCount() const;
  // issue() calls skipped because kMaxBatchesInFlight batches were pending.
  uint64_t skippedIssues() const { return skippedIssues_; }

  // Tests: ask `probe` whether a frame's counts have arrived instead of GL.
  void setFenceProbe(std::unique_ptr<FenceProbe> probe) { probe_ = std::move(probe); }

 private:
  // One issue()'s queries: their nodes, and the readback buffer their counts are copied into.
  struct Batch {
    uint32_t buffer = 0;
    const uint32_t* mapped = nullptr;  // capacity words, persistently mapped
    uint32_t capacity = 0;
    GlSync fence = nullptr;
    uint64_t issuedFrame = 0;
    std::vector<NodeKey> keys;  // query i counts into word i
  };
  Batch takeBatch(uint32_t queries);
  static void release(Batch& batch);

  std::unique_ptr<ShaderProgram> program_;
  std::unique_ptr<FenceProbe> probe_;
  uint32_t vertexArray_ = 0;
  uint32_t boxBuffer_ = 0, boxCapacity_ = 0;      // records
  uint32_t countBuffer_ = 0, countCapacity_ = 0;  // words
  std::vector<OcclusionBoxRecord> records_;       // this frame's, kept for their allocation
  std::deque<Batch> pending_;                     // in flight, oldest first
  std::vector<Batch> free_;                       // readback buffers to reuse
  uint64_t skippedIssues_ = 0;
};

}  // namespace ropecast
