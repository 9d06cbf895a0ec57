#include "render/gradient_pool.h"

#include <string>

#include <epoxy/gl.h>
#include <glm/vector_relational.hpp>

#include "core/error.h"
#include "render/shader_program.h"

namespace ropecast {

namespace {
constexpr GLuint kValueUnit = 0;
constexpr GLuint kSampleImageUnit = 0;  // binding = 0 in shaders/gradient_pool.comp
constexpr GLuint kWorkgroupEdge = 4;
}  // namespace

GradientPool::GradientPool(glm::u32vec3 textureDims) : dims_(textureDims) {
  while (glGetError() != GL_NO_ERROR) {
  }
  glCreateTextures(GL_TEXTURE_3D, 1, &texture_);
  glTextureStorage3D(texture_, 1, GL_RGBA16_SNORM, GLsizei(dims_.x), GLsizei(dims_.y), GLsizei(dims_.z));
  const GLenum e = glGetError();
  if (e != GL_NO_ERROR) {
    glDeleteTextures(1, &texture_);
    throw Error("GradientPool: allocating a " + std::to_string(dims_.x) + "x" + std::to_string(dims_.y) +
                "x" + std::to_string(dims_.z) + " RGBA16 3D texture failed (GL error " + std::to_string(e) +
                "); lower --gpu-budget or use --gradients computed");
  }
  glTextureParameteri(texture_, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(texture_, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  for (GLenum p : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
    glTextureParameteri(texture_, p, GL_CLAMP_TO_EDGE);
  program_ = std::make_unique<ShaderProgram>(
      std::vector<ShaderFile>{{ShaderStage::Compute, "shaders/gradient_pool.comp"}},
      std::vector<std::string>{});
  glProgramUniform1i(program_->id(), program_->uniform("uValues"), GLint(kValueUnit));
}

GradientPool::~GradientPool() {
  if (texture_) glDeleteTextures(1, &texture_);
}

void GradientPool::derive(uint32_t valueTexture, std::span<const glm::u32vec3> origins, glm::u32vec3 extent) {
  if (origins.empty()) return;
  const GLuint id = program_->id();
  program_->use();
  glBindTextureUnit(kValueUnit, valueTexture);
  glBindImageTexture(kSampleImageUnit, texture_, 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA16_SNORM);
  glProgramUniform3i(id, program_->uniform("uExtent"), GLint(extent.x), GLint(extent.y), GLint(extent.z));
  const auto groups = [](uint32_t n) { return (n + kWorkgroupEdge - 1) / kWorkgroupEdge; };
  for (const glm::u32vec3& o : origins) {
    if (glm::any(glm::greaterThan(o + extent, dims_)))
      throw Error("GradientPool::derive: region beyond the " + std::to_string(dims_.x) + "x" +
                  std::to_string(dims_.y) + "x" + std::to_string(dims_.z) + " texture");
    glProgramUniform3i(id, program_->uniform("uOrigin"), GLint(o.x), GLint(o.y), GLint(o.z));
    glDispatchCompute(groups(extent.x), groups(extent.y), groups(extent.z));
  }
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
}

}  // namespace ropecast
