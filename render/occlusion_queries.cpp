#include "render/occlusion_queries.h"

#include <cmath>
#include <string>

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
constexpr GLint kBoxLoLocation = 1;           // uBoxLo[8]: locations 1 to 8
constexpr GLint kBoxHiLocation = 9;           // uBoxHi[8]: locations 9 to 16
constexpr GLsizei kBoxVertices = 36;

class GlQueryResultReader final : public QueryResultReader {
 public:
  bool available(uint32_t query) override {
    GLuint ready = GL_FALSE;
    glGetQueryObjectuiv(query, GL_QUERY_RESULT_AVAILABLE, &ready);
    return ready == GL_TRUE;
  }
  uint64_t result(uint32_t query) override {
    GLuint64 samples = 0;
    glGetQueryObjectui64v(query, GL_QUERY_RESULT, &samples);
    return samples;
  }
};

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

OcclusionQueries::OcclusionQueries()
    : program_(std::make_unique<ShaderProgram>(
          std::vector<ShaderFile>{{ShaderStage::Vertex, "shaders/occlusion_box.vert"},
                                  {ShaderStage::Fragment, "shaders/occlusion_box.frag"}})),
      reader_(std::make_unique<GlQueryResultReader>()) {
  glCreateVertexArrays(1, &vertexArray_);
}

OcclusionQueries::~OcclusionQueries() {
  if (!allQueries_.empty()) glDeleteQueries(GLsizei(allQueries_.size()), allQueries_.data());
  glDeleteVertexArrays(1, &vertexArray_);
}

void OcclusionQueries::setReader(std::unique_ptr<QueryResultReader> reader) {
  reader_ = std::move(reader);
}

uint32_t OcclusionQueries::takeQuery() {
  if (freeQueries_.empty()) {
    GLuint q = 0;
    glCreateQueries(GL_SAMPLES_PASSED, 1, &q);
    allQueries_.push_back(q);
    return q;
  }
  const uint32_t q = freeQueries_.back();
  freeQueries_.pop_back();
  return q;
}

void OcclusionQueries::issue(std::span<const QueryBox> boxes, const Camera& camera, uint32_t width,
                             uint32_t height, DepthRange depth, uint64_t frame) {
  if (boxes.empty()) return;
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
  std::array<glm::vec3, 8> lo, hi;  // shaders/occlusion_box.vert's uBoxLo, uBoxHi
  for (const QueryBox& box : boxes) {
    const uint32_t count = box.parts.count;
    if (count == 0 || count > lo.size())
      throw Error("OcclusionQueries::issue: a query of " + std::to_string(count) + " boxes (1 to 8)");
    for (uint32_t i = 0; i < count; ++i) {
      lo[i] = glm::vec3(box.parts.boxes[i].lo);
      hi[i] = glm::vec3(box.parts.boxes[i].hi);
    }
    glProgramUniform3fv(program_->id(), kBoxLoLocation, GLsizei(count), glm::value_ptr(lo[0]));
    glProgramUniform3fv(program_->id(), kBoxHiLocation, GLsizei(count), glm::value_ptr(hi[0]));
    const uint32_t query = takeQuery();
    glBeginQuery(GL_SAMPLES_PASSED, query);
    glDrawArraysInstanced(GL_TRIANGLES, 0, kBoxVertices, GLsizei(count));
    glEndQuery(GL_SAMPLES_PASSED);
    pending_.push_back({query, box.key, frame});
  }
  glFrontFace(GL_CCW);
  glDisable(GL_CULL_FACE);
  glDisable(GL_DEPTH_CLAMP);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthMask(GL_TRUE);
  glBindVertexArray(0);
  checkGlError("OcclusionQueries::issue");
}

std::vector<QueryAnswer> OcclusionQueries::collect() {
  std::vector<QueryAnswer> answers;
  for (auto it = pending_.begin(); it != pending_.end();) {
    if (!reader_->available(it->query)) {
      ++it;
      continue;
    }
    answers.push_back({it->key, it->issuedFrame, reader_->result(it->query)});
    freeQueries_.push_back(it->query);
    it = pending_.erase(it);
  }
  return answers;
}

void OcclusionQueries::dropPending() {
  // A query still in flight may be reused: glBeginQuery on it replaces the old result.
  for (const Pending& p : pending_) freeQueries_.push_back(p.query);
  pending_.clear();
}

}  // namespace ropecast
