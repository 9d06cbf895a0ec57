#include "render/multipass_pass.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <epoxy/gl.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "core/error.h"
#include "core/transfer_function.h"
#include "loader/refiner.h"
#include "render/brick_pool.h"
#include "render/gl_context.h"
#include "render/gradient_pool.h"
#include "render/shader_program.h"

namespace ropecast {

namespace {

// Image units and uniform locations of shaders/multipass*.
constexpr GLuint kAccumImageUnit = 0;
constexpr GLuint kDepthImageUnit = 1;
constexpr GLuint kMarchImageUnit = 2;
constexpr GLuint kBeforeImageUnit = 3;
// shaders/multipass_block.frag packs a leaf's depth and brick slot into one word: depth | slot << 8.
static_assert(kMaxPoolSlots <= (uint64_t(1) << 24));
constexpr GLint kBoxMinLocation = 0;  // shaders/multipass.vert
constexpr GLint kBoxMaxLocation = 1;
constexpr GLint kNdcZLocation = 2;
constexpr GLint kLeafBoxMinLocation = 3;  // shaders/multipass_block.frag
constexpr GLint kLeafLocation = 4;
constexpr GLint kLeafMaxLocation = 5;
// The vertices of shaders/multipass.vert: a box's faces, then the full-screen triangle.
constexpr GLint kBoxVertices = 36;
constexpr GLint kFullScreenFirst = 36;

// Depth-test values (NDC z; window depth 0.5 + z/2) over a buffer cleared to 1: a block's fragments pass
// where no mark was written (0.5 < 1) and fail on one (0.5 >= 0.25); a mark's fragments write 0.25 once.
constexpr float kBlockNdcZ = 0.0f;
constexpr float kMarkNdcZ = -0.5f;

}  // namespace

void sortFrontToBack(std::vector<MultipassLeaf>& leaves, const OctreeLayout& layout, glm::dvec3 spacing,
                     glm::dvec3 eye) {
  const glm::dvec3 cube =
      double(uint64_t(layout.brickSize) << layout.maxDepth) * spacing;  // root cube, world
  // Two disjoint nodes are ordered by their ancestors one level below the deepest common one: the child on
  // the eye's side of the parent's center planes goes first, in the order of j = (child bits) xor (eye bits),
  // which no ray from the eye can contradict (a ray crosses each center plane at most once, away from the
  // eye).
  const auto before = [&](const MultipassLeaf& a, const MultipassLeaf& b) {
    const uint32_t depth = std::min(a.key.depth, b.key.depth);
    for (uint32_t d = 1; d <= depth; ++d) {
      const glm::u32vec3 ca = a.key.coord >> (a.key.depth - d);
      const glm::u32vec3 cb = b.key.coord >> (b.key.depth - d);
      if (ca == cb) continue;
      const glm::dvec3 center = (glm::dvec3(ca >> 1u) + 0.5) * cube / double(uint64_t(1) << (d - 1));
      uint32_t ja = 0, jb = 0;
      for (int axis = 0; axis < 3; ++axis) {
        const uint32_t eyeBit = eye[axis] >= center[axis] ? 1u : 0u;
        ja |= ((ca[axis] & 1u) ^ eyeBit) << axis;
        jb |= ((cb[axis] & 1u) ^ eyeBit) << axis;
      }
      return ja < jb;
    }
    return false;  // one holds the other: not two leaves of a cut
  };
  std::sort(leaves.begin(), leaves.end(), before);
}

MultipassPass::MultipassPass() {
  glCreateVertexArrays(1, &emptyVertexArray_);
  tfTexture_ = createTfTexture();
  glCreateQueries(GL_SAMPLES_PASSED, 1, &fragmentQuery_);
}

MultipassPass::~MultipassPass() {
  glDeleteQueries(1, &fragmentQuery_);
  glDeleteFramebuffers(1, &framebuffer_);
  glDeleteRenderbuffers(1, &depthBuffer_);
  glDeleteTextures(1, &marchTexture_);
  glDeleteTextures(1, &beforeTexture_);
  glDeleteTextures(1, &tfTexture_);
  glDeleteVertexArrays(1, &emptyVertexArray_);
}

const ShaderProgram& MultipassPass::program(const RenderParams& params, Stage stage) {
  std::unique_ptr<ShaderProgram>& p = programs_[{params.mode, dvrLightingOf(params), stage}];
  if (!p) {
    const char* fragment = stage == Stage::Block  ? "shaders/multipass_block.frag"
                           : stage == Stage::Mark ? "shaders/multipass_mark.frag"
                                                  : "shaders/multipass_resolve.frag";
    p = std::make_unique<ShaderProgram>(
        std::vector<ShaderFile>{{ShaderStage::Vertex, "shaders/multipass.vert"},
                                {ShaderStage::Fragment, fragment}},
        raycastDefines(params));
  }
  return *p;
}

void MultipassPass::resize(uint32_t width, uint32_t height) {
  target_.resize(width, height);
  if (width == width_ && height == height_) return;
  glDeleteFramebuffers(1, &framebuffer_);
  glDeleteRenderbuffers(1, &depthBuffer_);
  glDeleteTextures(1, &marchTexture_);
  glCreateTextures(GL_TEXTURE_2D, 1, &marchTexture_);
  glTextureStorage2D(marchTexture_, 1, GL_RGBA32F, GLsizei(width), GLsizei(height));
  glDeleteTextures(1, &beforeTexture_);
  glCreateTextures(GL_TEXTURE_2D, 1, &beforeTexture_);
  glTextureStorage2D(beforeTexture_, 1, GL_RGBA32UI, GLsizei(width), GLsizei(height));
  glCreateRenderbuffers(1, &depthBuffer_);
  glNamedRenderbufferStorage(depthBuffer_, GL_DEPTH_COMPONENT32F, GLsizei(width), GLsizei(height));
  glCreateFramebuffers(1, &framebuffer_);
  glNamedFramebufferRenderbuffer(framebuffer_, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depthBuffer_);
  glNamedFramebufferDrawBuffer(framebuffer_, GL_NONE);
  glNamedFramebufferReadBuffer(framebuffer_, GL_NONE);
  if (glCheckNamedFramebufferStatus(framebuffer_, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw Error("MultipassPass: the depth framebuffer is incomplete");
  width_ = width;
  height_ = height;
}

void MultipassPass::render(const RaycastFrame& f, std::vector<MultipassLeaf> leaves) {
  if (!f.pool) throw Error("MultipassPass::render: no brick pool");
  if (f.width == 0 || f.height == 0) throw Error("MultipassPass::render: image size must be positive");
  if (f.pool->geometry().slotEdge != f.volume.brickSize + 2 * kBrickBorder)
    throw Error("MultipassPass::render: the pool's slots are for another brick size than the volume's " +
                std::to_string(f.volume.brickSize));
  checkRaycastInputs(f.params, f.tf, "MultipassPass::render");
  if (usesStoredGradients(f.params) && !f.gradients)
    throw Error("MultipassPass::render: DVR with stored gradients needs the pool's GradientPool");

  const ShaderProgram& block = program(f.params, Stage::Block);
  const ShaderProgram& mark = program(f.params, Stage::Mark);
  const ShaderProgram& resolve = program(f.params, Stage::Resolve);
  resize(f.width, f.height);
  if (f.tf) uploadTf(tfTexture_, *f.tf);
  blockBuffer_.upload(raycastFrameBlock(f));

  // Front to back for the eye (CPU, before the timer: the single pass's order costs it nothing either).
  const OctreeLayout layout = OctreeLayout::forVolume(f.volume.dims, f.volume.brickSize);
  sortFrontToBack(leaves, layout, f.volume.spacing, f.camera.eye);
  const glm::dvec3 forward = glm::normalize(f.camera.target - f.camera.eye);
  const double tanHalfFov = std::tan(glm::radians(f.camera.fovYDeg) * 0.5);
  const WorldBox sampled = sampledWorldBox(f.params, f.volume.dims, f.volume.spacing);

  counts_ = {};
  timer_.begin();
  // Clear: nothing accumulated, no depth, no march, no ray ended.
  const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  const float infinity = std::numeric_limits<float>::infinity();
  glClearTexImage(target_.colorTexture(), 0, GL_RGBA, GL_FLOAT, zero);
  glClearTexImage(target_.depthTexture(), 0, GL_RED, GL_FLOAT, &infinity);
  glClearTexImage(marchTexture_, 0, GL_RGBA, GL_FLOAT, zero);
  const GLuint zeroBits[4] = {0, 0, 0, 0};
  glClearTexImage(beforeTexture_, 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT, zeroBits);
  const float clearDepth = 1.0f;
  glClearNamedFramebufferfv(framebuffer_, GL_DEPTH, 0, &clearDepth);

  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glViewport(0, 0, GLsizei(f.width), GLsizei(f.height));
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDisable(GL_SCISSOR_TEST);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glBindVertexArray(emptyVertexArray_);
  glBindTextureUnit(kRaycastValueUnit, f.pool->texture());
  glBindTextureUnit(kRaycastTfUnit, tfTexture_);
  if (usesStoredGradients(f.params)) glBindTextureUnit(kRaycastSampleUnit, f.gradients->texture());
  blockBuffer_.bind();
  glBindImageTexture(kAccumImageUnit, target_.colorTexture(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
  glBindImageTexture(kDepthImageUnit, target_.depthTexture(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32F);
  glBindImageTexture(kMarchImageUnit, marchTexture_, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
  glBindImageTexture(kBeforeImageUnit, beforeTexture_, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32UI);
  glProgramUniform1f(block.id(), kNdcZLocation, kBlockNdcZ);
  glProgramUniform1f(mark.id(), kNdcZLocation, kMarkNdcZ);

  glBeginQuery(GL_SAMPLES_PASSED, fragmentQuery_);
  for (const MultipassLeaf& leaf : leaves) {
    // Only the part of the leaf inside --crop holds samples (the fragments clip their rays to both).
    WorldBox box = intersection(nodeWorldBox(layout, f.volume.spacing, leaf.key), sampled);
    if (!hasVolume(box)) continue;
    double nearest = std::numeric_limits<double>::infinity(), farthest = 0.0;
    for (int corner = 0; corner < 8; ++corner) {
      const glm::dvec3 p((corner & 1) ? box.hi.x : box.lo.x, (corner & 2) ? box.hi.y : box.lo.y,
                         (corner & 4) ? box.hi.z : box.lo.z);
      const double depth = glm::dot(p - f.camera.eye, forward);
      nearest = std::min(nearest, depth);
      farthest = std::max(farthest, depth);
    }
    // The box is rasterized a twentieth of a pixel larger than it is: a pixel whose ray grazes the box's
    // silhouette is then always shaded, and the fragment's own clip of its ray (exact, as the rope
    // traversal's) decides which samples are the block's. Without it, the rasterizer's rounding at the
    // silhouette drops the odd sample that the single pass takes.
    const double grow = 0.05 * farthest * 2.0 * tanHalfFov / double(f.height);
    box.lo -= grow;
    box.hi += grow;
    nearest -= grow * std::sqrt(3.0);
    // A box with a corner at or behind the eye plane would be clipped at w = 0: it is drawn as the whole
    // viewport instead, and each fragment's own clip of its ray to the box decides.
    const double extent = glm::length(box.hi - box.lo);
    const bool fullScreen = !(nearest > 1e-3 * extent);
    const GLint first = fullScreen ? kFullScreenFirst : 0;
    const GLsizei count = fullScreen ? 3 : kBoxVertices;
    const glm::vec3 lo(box.lo), hi(box.hi);
    const glm::vec3 cubeMin = glm::vec3(leaf.key.coord) * std::ldexp(1.0f, -int(leaf.key.depth));  // exact

    for (const ShaderProgram* p : {&block, &mark}) {
      glProgramUniform3f(p->id(), kBoxMinLocation, lo.x, lo.y, lo.z);
      glProgramUniform3f(p->id(), kBoxMaxLocation, hi.x, hi.y, hi.z);
    }
    glProgramUniform3f(block.id(), kLeafBoxMinLocation, cubeMin.x, cubeMin.y, cubeMin.z);
    glProgramUniform2ui(block.id(), kLeafLocation, leaf.key.depth, leaf.slot);
    if (isIntensityProjection(f.params.mode)) glProgramUniform1f(block.id(), kLeafMaxLocation, leaf.maxValue);

    // Block: the leaf's samples into the images, where no ray has ended (early depth test, no depth write).
    block.use();
    glDepthMask(GL_FALSE);
    glDrawArrays(GL_TRIANGLES, first, count);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    // Mark: depth where the rays ended, so the next blocks skip those pixels.
    mark.use();
    glDepthMask(GL_TRUE);
    glDrawArrays(GL_TRIANGLES, first, count);
    ++counts_.blocks;
    counts_.fullScreen += fullScreen;
    counts_.glDrawCalls += 2;
  }

  glEndQuery(GL_SAMPLES_PASSED);

  // Resolve: the background under the accumulation.
  glDisable(GL_DEPTH_TEST);
  glDepthMask(GL_TRUE);
  resolve.use();
  glDrawArrays(GL_TRIANGLES, kFullScreenFirst, 3);
  ++counts_.glDrawCalls;
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
  glBindVertexArray(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  timer_.end();
  GLuint64 fragments = 0;
  glGetQueryObjectui64v(fragmentQuery_, GL_QUERY_RESULT, &fragments);  // after the frame's work, as the timer
  counts_.fragments = fragments;
  checkGlError("MultipassPass::render");
}

}  // namespace ropecast
