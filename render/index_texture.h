// IndexTexture: the rope index on the GPU, a buffer texture (glTexBuffer) of 32-bit unsigned texels with 1, 2
// or 4 components (R32UI / RG32UI / RGBA32UI, read by `usamplerBuffer uRopeIndex` in
// shaders/rope_traversal.glsl); also a MIP frame's leaf maxima beside it (render/raycast_pass.h). The buffer
// grows by doubling as its contents grow and is reused frame to frame.
//
// Owns GL objects: render thread only, with the GlContext current.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace ropecast {

class IndexTexture {
 public:
  // componentsPerTexel: 1 (uint texels), 2 (uvec2) or 4 (uvec4); throws ropecast::Error otherwise.
  explicit IndexTexture(uint32_t componentsPerTexel, int maxTextureBufferTexels);
  ~IndexTexture();
  IndexTexture(const IndexTexture&) = delete;
  IndexTexture& operator=(const IndexTexture&) = delete;

  // Replaces the contents with `words` (texel-major, componentsPerTexel words per texel). Throws
  // ropecast::Error when the word count is not a multiple of the texel size or exceeds
  // GL_MAX_TEXTURE_BUFFER_SIZE.
  void upload(std::span<const uint32_t> words);

  uint32_t componentsPerTexel() const { return components_; }
  size_t texelCount() const { return texels_; }
  size_t capacityBytes() const { return capacityBytes_; }
  uint32_t texture() const { return texture_; }
  // Binds the buffer texture to texture unit `unit`.
  void bind(uint32_t unit) const;

 private:
  uint32_t components_;
  int maxTexels_;
  uint32_t buffer_ = 0;
  uint32_t texture_ = 0;
  size_t capacityBytes_ = 0;
  size_t texels_ = 0;
};

}  // namespace ropecast
