#include "render/occlusion_queries.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>

#include <epoxy/gl.h>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>
#include <glm/trigonometric.hpp>

#include "core/error.h"
#include "render/gl_context.h"
#include "render/shader_program.h"

namespace ropecast {

namespace {

constexpr GLint kViewProjectionLocation = 0;  // shaders/occlusion_box.vert
constexpr GLsizei kVerticesPerBox = 36;       // shaders/occlusion_box.vert: 12 triangles
constexpr uint32_t kMaxBoxesPerQuery = std::tuple_size_v<decltype(NodeDataParts::boxes)>;

// A buffer of at least `wanted` elements, grown by half again so that a slowly growing frame reallocates
// rarely; its contents are not kept.
void ensureCapacity(uint32_t& buffer, uint32_t& capacity, uint32_t wanted, size_t elementBytes) {
  if (wanted <= capacity) return;
  capacity = std::max(wanted, capacity + capacity / 2);
  glDeleteBuffers(1, &buffer);
  glCreateBuffers(1, &buffer);
  glNamedBufferStorage(buffer, GLsizeiptr(capacity * elementBytes), nullptr, GL_DYNAMIC_STORAGE_BIT);
}

// World -> clip space as the ray caster's rays see it (core/camera.h pixelRay): view axes from cameraFrame,
// image row 0 at framebuffer row 0 (so y is flipped), depth as shaders/window_depth.glsl.
glm::mat4 viewProjection(const Camera& camera, uint32_t width, uint32_t height, DepthRange depth) {
  const CameraFrame f = cameraFrame(camera);
  glm::dmat4 view(1.0);
  for (int c = 0; c < 3; ++c) {
    view[c][0] = f.right[c];
    view[c][1] = f.up[c];
    view[c][2] = -f.forward[c];
  }
  view[3][0] = -glm::dot(f.right, camera.eye);
  view[3][1] = -glm::dot(f.up, camera.eye);
  view[3][2] = glm::dot(f.forward, camera.eye);
  const double tanHalf = std::tan(glm::radians(camera.fovYDeg) * 0.5);
  const double aspect = double(width) / double(height);
  const double n = depth.nearDepth, fa = depth.farDepth;
  glm::dmat4 projection(0.0);
  projection[0][0] = 1.0 / (tanHalf * aspect);
  projection[1][1] = -1.0 / tanHalf;
  projection[2][2] = -(fa + n) / (fa - n);
  projection[2][3] = -1.0;
  projection[3][2] = -2.0 * fa * n / (fa - n);
  return glm::mat4(projection * view);
}

}  // namespace

OcclusionQueries::OcclusionQueries(std::unique_ptr<FenceProbe> probe)
    : program_(std::make_unique<ShaderProgram>(
          std::vector<ShaderFile>{{ShaderStage::Vertex, "shaders/occlusion_box.vert"},
                                  {ShaderStage::Fragment, "shaders/occlusion_box.frag"}})),
      probe_(probe ? std::move(probe) : makeGlFenceProbe()) {
  glCreateVertexArrays(1, &vertexArray_);
}

OcclusionQueries::~OcclusionQueries() {
  for (Batch& b : pending_) release(b);
  for (Batch& b : free_) release(b);
  glDeleteBuffers(1, &boxBuffer_);
  glDeleteBuffers(1, &countBuffer_);
  glDeleteVertexArrays(1, &vertexArray_);
}

void OcclusionQueries::release(Batch& batch) {
  if (batch.fence) glDeleteSync(batch.fence);
  if (batch.mapped) glUnmapNamedBuffer(batch.buffer);
  glDeleteBuffers(1, &batch.buffer);
  batch = {};
}

OcclusionQueries::Batch OcclusionQueries::takeBatch(uint32_t queries) {
  // A free readback buffer large enough, else a new one (the ring grows with the frames in flight, up to
  // kMaxBatchesInFlight).
  for (auto it = free_.begin(); it != free_.end(); ++it) {
    if (it->capacity < queries) continue;
    Batch b = std::move(*it);
    free_.erase(it);
    return b;
  }
  if (!free_.empty()) {  // all too small: replace one rather than keep more buffers than frames in flight
    release(free_.back());
    free_.pop_back();
  }
  Batch b;
  b.capacity = queries;
  const GLbitfield flags = GL_MAP_READ_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
  glCreateBuffers(1, &b.buffer);
  glNamedBufferStorage(b.buffer, GLsizeiptr(b.capacity) * 4, nullptr, flags);
  b.mapped =
      static_cast<const uint32_t*>(glMapNamedBufferRange(b.buffer, 0, GLsizeiptr(b.capacity) * 4, flags));
  if (!b.mapped) throw Error("OcclusionQueries: could not map a readback buffer persistently");
  return b;
}

void OcclusionQueries::issue(std::span<const QueryBox> boxes, const Camera& camera, uint32_t width,
                             uint32_t height, DepthRange depth, uint64_t frame) {
  if (boxes.empty()) return;
  if (pending_.size() >= kMaxBatchesInFlight) {
    ++skippedIssues_;
    return;
  }
  records_.clear();
  for (uint32_t q = 0; q < boxes.size(); ++q) {
    const NodeDataParts& parts = boxes[q].parts;
    if (parts.count == 0 || parts.count > kMaxBoxesPerQuery)
      throw Error("OcclusionQueries::issue: a query of " + std::to_string(parts.count) + " boxes (1 to 8)");
    for (uint32_t i = 0; i < parts.count; ++i) {
      const WorldBox& b = parts.boxes[i];
      records_.push_back({{float(b.lo.x), float(b.lo.y), float(b.lo.z)},
                          q,
                          {float(b.hi.x), float(b.hi.y), float(b.hi.z)},
                          0});
    }
  }
  const uint32_t queryCount = uint32_t(boxes.size());
  ensureCapacity(boxBuffer_, boxCapacity_, uint32_t(records_.size()), sizeof(OcclusionBoxRecord));
  glNamedBufferSubData(boxBuffer_, 0, GLsizeiptr(records_.size() * sizeof(OcclusionBoxRecord)),
                       records_.data());
  ensureCapacity(countBuffer_, countCapacity_, queryCount, sizeof(uint32_t));
  const GLuint zero = 0;
  glClearNamedBufferSubData(countBuffer_, GL_R32UI, 0, GLsizeiptr(queryCount) * 4, GL_RED_INTEGER,
                            GL_UNSIGNED_INT, &zero);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kOcclusionBoxBinding, boxBuffer_);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kOcclusionCountBinding, countBuffer_);

  program_->use();
  glProgramUniformMatrix4fv(program_->id(), kViewProjectionLocation, 1, GL_FALSE,
                            glm::value_ptr(viewProjection(camera, width, height, depth)));
  glBindVertexArray(vertexArray_);
  glViewport(0, 0, GLsizei(width), GLsizei(height));
  glDisable(GL_SCISSOR_TEST);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_FALSE);
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  glEnable(GL_DEPTH_CLAMP);
  glEnable(GL_CULL_FACE);
  glCullFace(GL_BACK);
  glFrontFace(GL_CW);  // the y flip mirrors the counter-clockwise faces of shaders/occlusion_box.vert
  glDrawArraysInstanced(GL_TRIANGLES, 0, kVerticesPerBox, GLsizei(records_.size()));
  glFrontFace(GL_CCW);
  glDisable(GL_CULL_FACE);
  glDisable(GL_DEPTH_CLAMP);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthMask(GL_TRUE);
  glBindVertexArray(0);

  Batch batch = takeBatch(queryCount);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);  // the copy reads what the fragments added
  glCopyNamedBufferSubData(countBuffer_, batch.buffer, 0, 0, GLsizeiptr(queryCount) * 4);
  batch.fence = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
  glFlush();  // so that the fence is submitted and can signal without a later wait flushing it
  batch.issuedFrame = frame;
  batch.keys.clear();
  for (const QueryBox& box : boxes) batch.keys.push_back(box.key);
  pending_.push_back(std::move(batch));
  checkGlError("OcclusionQueries::issue");
}

std::vector<QueryAnswer> OcclusionQueries::collect() {
  std::vector<QueryAnswer> answers;
  // Fences signal in the order they were set: the first one pending holds back the rest.
  while (!pending_.empty() && probe_->signaled(pending_.front().fence)) {
    Batch b = std::move(pending_.front());
    pending_.pop_front();
    glDeleteSync(b.fence);
    b.fence = nullptr;
    for (size_t i = 0; i < b.keys.size(); ++i) answers.push_back({b.keys[i], b.issuedFrame, b.mapped[i]});
    free_.push_back(std::move(b));
  }
  return answers;
}

void OcclusionQueries::dropPending() {
  // A readback buffer still being copied into may be reused: the next copy into it comes later in GL's order.
  for (Batch& b : pending_) {
    glDeleteSync(b.fence);
    b.fence = nullptr;
    free_.push_back(std::move(b));
  }
  pending_.clear();
}

size_t OcclusionQueries::pendingCount() const {
  size_t n = 0;
  for (const Batch& b : pending_) n += b.keys.size();
  return n;
}

}  // namespace ropecast
