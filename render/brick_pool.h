// BrickPool: the GPU brick pool, one large 3D texture (R8 or R16 UNORM by the store's sample type, LINEAR
// filtering, CLAMP_TO_EDGE) cut into slots of storedBrickEdge()^3 texels (B + 2*kBrickBorder per axis) laid
// out on a 3D slot grid, with uploads through glTexSubImage3D, directly from client memory or
// (uploadThroughPbo) a frame's bricks copied into one orphaned pixel buffer object first. Which brick lives
// in which slot is the loader's SlotTable's business; the pool only holds the texels.
//
// BrickPoolGeometry and slotOrigin() are plain data and pure functions (any thread); the shader computes the
// same slot -> texel origin from the uniforms uPoolSlotGrid / uPoolSlotEdge (shaders/raycast_common.glsl).
// BrickPool owns a GL texture: render thread only, with the GlContext current.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/sample_type.h"

namespace ropecast {

struct GlContextInfo;

struct BrickPoolGeometry {
  uint32_t slotEdge = 0;        // texels per slot per axis: brickSize + 2*kBrickBorder
  glm::u32vec3 slotGrid{0};     // slots per axis
  glm::u32vec3 textureDims{0};  // slotGrid * slotEdge

  uint32_t slotCount() const { return slotGrid.x * slotGrid.y * slotGrid.z; }
  // Texel origin of a slot: slots are numbered x fastest over the grid.
  glm::u32vec3 slotOrigin(uint32_t slot) const {
    return glm::u32vec3(slot % slotGrid.x, (slot / slotGrid.x) % slotGrid.y,
                        slot / (slotGrid.x * slotGrid.y)) *
           slotEdge;
  }
};

// At most this many slots: the shader's float slot -> texel origin (poolSlotOrigin in shaders/shading.glsl)
// is exact below it. 2^21 slots of 32^3 bricks are 98 GB of 8-bit samples.
inline constexpr uint64_t kMaxPoolSlots = uint64_t(1) << 21;

// The largest slot grid of `slotEdge`-texel slots within `budgetBytes` whose texture stays within
// max3DTextureSize per axis, with as few slots across x as make a texture row a multiple of 64 bytes
// (rows of linear layouts are padded to that; fewer slots than that: one across); `extraBytesPerTexel` are
// those of textures of the same dimensions kept beside the pool (a GradientPool), which the budget pays for
// too. With `maxSlots` (the bricks the volume has) the grid holds at least that many slots where the budget
// allows, and not many more: a small volume gets a small pool, not the whole budget. Never more than
// kMaxPoolSlots. Throws UsageError ("--gpu-budget ...") when the budget holds no slot, ropecast::Error when
// max3DTextureSize is below the slot edge.
BrickPoolGeometry planBrickPool(uint32_t brickSize, SampleType storedType, uint64_t budgetBytes,
                                int max3DTextureSize, uint32_t extraBytesPerTexel = 0,
                                uint64_t maxSlots = UINT64_MAX);

// The default --gpu-budget: half the memory the driver reports, at most 4 GiB; else 512 MiB.
uint64_t defaultGpuBudgetBytes(const GlContextInfo& info);

// One brick for BrickPool::uploadBatch.
struct BrickPoolUpload {
  uint32_t slot = 0;
  std::span<const std::byte> brick;
};

struct BrickPoolConfig {
  uint32_t brickSize = 32;
  SampleType storedType = SampleType::UInt8;  // UInt8 -> R8, UInt16 -> R16
  uint64_t budgetBytes = 512ull << 20;
  // Upload through a pixel buffer object. Where the GL's "GPU" memory is host memory (Mesa llvmpipe) this
  // only adds a copy of every brick, so the default is direct uploads; `--upload-pbo` turns it on.
  bool uploadThroughPbo = false;
  uint32_t extraBytesPerTexel = 0;  // planBrickPool's: textures beside the pool share the budget
  uint64_t maxSlots = UINT64_MAX;   // planBrickPool's: the bricks the volume has
};

class BrickPool {
 public:
  // Allocates the texture; throws ropecast::Error on a bad type, a budget too small for one slot or a GL
  // failure.
  BrickPool(const BrickPoolConfig& config, int max3DTextureSize);
  ~BrickPool();
  BrickPool(const BrickPool&) = delete;
  BrickPool& operator=(const BrickPool&) = delete;

  const BrickPoolGeometry& geometry() const { return geometry_; }
  uint32_t slotCount() const { return geometry_.slotCount(); }
  size_t slotBytes() const;
  SampleType storedType() const { return config_.storedType; }
  uint32_t texture() const { return texture_; }

  // Uploads one brick (storedBrickEdge()^3 samples, x fastest, border included) into a slot; throws
  // ropecast::Error for a slot out of range or a brick of another size.
  void upload(uint32_t slot, std::span<const std::byte> brick);
  // Uploads a frame's bricks (each as upload() checks them). Through a PBO, all of them are copied into one
  // buffer (orphaned, mapped once), then each slot is filled from its offset.
  void uploadBatch(std::span<const BrickPoolUpload> uploads);
  bool uploadsThroughPbo() const { return config_.uploadThroughPbo; }
  // Reads a slot back (tests, verification); slow, synchronous.
  std::vector<std::byte> readSlot(uint32_t slot) const;

 private:
  void checkSlot(uint32_t slot, const char* where) const;

  BrickPoolConfig config_;
  BrickPoolGeometry geometry_;
  uint32_t texture_ = 0;
  uint32_t pbo_ = 0;
};

}  // namespace ropecast
