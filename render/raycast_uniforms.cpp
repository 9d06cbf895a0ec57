#include "render/raycast_uniforms.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include <epoxy/gl.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "core/error.h"
#include "core/transfer_function.h"
#include "render/gl_context.h"
#include "render/render_target.h"
#include "render/shader_program.h"
#include "store/octree_layout.h"
#include "store/volume_source.h"

namespace ropecast {

std::string floatDefine(const char* name, double value) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s %.9g", name, value);
  return buf;
}

std::vector<std::string> raycastDefines(const RenderParams& params) {
  std::vector<std::string> defines = {
      params.mode == RenderMode::Iso     ? "RAYCAST_MODE_ISO"
      : params.mode == RenderMode::Dvr   ? "RAYCAST_MODE_DVR"
      : params.mode == RenderMode::Aip   ? "RAYCAST_MODE_AIP"
      : params.mode == RenderMode::Slice ? "RAYCAST_MODE_SLICE"
                                         : "RAYCAST_MODE_MIP",
      floatDefine("MIP_SIGN", projectionSign(params.mode)),
      "BRICK_BORDER " + std::to_string(kBrickBorder),
      "ISO_BISECTION_STEPS " + std::to_string(kIsoBisectionSteps),
      floatDefine("DVR_SHADE_GRADIENT_THRESHOLD", kDvrShadeGradientThreshold),
      floatDefine("DVR_DEPTH_OPACITY", kDvrDepthOpacity),
      "TF_ENTRIES " + std::to_string(TfTable::kDefaultEntries),
  };
  if (dvrLightingOf(params) == DvrLighting::Stored) defines.push_back("DVR_STORED_GRADIENTS");
  if (dvrLightingOf(params) == DvrLighting::Unlit) defines.push_back("DVR_UNLIT");
  return defines;
}

void checkRaycastInputs(const RenderParams& params, const TfTable* tf, const char* where) {
  if (!(params.stepVoxels > 0.0)) throw Error(std::string(where) + ": --step must be positive");
  if (usesTransferFunction(params.mode) && !tf)
    throw Error(std::string(where) + ": " + std::string(renderModeName(params.mode)) +
                " mode needs a baked transfer function");
  if (tf && tf->entryCount() != TfTable::kDefaultEntries)
    throw Error(std::string(where) + ": transfer function tables have " +
                std::to_string(TfTable::kDefaultEntries) + " entries, got " +
                std::to_string(tf->entryCount()));
}

uint32_t createTfTexture() {
  GLuint texture = 0;
  glCreateTextures(GL_TEXTURE_1D, 1, &texture);
  glTextureStorage1D(texture, 1, GL_RGBA32F, TfTable::kDefaultEntries);
  for (GLenum p : {GL_TEXTURE_MIN_FILTER, GL_TEXTURE_MAG_FILTER}) glTextureParameteri(texture, p, GL_LINEAR);
  glTextureParameteri(texture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  return texture;
}

void uploadTf(uint32_t texture, const TfTable& tf) {
  glTextureSubImage1D(texture, 0, 0, GLsizei(tf.entryCount()), GL_RGBA, GL_FLOAT, tf.entries().data());
}

RaycastBlock raycastBlock(const Camera& camera, uint32_t width, uint32_t height, glm::u32vec3 dims,
                          glm::dvec3 spacing, const ValueMapping& mapping, double storedMax,
                          const RenderParams& rp) {
  // Never draw rays that are not finite, nor a volume without a box: the traversal loops would not end (a
  // hung GPU).
  if (const std::string problem = viewProblem(camera.eye, camera.target); !problem.empty())
    throw Error("ray cast: unusable camera: " + problem);
  if (!isValidSpacing(spacing))
    throw Error("ray cast: volume spacing " + formatSpacing(spacing) + " is not " + validSpacingText());
  const CameraFrame cam = cameraFrame(camera);
  RaycastBlock b{};
  b.eye = glm::vec3(camera.eye);
  b.forward = glm::vec3(cam.forward);
  b.right = glm::vec3(cam.right);
  b.up = glm::vec3(cam.up);
  b.tanHalfFov = float(std::tan(glm::radians(camera.fovYDeg) * 0.5));
  b.aspect = float(double(width) / double(height));
  b.imageSize = {width, height};

  const WorldBox sampled = sampledWorldBox(rp, dims, spacing);
  b.clipMin = glm::vec3(sampled.lo);
  b.clipMax = glm::vec3(sampled.hi);
  b.clipPlaneFar = std::numeric_limits<float>::infinity();
  if (rp.clipPlane.enabled()) {
    b.clipPlaneNormal = glm::vec3(rp.clipPlane.normal);
    // A slice's rays start at the plane itself; it has no slab.
    const bool slice = rp.mode == RenderMode::Slice;
    b.clipPlaneOffset = float(slice ? rp.clipPlane.offset() : rp.clipPlane.keptFrom());
    if (!slice) b.clipPlaneFar = float(rp.clipPlane.keptTo());
  }
  b.capBounds = capBoundsOf(rp, dims);
  b.spacing = glm::vec3(spacing);
  b.minSpacing = float(std::min({spacing.x, spacing.y, spacing.z}));

  b.stepVoxels = float(rp.stepVoxels);
  b.ert = float(rp.ert);
  b.background = glm::vec3(rp.background);
  b.isoValue = float(mapping.toStored(rp.isoValue) / storedMax);
  b.isoBaseColor = glm::vec3(rp.lighting.isoBaseColor);
  b.ambient = float(rp.lighting.ambient);
  b.diffuse = float(rp.lighting.diffuse);
  b.specular = float(rp.lighting.specular);
  b.shininess = float(rp.lighting.shininess);
  b.leafMaximaLargest = 2.0f;  // no leaf's largest value known: no MIP ray ends early (values lie in [0, 1])
  return b;
}

DepthRange windowDepthRange(const Camera& camera, glm::dvec3 volumeMax) {
  const double extent = glm::length(volumeMax);
  const double farDepth = glm::length(camera.eye - 0.5 * volumeMax) + extent;
  return {std::max(1e-4 * extent, 1e-9), std::max(farDepth, 2e-4 * extent)};
}

void bindComputeTargets(const RenderTarget& target) {
  glBindImageTexture(kRaycastColorImageUnit, target.colorTexture(), 0, GL_FALSE, 0, GL_WRITE_ONLY,
                     GL_RGBA32F);
  glBindImageTexture(kRaycastDepthImageUnit, target.depthTexture(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
}

void dispatchComputeTile(const ShaderProgram& program, const PixelRect& tile) {
  if (tile.width == 0 || tile.height == 0) return;
  const uint32_t side = kRaycastWorkgroupSize;
  glProgramUniform2ui(program.id(), kRaycastTileOriginLocation, tile.x, tile.y);
  glProgramUniform2ui(program.id(), kRaycastTileEndLocation, tile.x + tile.width, tile.y + tile.height);
  glDispatchCompute((tile.width + side - 1) / side, (tile.height + side - 1) / side, 1);
}

void finishComputeWrites() {
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
}

RaycastBlockBuffer::RaycastBlockBuffer() {
  glCreateBuffers(1, &buffer_);
  glNamedBufferStorage(buffer_, sizeof(RaycastBlock), nullptr, GL_DYNAMIC_STORAGE_BIT);
}

RaycastBlockBuffer::~RaycastBlockBuffer() {
  glDeleteBuffers(1, &buffer_);
}

void RaycastBlockBuffer::upload(const RaycastBlock& block) {
  glNamedBufferSubData(buffer_, 0, sizeof(RaycastBlock), &block);
  glBindBufferBase(GL_UNIFORM_BUFFER, GLuint(kRaycastBlockBinding), buffer_);
}

void RaycastBlockBuffer::bind() const {
  glBindBufferBase(GL_UNIFORM_BUFFER, GLuint(kRaycastBlockBinding), buffer_);
}

}  // namespace ropecast
