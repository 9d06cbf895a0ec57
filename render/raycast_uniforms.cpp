#include "render/raycast_uniforms.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <epoxy/gl.h>
#include <glm/trigonometric.hpp>

#include "core/error.h"
#include "core/transfer_function.h"
#include "render/gl_context.h"
#include "render/shader_program.h"
#include "store/octree_layout.h"
#include "store/volume_source.h"

namespace ropecast {

void setVec3Uniform(uint32_t program, int location, glm::dvec3 v) {
  glProgramUniform3f(program, location, float(v.x), float(v.y), float(v.z));
}

std::string floatDefine(const char* name, double value) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s %.9g", name, value);
  return buf;
}

std::vector<std::string> raycastDefines(const RenderParams& params) {
  std::vector<std::string> defines = {
      params.mode == RenderMode::Iso ? "RAYCAST_MODE_ISO" : "RAYCAST_MODE_DVR",
      "BRICK_BORDER " + std::to_string(kBrickBorder),
      "ISO_BISECTION_STEPS " + std::to_string(kIsoBisectionSteps),
      floatDefine("DVR_SHADE_GRADIENT_THRESHOLD", kDvrShadeGradientThreshold),
  };
  if (usesStoredGradients(params)) defines.push_back("DVR_STORED_GRADIENTS");
  return defines;
}

void checkRaycastInputs(const RenderParams& params, const TfTable* tf, const char* where) {
  if (!(params.stepVoxels > 0.0)) throw Error(std::string(where) + ": --step must be positive");
  if (params.mode == RenderMode::Dvr && !tf)
    throw Error(std::string(where) + ": DVR mode needs a baked transfer function");
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

void setSharedRaycastUniforms(const ShaderProgram& p, const Camera& camera, uint32_t width, uint32_t height,
                              glm::u32vec3 dims, glm::dvec3 spacing, const ValueMapping& mapping,
                              double storedMax, const RenderParams& rp) {
  const GLuint id = p.id();
  const auto u = [&](const char* name) { return p.uniform(name); };
  // Never draw rays that are not finite, nor a volume without a box: the traversal loops would not end (a
  // hung GPU).
  if (const std::string problem = viewProblem(camera.eye, camera.target); !problem.empty())
    throw Error("ray cast: unusable camera: " + problem);
  if (!isValidSpacing(spacing))
    throw Error("ray cast: volume spacing " + formatSpacing(spacing) +
                " is not three finite positive numbers");
  const CameraFrame cam = cameraFrame(camera);
  setVec3Uniform(id, u("uEye"), camera.eye);
  setVec3Uniform(id, u("uForward"), cam.forward);
  setVec3Uniform(id, u("uRight"), cam.right);
  setVec3Uniform(id, u("uUp"), cam.up);
  glProgramUniform1f(id, u("uTanHalfFov"), float(std::tan(glm::radians(camera.fovYDeg) * 0.5)));
  glProgramUniform1f(id, u("uAspect"), float(double(width) / double(height)));
  glProgramUniform2ui(id, u("uImageSize"), width, height);

  setVec3Uniform(id, u("uVolumeMax"), glm::dvec3(dims) * spacing);
  setVec3Uniform(id, u("uSpacing"), spacing);
  glProgramUniform1f(id, u("uMinSpacing"), float(std::min({spacing.x, spacing.y, spacing.z})));

  glProgramUniform1f(id, u("uStepVoxels"), float(rp.stepVoxels));
  glProgramUniform1f(id, u("uErt"), float(rp.ert));
  setVec3Uniform(id, u("uBackground"), rp.background);
  glProgramUniform1f(id, u("uIsoValue"), float(mapping.toStored(rp.isoValue) / storedMax));
  setVec3Uniform(id, u("uIsoBaseColor"), rp.lighting.isoBaseColor);
  glProgramUniform1f(id, u("uAmbient"), float(rp.lighting.ambient));
  glProgramUniform1f(id, u("uDiffuse"), float(rp.lighting.diffuse));
  glProgramUniform1f(id, u("uSpecular"), float(rp.lighting.specular));
  glProgramUniform1f(id, u("uShininess"), float(rp.lighting.shininess));
}

FloatImage readFloatTexture(uint32_t texture, uint32_t width, uint32_t height, uint32_t channels,
                            const char* where) {
  FloatImage img{width, height, channels, std::vector<float>(size_t(width) * height * channels)};
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(texture, 0, channels == 1 ? GL_RED : GL_RGBA, GL_FLOAT,
                    GLsizei(img.pixels.size() * sizeof(float)), img.pixels.data());
  checkGlError(where);
  return img;
}

}  // namespace ropecast
