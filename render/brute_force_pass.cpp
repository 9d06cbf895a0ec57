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
  glCreateVertexArrays(1, &emptyVertexArray_);
  checkGlError("BruteForcePass: volume upload");
}

BruteForcePass::~BruteForcePass() {
  const GLuint textures[] = {volumeTexture_, tfTexture_};
  glDeleteTextures(2, textures);
  glDeleteVertexArrays(1, &emptyVertexArray_);
}

const ShaderProgram& BruteForcePass::program(const RenderParams& params) {
  std::unique_ptr<ShaderProgram>& p = programs_[{params.backend, params.mode, dvrLightingOf(params)}];
  if (!p) {
    const std::vector<ShaderFile> files =
        params.backend == RenderBackend::Compute
            ? std::vector<ShaderFile>{{ShaderStage::Compute, "shaders/brute_force.comp"}}
            : std::vector<ShaderFile>{{ShaderStage::Vertex, "shaders/brute_force.vert"},
                                      {ShaderStage::Fragment, "shaders/brute_force.frag"}};
    p = std::make_unique<ShaderProgram>(files, raycastDefines(params));
  }
  return *p;
}

void BruteForcePass::render(const BruteForceFrame& worldFrame) {
  BruteForceFrame f = worldFrame;  // as the volume's own axes see it (store/volume_source.h)
  f.camera = cameraInVolume(worldFrame.camera, info_.volume);
  f.params.clipPlane = clipPlaneInVolume(worldFrame.params.clipPlane, info_.volume);
  if (f.width == 0 || f.height == 0) throw Error("BruteForcePass::render: image size must be positive");
  const RenderBackend stage = f.params.backend;
  if (stage != RenderBackend::Fragment && stage != RenderBackend::Compute)
    throw Error("BruteForcePass::render: params.backend must name an entry point, fragment or compute; got " +
                std::string(renderBackendName(stage)));
  checkRaycastInputs(f.params, f.tf, "BruteForcePass::render");
  const ShaderProgram& p = program(f.params);
  if (usesStoredGradients(f.params) && !gradients_) {
    gradients_ = std::make_unique<GradientPool>(info_.layout.dims);
    const glm::u32vec3 origin(0);
    gradients_->derive(volumeTexture_, std::span(&origin, 1), info_.layout.dims);
  }
  target_.resize(f.width, f.height);
  if (f.tf) uploadTf(tfTexture_, *f.tf);

  // The block of the rope ray caster's shaders, which brute_force_common.glsl shares; the volume is the value
  // texture.
  RaycastBlock block = raycastBlock(f.camera, f.width, f.height, info_.layout.dims, info_.volume.spacing,
                                    info_.mapping, storedMaxOf(info_.storedType), f.params);
  block.valueTexelSize = glm::vec3(1.0 / glm::dvec3(info_.layout.dims));
  blockBuffer_.upload(block);

  glBindTextureUnit(kRaycastValueUnit, volumeTexture_);
  glBindTextureUnit(kRaycastTfUnit, tfTexture_);
  if (gradients_) glBindTextureUnit(kRaycastSampleUnit, gradients_->texture());
  p.use();
  timer_.begin();
  if (stage == RenderBackend::Compute) {
    bindComputeTargets(target_);
    dispatchComputeTile(p, PixelRect{0, 0, f.width, f.height});
    finishComputeWrites();
  } else {
    target_.bindForDrawing();
    glDisable(GL_DEPTH_TEST);
    glBindVertexArray(emptyVertexArray_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }
  timer_.end();
  checkGlError("BruteForcePass::render");
}

}  // namespace ropecast
