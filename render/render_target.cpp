#include "render/render_target.h"

#include <utility>
#include <vector>

#include <epoxy/gl.h>

#include "core/error.h"
#include "render/gl_context.h"

namespace ropecast {

RenderTarget::RenderTarget(std::string owner, bool withDepthBuffer)
    : owner_(std::move(owner)), withDepthBuffer_(withDepthBuffer) {
  glCreateFramebuffers(1, &framebuffer_);
}

RenderTarget::~RenderTarget() {
  const GLuint textures[] = {colorTexture_, worldDepthTexture_, depthBuffer_};
  glDeleteTextures(3, textures);
  glDeleteFramebuffers(1, &framebuffer_);
}

void RenderTarget::bindForDrawing() const {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glViewport(0, 0, GLsizei(width_), GLsizei(height_));
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
}

void RenderTarget::resize(uint32_t width, uint32_t height) {
  if (width == width_ && height == height_) return;
  const GLuint old[] = {colorTexture_, worldDepthTexture_, depthBuffer_};
  glDeleteTextures(3, old);
  depthBuffer_ = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &colorTexture_);
  glTextureStorage2D(colorTexture_, 1, GL_RGBA32F, GLsizei(width), GLsizei(height));
  glCreateTextures(GL_TEXTURE_2D, 1, &worldDepthTexture_);
  glTextureStorage2D(worldDepthTexture_, 1, GL_R32F, GLsizei(width), GLsizei(height));
  for (GLuint t : {colorTexture_, worldDepthTexture_}) {
    glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  }
  glNamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT0, colorTexture_, 0);
  glNamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT1, worldDepthTexture_, 0);
  if (withDepthBuffer_) {
    glCreateTextures(GL_TEXTURE_2D, 1, &depthBuffer_);
    glTextureStorage2D(depthBuffer_, 1, GL_DEPTH_COMPONENT32F, GLsizei(width), GLsizei(height));
    glNamedFramebufferTexture(framebuffer_, GL_DEPTH_ATTACHMENT, depthBuffer_, 0);
  }
  const GLenum drawBuffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(framebuffer_, 2, drawBuffers);
  const GLenum status = glCheckNamedFramebufferStatus(framebuffer_, GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    throw Error(owner_ + ": render targets incomplete (status 0x" + std::to_string(status) + ")");
  width_ = width;
  height_ = height;
}

FloatImage RenderTarget::read(uint32_t texture, uint32_t channels, const char* what) const {
  FloatImage img{width_, height_, channels, std::vector<float>(size_t(width_) * height_ * channels)};
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(texture, 0, channels == 1 ? GL_RED : GL_RGBA, GL_FLOAT,
                    GLsizei(img.pixels.size() * sizeof(float)), img.pixels.data());
  checkGlError((owner_ + what).c_str());
  return img;
}

FloatImage RenderTarget::readColor() const {
  return read(colorTexture_, 4, "::readColor");
}

FloatImage RenderTarget::readDepth() const {
  return read(worldDepthTexture_, 1, "::readDepth");
}

float RenderTarget::readDepthAt(uint32_t x, uint32_t y) const {
  if (x >= width_ || y >= height_)
    throw Error(owner_ + "::readDepthAt: pixel " + std::to_string(x) + ", " + std::to_string(y) +
                " lies outside the " + std::to_string(width_) + "x" + std::to_string(height_) + " target");
  float depth = 0.0f;
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureSubImage(worldDepthTexture_, 0, GLint(x), GLint(y), 0, 1, 1, 1, GL_RED, GL_FLOAT, sizeof depth,
                       &depth);
  checkGlError((owner_ + "::readDepthAt").c_str());
  return depth;
}

FloatImage RenderTarget::readDepthBuffer() const {
  if (!withDepthBuffer_) throw Error(owner_ + "::readDepthBuffer: this target has no depth buffer");
  FloatImage img{width_, height_, 1, std::vector<float>(size_t(width_) * height_)};
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(depthBuffer_, 0, GL_DEPTH_COMPONENT, GL_FLOAT, GLsizei(img.pixels.size() * sizeof(float)),
                    img.pixels.data());
  checkGlError((owner_ + "::readDepthBuffer").c_str());
  return img;
}

}  // namespace ropecast
