#include "render/brute_force_pass.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <epoxy/gl.h>
#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/transfer_function.h"
#include "render/gl_context.h"
#include "render/gradient_pool.h"
#include "render/raycast_uniforms.h"
#include "render/shader_program.h"
#include "store/octree_layout.h"

namespace ropecast {

namespace {

constexpr GLuint kVolumeUnit = 0;
constexpr GLuint kTfUnit = 1;
constexpr GLuint kVolumeSamplesUnit = 2;

}  // namespace

BruteForcePass::BruteForcePass(const BrickSource& source) : info_(source.info()) {
  const OctreeLayout& layout = info_.layout;
  const glm::u32vec3 n = layout.dims;
  GLint max3d = 0;
  glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3d);
  if (std::max({n.x, n.y, n.z}) > uint32_t(max3d))
    throw Error("BruteForcePass: the volume (" + std::to_string(n.x) + "x" + std::to_string(n.y) + "x" +
                std::to_string(n.z) + ") exceeds GL_MAX_3D_TEXTURE_SIZE " + std::to_string(max3d));
  const bool u8 = info_.storedType == SampleType::UInt8;
  const GLenum type = u8 ? GL_UNSIGNED_BYTE : GL_UNSIGNED_SHORT;
  glCreateTextures(GL_TEXTURE_3D, 1, &volumeTexture_);
  glTextureStorage3D(volumeTexture_, 1, u8 ? GL_R8 : GL_R16, GLsizei(n.x), GLsizei(n.y), GLsizei(n.z));
  for (GLenum p : {GL_TEXTURE_MIN_FILTER, GL_TEXTURE_MAG_FILTER})
    glTextureParameteri(volumeTexture_, p, GL_LINEAR);
  for (GLenum p : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
    glTextureParameteri(volumeTexture_, p, GL_CLAMP_TO_EDGE);
  volumeBytes_ = uint64_t(n.x) * n.y * n.z * (u8 ? 1 : 2);

  // Level-0 bricks straight from their stored layout: the unpack state skips the border.
  const uint32_t edge = layout.storedBrickEdge(), b = layout.brickSize;
  std::vector<std::byte> brick(source.brickBytes());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, GLint(edge));
  glPixelStorei(GL_UNPACK_IMAGE_HEIGHT, GLint(edge));
  glPixelStorei(GL_UNPACK_SKIP_PIXELS, GLint(kBrickBorder));
  glPixelStorei(GL_UNPACK_SKIP_ROWS, GLint(kBrickBorder));
  glPixelStorei(GL_UNPACK_SKIP_IMAGES, GLint(kBrickBorder));
  const glm::u32vec3 nodes = layout.insideNodes(layout.maxDepth);
  for (uint32_t z = 0; z < nodes.z; ++z)
    for (uint32_t y = 0; y < nodes.y; ++y)
      for (uint32_t x = 0; x < nodes.x; ++x) {
        const NodeKey key{layout.maxDepth, {x, y, z}};
        source.readBrick(key, brick);
        const glm::u32vec3 origin = key.coord * b;
        const glm::u32vec3 extent = glm::min(glm::u32vec3(b), n - origin);
        glTextureSubImage3D(volumeTexture_, 0, GLint(origin.x), GLint(origin.y), GLint(origin.z),
                            GLsizei(extent.x), GLsizei(extent.y), GLsizei(extent.z), GL_RED, type,
                            brick.data());
      }
  for (GLenum p : {GL_UNPACK_ROW_LENGTH, GL_UNPACK_IMAGE_HEIGHT, GL_UNPACK_SKIP_PIXELS, GL_UNPACK_SKIP_ROWS,
                   GL_UNPACK_SKIP_IMAGES})
    glPixelStorei(p, 0);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);

  tfTexture_ = createTfTexture();
  glCreateFramebuffers(1, &framebuffer_);
  glCreateVertexArrays(1, &emptyVertexArray_);
  checkGlError("BruteForcePass: volume upload");
}

BruteForcePass::~BruteForcePass() {
  GLuint textures[] = {volumeTexture_, tfTexture_, colorTexture_, worldDepthTexture_};
  glDeleteTextures(4, textures);
  glDeleteFramebuffers(1, &framebuffer_);
  glDeleteVertexArrays(1, &emptyVertexArray_);
}

const ShaderProgram& BruteForcePass::program(const RenderParams& params) {
  std::unique_ptr<ShaderProgram>& p = programs_[params.mode == RenderMode::Iso ? 0
                                                : usesStoredGradients(params)  ? 2
                                                                               : 1];
  if (!p) {
    p = std::make_unique<ShaderProgram>(
        std::vector<ShaderFile>{{ShaderStage::Vertex, "shaders/brute_force.vert"},
                                {ShaderStage::Fragment, "shaders/brute_force.frag"}},
        raycastDefines(params));
  }
  return *p;
}

void BruteForcePass::resizeTargets(uint32_t width, uint32_t height) {
  if (width == width_ && height == height_) return;
  GLuint old[] = {colorTexture_, worldDepthTexture_};
  glDeleteTextures(2, old);
  glCreateTextures(GL_TEXTURE_2D, 1, &colorTexture_);
  glTextureStorage2D(colorTexture_, 1, GL_RGBA32F, GLsizei(width), GLsizei(height));
  glCreateTextures(GL_TEXTURE_2D, 1, &worldDepthTexture_);
  glTextureStorage2D(worldDepthTexture_, 1, GL_R32F, GLsizei(width), GLsizei(height));
  glNamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT0, colorTexture_, 0);
  glNamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT1, worldDepthTexture_, 0);
  const GLenum drawBuffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(framebuffer_, 2, drawBuffers);
  if (glCheckNamedFramebufferStatus(framebuffer_, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw Error("BruteForcePass: render targets incomplete");
  width_ = width;
  height_ = height;
}

void BruteForcePass::render(const BruteForceFrame& f) {
  if (f.width == 0 || f.height == 0) throw Error("BruteForcePass::render: image size must be positive");
  checkRaycastInputs(f.params, f.tf, "BruteForcePass::render");
  const ShaderProgram& p = program(f.params);
  if (usesStoredGradients(f.params) && !gradients_) {
    gradients_ = std::make_unique<GradientPool>(info_.layout.dims);
    const glm::u32vec3 origin(0);
    gradients_->derive(volumeTexture_, std::span(&origin, 1), info_.layout.dims);
  }
  resizeTargets(f.width, f.height);
  if (f.tf) uploadTf(tfTexture_, *f.tf);

  // Uniforms: the names of shaders/raycast_common.glsl and shading.glsl, which brute_force.frag includes.
  const GLuint id = p.id();
  const auto u = [&](const char* name) { return p.uniform(name); };
  setSharedRaycastUniforms(p, f.camera, f.width, f.height, info_.layout.dims, info_.volume.spacing,
                           info_.mapping, info_.storedType == SampleType::UInt8 ? 255.0 : 65535.0, f.params);
  glProgramUniform3i(id, u("uVolumeDims"), GLint(info_.layout.dims.x), GLint(info_.layout.dims.y),
                     GLint(info_.layout.dims.z));
  glProgramUniform1i(id, u("uVolume"), GLint(kVolumeUnit));
  glProgramUniform1i(id, u("uVolumeSamples"), GLint(kVolumeSamplesUnit));
  glProgramUniform1i(id, u("uTransferFunction"), GLint(kTfUnit));
  glProgramUniform1f(id, u("uTfEntries"), float(TfTable::kDefaultEntries));

  glBindTextureUnit(kVolumeUnit, volumeTexture_);
  glBindTextureUnit(kTfUnit, tfTexture_);
  if (gradients_) glBindTextureUnit(kVolumeSamplesUnit, gradients_->texture());
  p.use();
  timer_.begin();
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glViewport(0, 0, GLsizei(f.width), GLsizei(f.height));
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDisable(GL_DEPTH_TEST);
  glBindVertexArray(emptyVertexArray_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  timer_.end();
  checkGlError("BruteForcePass::render");
}

FloatImage BruteForcePass::readColor() const {
  return readFloatTexture(colorTexture_, width_, height_, 4, "BruteForcePass::readColor");
}

FloatImage BruteForcePass::readDepth() const {
  return readFloatTexture(worldDepthTexture_, width_, height_, 1, "BruteForcePass::readDepth");
}

}  // namespace ropecast
