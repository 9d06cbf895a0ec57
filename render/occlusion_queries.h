// OcclusionQueries: the GL side of the visibility feedback (Gobbetti et al. 2008, Sect. 6). issue() draws
// each node's boxes (up to 8, one instanced draw) under its own GL_SAMPLES_PASSED query, against the depth
// buffer where the ray caster left the depth at which each ray stopped (front faces only, so a pixel counts
// once; no color or depth writes; depth clamped so a box reaching the near plane is not clipped away).
// collect() takes, in a later frame, the answers the driver says are available (GL_QUERY_RESULT_AVAILABLE)
// and leaves the others pending: it never waits. Planning which nodes to query is occlusion/'s
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
#include "render/raycast_uniforms.h"
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

// How collect() reads a query: from GL in the renderer; tests substitute one that holds results back.
class QueryResultReader {
 public:
  virtual ~QueryResultReader() = default;
  virtual bool available(uint32_t query) = 0;   // must not wait
  virtual uint64_t result(uint32_t query) = 0;  // called only when available() said so
};

class OcclusionQueries {
 public:
  OcclusionQueries();
  ~OcclusionQueries();
  OcclusionQueries(const OcclusionQueries&) = delete;
  OcclusionQueries& operator=(const OcclusionQueries&) = delete;

  // Issues one query per QueryBox into the bound framebuffer (width x height, the ray caster's image),
  // projected as the ray caster's rays see them, `depth` as the ray caster mapped it. Changes the program,
  // vertex array, viewport and depth test; leaves writes enabled.
  void issue(std::span<const QueryBox> boxes, const Camera& camera, uint32_t width, uint32_t height,
             DepthRange depth, uint64_t frame);

  // The answers available now, in the order they were issued; the rest stay pending. Never waits.
  std::vector<QueryAnswer> collect();
  // Forgets the pending queries (their answers would describe another isovalue or transfer function).
  void dropPending();
  size_t pendingCount() const { return pending_.size(); }

  // Tests: read results through `reader` instead of GL.
  void setReader(std::unique_ptr<QueryResultReader> reader);

 private:
  struct Pending {
    uint32_t query = 0;
    NodeKey key;
    uint64_t issuedFrame = 0;
  };
  uint32_t takeQuery();

  std::unique_ptr<ShaderProgram> program_;
  std::unique_ptr<QueryResultReader> reader_;
  uint32_t vertexArray_ = 0;
  std::deque<Pending> pending_;
  std::vector<uint32_t> freeQueries_;
  std::vector<uint32_t> allQueries_;
};

}  // namespace ropecast
