#include "render/raycast_pass.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <epoxy/gl.h>
#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/transfer_function.h"
#include "render/backend_choice.h"
#include "render/brick_pool.h"
#include "render/gl_context.h"
#include "render/gradient_pool.h"
#include "render/index_texture.h"
#include "render/raycast_uniforms.h"
#include "render/shader_program.h"
#include "store/octree_layout.h"

namespace ropecast {

namespace {

// Image units and uniform locations of the entry points (the textures' units: shaders/raycast_block.h).
constexpr GLuint kColorImageUnit = 0;  // match the binding = N of shaders/raycast.comp
constexpr GLuint kDepthImageUnit = 1;
constexpr GLint kTileOriginLocation = 0;  // shaders/raycast.comp uTileOrigin
constexpr GLint kTileRectLocation = 0;    // shaders/raycast.vert uTileRect
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
  const GLubyte* renderer = glGetString(GL_RENDERER);
  dvrLeafBatch_ = renderer && isSoftwareRenderer(reinterpret_cast<const char*>(renderer));
  glCreateVertexArrays(1, &emptyVertexArray_);
  tfTexture_ = createTfTexture();
}

RaycastPass::~RaycastPass() {
  glDeleteTextures(1, &tfTexture_);
  glDeleteVertexArrays(1, &emptyVertexArray_);
}

const ShaderProgram& RaycastPass::program(const RenderParams& params) {
  const RenderBackend backend = params.backend;
  const RenderMode mode = params.mode;
  const bool leafBatch = dvrLeafBatch_ && mode == RenderMode::Dvr;
  std::unique_ptr<ShaderProgram>& p = programs_[{backend, mode, usesStoredGradients(params), leafBatch}];
  if (!p) {
    std::vector<std::string> defines = raycastDefines(params);
    if (leafBatch) defines.push_back("LLVMPIPE_DVR_LEAF_BATCH");
    if (backend == RenderBackend::Compute)
      p = std::make_unique<ShaderProgram>(
          std::vector<ShaderFile>{{ShaderStage::Compute, "shaders/raycast.comp"}}, defines);
    else
      p = std::make_unique<ShaderProgram>(
          std::vector<ShaderFile>{{ShaderStage::Vertex, "shaders/raycast.vert"},
                                  {ShaderStage::Fragment, "shaders/raycast.frag"}},
          defines);
    // shaders/rope_traversal.glsl declares its sampler without a binding, for any entry point to choose.
    glProgramUniform1i(p->id(), p->uniform("uRopeIndex"), kRaycastRopeIndexUnit);
  }
  return *p;
}

RaycastBlock RaycastPass::block(const RaycastFrame& f) const {
  const VolumeGeometry& vol = f.volume;
  RaycastBlock b = raycastBlock(f.camera, f.width, f.height, vol.dims, vol.spacing, vol.mapping,
                                vol.storedMax(), f.params);

  // The root cube, the level grid and the pool.
  const double cubeSamples = double(uint64_t(vol.brickSize) << vol.maxDepth);
  b.cubeWorld = glm::vec3(cubeSamples * vol.spacing);
  b.brickSize = float(vol.brickSize);
  b.maxDepth = vol.maxDepth;
  const BrickPoolGeometry& pool = f.pool->geometry();
  b.valueTexelSize = glm::vec3(1.0 / glm::dvec3(pool.textureDims));
  b.poolSlotGrid = pool.slotGrid;
  b.poolSlotEdge = float(pool.slotEdge);

  // Window depth for gl_FragDepth: a perspective range enclosing the volume.
  const glm::dvec3 volumeMax = glm::dvec3(vol.dims) * vol.spacing;
  const double extent = glm::length(volumeMax);
  const double farDist = glm::length(f.camera.eye - 0.5 * volumeMax) + extent;
  b.depthNear = float(std::max(1e-4 * extent, 1e-9));
  b.depthFar = float(std::max(farDist, 2e-4 * extent));
  return b;
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
  target_.resize(f.width, f.height);
  if (f.tf) uploadTf(tfTexture_, *f.tf);
  blockBuffer_.upload(block(f));
  glBindTextureUnit(kRaycastValueUnit, f.pool->texture());
  glBindTextureUnit(kRaycastTfUnit, tfTexture_);
  f.index->bind(kRaycastRopeIndexUnit);
  if (usesStoredGradients(f.params)) glBindTextureUnit(kRaycastSampleUnit, f.gradients->texture());
  p.use();

  timer_.begin();
  if (f.params.backend == RenderBackend::Compute) {
    glBindImageTexture(kColorImageUnit, target_.colorTexture(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(kDepthImageUnit, target_.depthTexture(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    glProgramUniform2ui(p.id(), kTileOriginLocation, 0, 0);
    glDispatchCompute((f.width + kWorkgroupSize - 1) / kWorkgroupSize,
                      (f.height + kWorkgroupSize - 1) / kWorkgroupSize, 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT |
                    GL_FRAMEBUFFER_BARRIER_BIT);
  } else {
    target_.bindForDrawing();
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    glDepthMask(GL_TRUE);
    const float clearDepth = 1.0f;
    glClearNamedFramebufferfv(target_.framebuffer(), GL_DEPTH, 0, &clearDepth);
    glBindVertexArray(emptyVertexArray_);
    // Each tile is one triangle around it, cut to the tile by the scissor: a quad's two triangles would
    // shade the pixel blocks along their diagonal twice on a software rasterizer (each with part of a mask).
    glEnable(GL_SCISSOR_TEST);
    for (uint32_t y = 0; y < f.height; y += kTileSize)
      for (uint32_t x = 0; x < f.width; x += kTileSize) {
        const uint32_t w = std::min(kTileSize, f.width - x), h = std::min(kTileSize, f.height - y);
        glProgramUniform4ui(p.id(), kTileRectLocation, x, y, w, h);
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

}  // namespace ropecast
