// GradientPool: the DVR sample texture beside a value texture (the BrickPool's, or the brute-force pass's
// volume): RGBA16_SNORM of the same dimensions, texel i = (v(i+e_x) - v(i-e_x), v(i+e_y) - v(i-e_y),
// v(i+e_z) - v(i-e_z), v(i)), derived on the GPU by shaders/gradient_pool.comp for the regions just uploaded.
// One filtered lookup of it gives a DVR sample its value and its central-difference gradient, where the
// value texture needed seven (docs/RENDERING.md "Direct volume rendering"); it costs kBytesPerTexel more per
// texel of GPU memory, which the pool's budget accounts for (render/brick_pool.h).
//
// Owns GL objects: render thread only, with the GlContext current.
#pragma once

#include <cstdint>
#include <memory>
#include <span>

#include <glm/vec3.hpp>

namespace ropecast {

class ShaderProgram;

class GradientPool {
 public:
  static constexpr uint32_t kBytesPerTexel = 8;  // RGBA16_SNORM

  // Allocates the texture; throws ropecast::Error when GL cannot (naming the size).
  explicit GradientPool(glm::u32vec3 textureDims);
  ~GradientPool();
  GradientPool(const GradientPool&) = delete;
  GradientPool& operator=(const GradientPool&) = delete;

  // Derives the texels of each region [origin, origin + extent) from `valueTexture` (R8/R16, same
  // dimensions), neighbours clamped to the region, and makes the result visible to later texture fetches.
  void derive(uint32_t valueTexture, std::span<const glm::u32vec3> origins, glm::u32vec3 extent);

  uint32_t texture() const { return texture_; }
  glm::u32vec3 dims() const { return dims_; }

 private:
  glm::u32vec3 dims_;
  uint32_t texture_ = 0;
  std::unique_ptr<ShaderProgram> program_;
};

}  // namespace ropecast
