#include "render/raycast_pass.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <epoxy/gl.h>
#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/transfer_function.h"
#include "render/brick_pool.h"
#include "render/gl_context.h"
#include "render/gradient_pool.h"
#include "render/index_texture.h"
#include "render/raycast_uniforms.h"
#include "render/shader_program.h"
#include "store/octree_layout.h"

namespace ropecast {

namespace {

// Texture and image units of the pass.
constexpr GLuint kPoolUnit = 0;
constexpr GLuint kTfUnit = 1;
constexpr GLuint kRopeIndexUnit = 2;
constexpr GLuint kGradientUnit = 3;
constexpr GLuint kColorImageUnit = 0;  // match the binding = N of shaders/raycast.comp
constexpr GLuint kDepthImageUnit = 1;
constexpr uint32_t kWorkgroupSize = 8;

}  // namespace

VolumeGeometry VolumeGeometry::of(const BrickSourceInfo& info) {
  VolumeGeometry g;
  g.dims = info.layout.dims;
  g.spacing = info.volume.spacing;
  g.brickSize = info.layout.brickSize;
  g.maxDepth = info.layout.maxDepth;
  g.storedType = info.storedType;
  g.mapping = info.mapping;
  return g;
}

RaycastPass::RaycastPass() {
  glCreateVertexArrays(1, &emptyVertexArray_);
  glCreateFramebuffers(1, &framebuffer_);
  tfTexture_ = createTfTexture();
}

RaycastPass::~RaycastPass() {
  GLuint textures[] = {colorTexture_, worldDepthTexture_, depthBuffer_, tfTexture_};
  glDeleteTextures(4, textures);
  glDeleteFramebuffers(1, &framebuffer_);
  glDeleteVertexArrays(1, &emptyVertexArray_);
}

const ShaderProgram& RaycastPass::program(const RenderParams& params) {
  const RenderBackend backend = params.backend;
  const RenderMode mode = params.mode;
  std::unique_ptr<ShaderProgram>& p = programs_[{backend, mode, usesStoredGradients(params)}];
  if (!p) {
    const std::vector<std::string> defines = raycastDefines(params);
    if (backend == RenderBackend::Compute)
      p = std::make_unique<ShaderProgram>(
          std::vector<ShaderFile>{{ShaderStage::Compute, "shaders/raycast.comp"}}, defines);
    else
      p = std::make_unique<ShaderProgram>(
          std::vector<ShaderFile>{{ShaderStage::Vertex, "shaders/raycast.vert"},
                                  {ShaderStage::Fragment, "shaders/raycast.frag"}},
          defines);
  }
  return *p;
}

void RaycastPass::resizeTargets(uint32_t width, uint32_t height) {
  if (width == width_ && height == height_) return;
  GLuint old[] = {colorTexture_, worldDepthTexture_, depthBuffer_};
  glDeleteTextures(3, old);
  glCreateTextures(GL_TEXTURE_2D, 1, &colorTexture_);
  glTextureStorage2D(colorTexture_, 1, GL_RGBA32F, GLsizei(width), GLsizei(height));
  glCreateTextures(GL_TEXTURE_2D, 1, &worldDepthTexture_);
  glTextureStorage2D(worldDepthTexture_, 1, GL_R32F, GLsizei(width), GLsizei(height));
  glCreateTextures(GL_TEXTURE_2D, 1, &depthBuffer_);
  glTextureStorage2D(depthBuffer_, 1, GL_DEPTH_COMPONENT32F, GLsizei(width), GLsizei(height));
  for (GLuint t : {colorTexture_, worldDepthTexture_}) {
    glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  }
  glNamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT0, colorTexture_, 0);
  glNamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT1, worldDepthTexture_, 0);
  glNamedFramebufferTexture(framebuffer_, GL_DEPTH_ATTACHMENT, depthBuffer_, 0);
  const GLenum drawBuffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(framebuffer_, 2, drawBuffers);
  const GLenum status = glCheckNamedFramebufferStatus(framebuffer_, GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    throw Error("RaycastPass: render targets incomplete (status 0x" + std::to_string(status) + ")");
  width_ = width;
  height_ = height;
}

void RaycastPass::setUniforms(const ShaderProgram& p, const RaycastFrame& f) {
  const GLuint id = p.id();
  const VolumeGeometry& vol = f.volume;
  const auto u = [&](const char* name) { return p.uniform(name); };

  // Camera, spacing and RenderParams (shared with BruteForcePass).
  setSharedRaycastUniforms(p, f.camera, f.width, f.height, vol.dims, vol.spacing, vol.mapping,
                           vol.storedMax(), f.params);
  const glm::dvec3 volumeMax = glm::dvec3(vol.dims) * vol.spacing;

  // Volume: the root cube and the level grid.
  const double cubeSamples = double(uint64_t(vol.brickSize) << vol.maxDepth);
  setVec3Uniform(id, u("uCubeWorld"), cubeSamples * vol.spacing);
  glProgramUniform1f(id, u("uBrickSize"), float(vol.brickSize));
  glProgramUniform1ui(id, u("uMaxDepth"), vol.maxDepth);

  // Pool, index and transfer function.
  const BrickPoolGeometry& pool = f.pool->geometry();
  glProgramUniform3ui(id, u("uPoolSlotGrid"), pool.slotGrid.x, pool.slotGrid.y, pool.slotGrid.z);
  glProgramUniform1f(id, u("uPoolSlotEdge"), float(pool.slotEdge));
  setVec3Uniform(id, u("uPoolTexelSize"), 1.0 / glm::dvec3(pool.textureDims));
  glProgramUniform1i(id, u("uPool"), GLint(kPoolUnit));
  glProgramUniform1i(id, u("uGradientPool"), GLint(kGradientUnit));
  glProgramUniform1i(id, u("uTransferFunction"), GLint(kTfUnit));
  glProgramUniform1f(id, u("uTfEntries"), float(TfTable::kDefaultEntries));
  glProgramUniform1i(id, u("uRopeIndex"), GLint(kRopeIndexUnit));

  // Window depth for gl_FragDepth: a perspective range enclosing the volume.
  const double extent = glm::length(volumeMax);
  const double farDist = glm::length(f.camera.eye - 0.5 * volumeMax) + extent;
  glProgramUniform1f(id, u("uDepthNear"), float(std::max(1e-4 * extent, 1e-9)));
  glProgramUniform1f(id, u("uDepthFar"), float(std::max(farDist, 2e-4 * extent)));
}

void RaycastPass::render(const RaycastFrame& f) {
  if (!f.pool) throw Error("RaycastPass::render: no brick pool");
  if (!f.index) throw Error("RaycastPass::render: no index texture");
  if (f.index->componentsPerTexel() != 4)
    throw Error("RaycastPass::render: the rope index needs 4-component texels (index/rope_layout.h)");
  if (f.width == 0 || f.height == 0) throw Error("RaycastPass::render: image size must be positive");
  if (f.pool->geometry().slotEdge != f.volume.brickSize + 2 * kBrickBorder)
    throw Error("RaycastPass::render: the pool's slots are for another brick size than the volume's " +
                std::to_string(f.volume.brickSize));
  if (f.pool->storedType() != f.volume.storedType)
    throw Error("RaycastPass::render: the pool's sample type differs from the volume's");
  checkRaycastInputs(f.params, f.tf, "RaycastPass::render");

  if (usesStoredGradients(f.params)) {
    if (!f.gradients)
      throw Error("RaycastPass::render: DVR with stored gradients needs the pool's GradientPool");
    if (f.gradients->dims() != f.pool->geometry().textureDims)
      throw Error("RaycastPass::render: the GradientPool's dimensions differ from the brick pool's");
  }

  const ShaderProgram& p = program(f.params);
  resizeTargets(f.width, f.height);
  if (f.tf) uploadTf(tfTexture_, *f.tf);
  setUniforms(p, f);
  glBindTextureUnit(kPoolUnit, f.pool->texture());
  glBindTextureUnit(kTfUnit, tfTexture_);
  f.index->bind(kRopeIndexUnit);
  if (usesStoredGradients(f.params)) glBindTextureUnit(kGradientUnit, f.gradients->texture());
  p.use();

  timer_.begin();
  if (f.params.backend == RenderBackend::Compute) {
    glBindImageTexture(kColorImageUnit, colorTexture_, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(kDepthImageUnit, worldDepthTexture_, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    glProgramUniform2ui(p.id(), p.uniform("uTileOrigin"), 0, 0);
    glDispatchCompute((f.width + kWorkgroupSize - 1) / kWorkgroupSize,
                      (f.height + kWorkgroupSize - 1) / kWorkgroupSize, 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT |
                    GL_FRAMEBUFFER_BARRIER_BIT);
  } else {
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
    glViewport(0, 0, GLsizei(f.width), GLsizei(f.height));
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    glDepthMask(GL_TRUE);
    const float clearDepth = 1.0f;
    glClearNamedFramebufferfv(framebuffer_, GL_DEPTH, 0, &clearDepth);
    glBindVertexArray(emptyVertexArray_);
    glProgramUniform2ui(p.id(), p.uniform("uTargetSize"), f.width, f.height);
    // Each tile is one triangle around it, cut to the tile by the scissor: a quad's two triangles would
    // shade the pixel blocks along their diagonal twice on a software rasterizer (each with part of a mask).
    const GLint tileRect = p.uniform("uTileRect");
    glEnable(GL_SCISSOR_TEST);
    for (uint32_t y = 0; y < f.height; y += kTileSize)
      for (uint32_t x = 0; x < f.width; x += kTileSize) {
        const uint32_t w = std::min(kTileSize, f.width - x), h = std::min(kTileSize, f.height - y);
        glProgramUniform4ui(p.id(), tileRect, x, y, w, h);
        glScissor(GLint(x), GLint(y), GLsizei(w), GLsizei(h));
        glDrawArrays(GL_TRIANGLES, 0, 3);
      }
    glDisable(GL_SCISSOR_TEST);
    glBindVertexArray(0);
    glDisable(GL_DEPTH_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }
  timer_.end();
  checkGlError("RaycastPass::render");
}

FloatImage RaycastPass::readColor() const {
  return readFloatTexture(colorTexture_, width_, height_, 4, "RaycastPass::readColor");
}

FloatImage RaycastPass::readDepth() const {
  return readFloatTexture(worldDepthTexture_, width_, height_, 1, "RaycastPass::readDepth");
}

}  // namespace ropecast
