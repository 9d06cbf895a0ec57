// RenderTarget: the float targets a ray-cast pass renders into and reads back, shared by RaycastPass and
// BruteForcePass: an RGBA32F color texture (final color, alpha = coverage), an R32F world-depth texture
// (world units along the camera axis, +inf = miss), optionally a DEPTH_COMPONENT32F depth buffer (the
// fragment entry point's window depth), and the framebuffer that binds them as color attachments 0 and 1.
//
// Owns GL objects: render thread only, with the GlContext current.
#pragma once

#include <cstdint>
#include <string>

#include "core/float_image.h"

namespace ropecast {

class RenderTarget {
 public:
  // `owner` prefixes error messages ("RaycastPass").
  RenderTarget(std::string owner, bool withDepthBuffer);
  ~RenderTarget();
  RenderTarget(const RenderTarget&) = delete;
  RenderTarget& operator=(const RenderTarget&) = delete;

  // Reallocates the textures when the size changes. Throws ropecast::Error when the framebuffer is
  // incomplete.
  void resize(uint32_t width, uint32_t height);
  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }

  // Binds the framebuffer for a full-target draw of opaque pixels: viewport over the whole target, no
  // blending, no face culling. The caller sets the depth test it needs.
  void bindForDrawing() const;

  // The targets, row 0 as GL stores it (the passes draw image row r into framebuffer row r). Synchronous.
  FloatImage readColor() const;
  FloatImage readDepth() const;
  // One pixel of readDepth's image (x, y < width, height), without reading the rest.
  float readDepthAt(uint32_t x, uint32_t y) const;
  // The depth buffer's window depths in [0, 1]. Throws ropecast::Error for a target without one.
  FloatImage readDepthBuffer() const;

  uint32_t framebuffer() const { return framebuffer_; }
  uint32_t colorTexture() const { return colorTexture_; }
  uint32_t depthTexture() const { return worldDepthTexture_; }

 private:
  FloatImage read(uint32_t texture, uint32_t channels, const char* what) const;

  std::string owner_;
  bool withDepthBuffer_;
  uint32_t width_ = 0, height_ = 0;
  uint32_t colorTexture_ = 0, worldDepthTexture_ = 0, depthBuffer_ = 0, framebuffer_ = 0;
};

}  // namespace ropecast
