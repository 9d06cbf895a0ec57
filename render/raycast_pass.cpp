#include "render/raycast_pass.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <epoxy/gl.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "core/error.h"
#include "core/transfer_function.h"
#include "render/backend_choice.h"
#include "render/brick_pool.h"
#include "render/feedback_buffer.h"
#include "render/gl_context.h"
#include "render/gradient_pool.h"
#include "render/index_texture.h"
#include "render/raycast_uniforms.h"
#include "render/shader_program.h"
#include "store/octree_layout.h"

namespace ropecast {

namespace {

// A texture unit and a uniform location of the fragment entry point and the stop-depth copy (the other units
// and the compute entry point's locations: shaders/raycast_block.h).
constexpr GLuint kStopDepthTextureUnit = 0;  // shaders/stop_depth.frag uStopDepth
constexpr GLint kTileRectLocation = 0;       // shaders/raycast.vert uTileRect

// The pixels both rectangles hold (an empty rectangle when none).
PixelRect intersection(const PixelRect& a, const PixelRect& b) {
  const uint32_t x0 = std::max(a.x, b.x), y0 = std::max(a.y, b.y);
  const uint32_t x1 = std::min(a.x + a.width, b.x + b.width), y1 = std::min(a.y + a.height, b.y + b.height);
  if (x1 <= x0 || y1 <= y0) return {};
  return {x0, y0, x1 - x0, y1 - y0};
}

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
  leafMaxima_ = std::make_unique<IndexTexture>(1, 0);
}

RaycastPass::~RaycastPass() {
  glDeleteTextures(1, &stopDepthTexture_);
  glDeleteTextures(1, &tfTexture_);
  glDeleteVertexArrays(1, &emptyVertexArray_);
}

const ShaderProgram& RaycastPass::program(const RenderParams& params, bool feedback) {
  const RenderBackend backend = params.backend;
  const RenderMode mode = params.mode;
  const bool leafBatch = dvrLeafBatch_ && mode == RenderMode::Dvr;
  std::unique_ptr<ShaderProgram>& p = programs_[{backend, mode, dvrLightingOf(params), leafBatch, feedback}];
  if (!p) {
    std::vector<std::string> defines = raycastDefines(params);
    if (leafBatch) defines.push_back("LLVMPIPE_DVR_LEAF_BATCH");
    if (feedback) defines.push_back("RAYCAST_FEEDBACK");
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

RaycastBlock raycastFrameBlock(const RaycastFrame& f) {
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
  const DepthRange depth = windowDepthRange(f.camera, glm::dvec3(vol.dims) * vol.spacing);
  b.depthNear = float(depth.nearDepth);
  b.depthFar = float(depth.farDepth);

  // Feedback: 2^L R > d <=> pixels(L) > 1 / voxelsPerPixel (docs/RENDERING.md "Feedback").
  const double maxSpacing = std::max({vol.spacing.x, vol.spacing.y, vol.spacing.z});
  const double minSpacing = std::min({vol.spacing.x, vol.spacing.y, vol.spacing.z});
  const double tanHalfFov = std::tan(glm::radians(f.camera.fovYDeg) * 0.5);
  b.feedbackRequestDistance = float(f.voxelsPerPixel * maxSpacing * double(f.height) / (2.0 * tanHalfFov));
  b.feedbackMinDistance = float(0.5 * minSpacing);
  const bool maxima = isIntensityProjection(f.params.mode) && !f.leafMaxima.empty();
  b.leafMaximaCount = maxima ? uint32_t(f.leafMaxima.size()) : 0u;
  if (maxima) b.leafMaximaLargest = *std::max_element(f.leafMaxima.begin(), f.leafMaxima.end());
  return b;
}

void RaycastPass::render(const RaycastFrame& f, const TileSchedule& schedule) {
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
  if (f.feedback && !f.feedback->inFrame())
    throw Error("RaycastPass::render: the FeedbackBuffer has no frame begun (FeedbackBuffer::begin)");
  if (f.feedback && !(f.voxelsPerPixel > 0.0))
    throw Error("RaycastPass::render: voxelsPerPixel must be positive with feedback on");

  if (usesStoredGradients(f.params)) {
    if (!f.gradients)
      throw Error("RaycastPass::render: DVR with stored gradients needs the pool's GradientPool");
    if (f.gradients->dims() != f.pool->geometry().textureDims)
      throw Error("RaycastPass::render: the GradientPool's dimensions differ from the brick pool's");
  }

  if (schedule.castOnly) {
    if (target_.width() != f.width || target_.height() != f.height || lastBackend_ != f.params.backend)
      throw Error("RaycastPass::render: casting part of a " + std::to_string(f.width) + "x" +
                  std::to_string(f.height) +
                  " image whose other pixels were not drawn at that size by the same entry point");
    for (const PixelRect& r : *schedule.castOnly)
      if (r.x + r.width > f.width || r.y + r.height > f.height)
        throw Error("RaycastPass::render: a rectangle to cast reaches outside the image");
  }

  target_.resize(f.width, f.height);
  if (f.params.backend == RenderBackend::Compute &&
      (stopDepthWidth_ != f.width || stopDepthHeight_ != f.height)) {
    glDeleteTextures(1, &stopDepthTexture_);
    glCreateTextures(GL_TEXTURE_2D, 1, &stopDepthTexture_);
    glTextureStorage2D(stopDepthTexture_, 1, GL_R32F, GLsizei(f.width), GLsizei(f.height));
    stopDepthWidth_ = f.width;
    stopDepthHeight_ = f.height;
  }

  afterFirstTileTimed_ = false;
  lastDrawCalls_ = 0;
  lastPixelsCast_ = 0;
  if (schedule.nothingToSample) {  // the targets alone: no program, transfer function or uniforms
    timer_.begin();
    writeMisses(f, schedule);
    timer_.end();
    lastBackend_ = f.params.backend;
    checkGlError("RaycastPass::render");
    return;
  }
  const ShaderProgram& p = program(f.params, f.feedback != nullptr);
  if (f.tf) uploadTf(tfTexture_, *f.tf);
  if (isIntensityProjection(f.params.mode)) {
    leafMaximaWords_.resize(f.leafMaxima.size());
    std::transform(f.leafMaxima.begin(), f.leafMaxima.end(), leafMaximaWords_.begin(),
                   [](float v) { return std::bit_cast<uint32_t>(v); });
    leafMaxima_->upload(leafMaximaWords_);
  }
  blockBuffer_.upload(raycastFrameBlock(f));
  timer_.begin();
  if (f.params.backend == RenderBackend::Fragment && !schedule.castOnly) {
    const float clearDepth = 1.0f;
    glClearNamedFramebufferfv(target_.framebuffer(), GL_DEPTH, 0, &clearDepth);
  }
  const PixelRect whole{0, 0, f.width, f.height};
  const std::span<const PixelRect> tiles = schedule.tiles.empty()
                                               ? std::span<const PixelRect>(&whole, 1)
                                               : std::span<const PixelRect>(schedule.tiles);
  // A tile, or its part of the rectangles to cast.
  const auto cast = [&](const PixelRect& tile) {
    if (!schedule.castOnly) return castTile(f, p, tile);
    for (const PixelRect& r : *schedule.castOnly) castTile(f, p, intersection(tile, r));
  };
  bindForCasting(f, p);
  cast(tiles[0]);
  if (schedule.afterFirstTile) {
    if (f.params.backend == RenderBackend::Compute) copyStopDepth(tiles[0]);
    target_.bindForDrawing();
    afterFirstTileTimer_.begin();
    schedule.afterFirstTile();
    afterFirstTileTimer_.end();
    afterFirstTileTimed_ = true;
    bindForCasting(f, p);
  }
  for (const PixelRect& tile : tiles.subspan(1)) cast(tile);
  if (f.params.backend == RenderBackend::Compute) {
    finishComputeWrites();
  } else {
    glDisable(GL_SCISSOR_TEST);
    glBindVertexArray(0);
    glDisable(GL_DEPTH_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }
  timer_.end();
  lastBackend_ = f.params.backend;
  checkGlError("RaycastPass::render");
}

void RaycastPass::writeMisses(const RaycastFrame& f, const TileSchedule& schedule) {
  // What shaders/compositing.glsl's missedRay() gives every pixel: the background with no coverage, no
  // depth, and a stop depth at infinity (window depth 1, as shaders/window_depth.glsl maps it).
  const float miss[4] = {float(f.params.background.x), float(f.params.background.y),
                         float(f.params.background.z), 0.0f};
  const float infinity = std::numeric_limits<float>::infinity();
  glClearTexImage(target_.colorTexture(), 0, GL_RGBA, GL_FLOAT, miss);
  glClearTexImage(target_.depthTexture(), 0, GL_RED, GL_FLOAT, &infinity);
  if (f.params.backend == RenderBackend::Compute)
    glClearTexImage(stopDepthTexture_, 0, GL_RED, GL_FLOAT, &infinity);
  const float farDepth = 1.0f;
  glClearNamedFramebufferfv(target_.framebuffer(), GL_DEPTH, 0, &farDepth);
  if (schedule.afterFirstTile) {
    target_.bindForDrawing();
    afterFirstTileTimer_.begin();
    schedule.afterFirstTile();
    afterFirstTileTimer_.end();
    afterFirstTileTimed_ = true;
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }
}

double RaycastPass::lastRaycastMs() {
  return std::max(timer_.elapsedMs() - lastAfterFirstTileMs(), 0.0);
}

double RaycastPass::lastAfterFirstTileMs() {
  return afterFirstTileTimed_ ? afterFirstTileTimer_.elapsedMs() : 0.0;
}

void RaycastPass::bindForCasting(const RaycastFrame& f, const ShaderProgram& p) {
  glBindTextureUnit(kRaycastValueUnit, f.pool->texture());
  glBindTextureUnit(kRaycastTfUnit, tfTexture_);
  f.index->bind(kRaycastRopeIndexUnit);
  if (usesStoredGradients(f.params)) glBindTextureUnit(kRaycastSampleUnit, f.gradients->texture());
  if (isIntensityProjection(f.params.mode)) leafMaxima_->bind(kRaycastLeafMaximaUnit);
  if (f.feedback) f.feedback->bind();
  blockBuffer_.bind();
  p.use();
  if (f.params.backend == RenderBackend::Compute) {
    bindComputeTargets(target_);
    glBindImageTexture(kRaycastStopDepthImageUnit, stopDepthTexture_, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    return;
  }
  target_.bindForDrawing();
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_ALWAYS);
  glDepthMask(GL_TRUE);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glBindVertexArray(emptyVertexArray_);
  glEnable(GL_SCISSOR_TEST);
}

void RaycastPass::castTile(const RaycastFrame& f, const ShaderProgram& p, const PixelRect& tile) {
  if (tile.width == 0 || tile.height == 0) return;
  lastPixelsCast_ += uint64_t(tile.width) * tile.height;
  if (f.params.backend == RenderBackend::Compute) {
    dispatchComputeTile(p, tile);
    ++lastDrawCalls_;
    return;
  }
  // Each draw is one triangle around a kTileSize square, cut to it by the scissor: a quad's two triangles
  // would shade the pixel blocks along their diagonal twice on a software rasterizer (each with part of a
  // mask).
  for (uint32_t y = tile.y; y < tile.y + tile.height; y += kTileSize)
    for (uint32_t x = tile.x; x < tile.x + tile.width; x += kTileSize) {
      const uint32_t w = std::min(kTileSize, tile.x + tile.width - x);
      const uint32_t h = std::min(kTileSize, tile.y + tile.height - y);
      glProgramUniform4ui(p.id(), kTileRectLocation, x, y, w, h);
      glScissor(GLint(x), GLint(y), GLsizei(w), GLsizei(h));
      glDrawArrays(GL_TRIANGLES, 0, 3);
      ++lastDrawCalls_;
    }
}

void RaycastPass::copyStopDepth(const PixelRect& tile) {
  if (!stopDepthProgram_) {
    stopDepthProgram_ = std::make_unique<ShaderProgram>(
        std::vector<ShaderFile>{{ShaderStage::Vertex, "shaders/raycast.vert"},
                                {ShaderStage::Fragment, "shaders/stop_depth.frag"}},
        std::vector<std::string>{});
  }
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
  target_.bindForDrawing();
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_ALWAYS);
  glDepthMask(GL_TRUE);
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  glBindTextureUnit(kStopDepthTextureUnit, stopDepthTexture_);
  stopDepthProgram_->use();
  glBindVertexArray(emptyVertexArray_);
  glEnable(GL_SCISSOR_TEST);
  const uint32_t side = std::max(tile.width, tile.height);  // one triangle over the tile's bounding square
  glProgramUniform4ui(stopDepthProgram_->id(), kTileRectLocation, tile.x, tile.y, side, side);
  glScissor(GLint(tile.x), GLint(tile.y), GLsizei(tile.width), GLsizei(tile.height));
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glDisable(GL_SCISSOR_TEST);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glBindVertexArray(0);
}

}  // namespace ropecast
