#include "render/brick_pool.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <string>
#include <tuple>

#include <epoxy/gl.h>

#include "core/error.h"
#include "render/gl_context.h"
#include "store/octree_layout.h"

namespace ropecast {

namespace {

// What a linear texture layout pads each row to (llvmpipe: the CPU's cache line).
constexpr uint64_t kPoolRowAlignBytes = 64;

GLenum internalFormat(SampleType t) {
  return t == SampleType::UInt8 ? GL_R8 : GL_R16;
}
GLenum pixelType(SampleType t) {
  return t == SampleType::UInt8 ? GL_UNSIGNED_BYTE : GL_UNSIGNED_SHORT;
}

}  // namespace

BrickPoolGeometry planBrickPool(uint32_t brickSize, SampleType storedType, uint64_t budgetBytes,
                                int max3DTextureSize, uint32_t extraBytesPerTexel, uint64_t maxSlots) {
  if (storedType != SampleType::UInt8 && storedType != SampleType::UInt16)
    throw Error("planBrickPool: the pool holds uint8 or uint16 samples, got " +
                std::string(sampleTypeName(storedType)));
  BrickPoolGeometry g;
  g.slotEdge = brickSize + 2 * kBrickBorder;
  const uint64_t slotTexels = uint64_t(g.slotEdge) * g.slotEdge * g.slotEdge;
  const uint64_t slotBytes = slotTexels * (bytesPerSample(storedType) + extraBytesPerTexel);
  const uint64_t maxPerAxis = uint64_t(std::max(max3DTextureSize, 0)) / g.slotEdge;
  const uint64_t fitting =
      std::min({budgetBytes / slotBytes, maxPerAxis * maxPerAxis * maxPerAxis, kMaxPoolSlots});
  if (budgetBytes < slotBytes) {
    std::string problem = "--gpu-budget " + std::to_string(budgetBytes) + " bytes holds no brick slot of " +
                          std::to_string(slotBytes) + " bytes";
    if (extraBytesPerTexel > 0)
      problem += " (" + std::to_string(slotTexels * extraBytesPerTexel) +
                 " of them for stored DVR gradients; with --gradients computed a slot takes " +
                 std::to_string(slotTexels * bytesPerSample(storedType)) + ")";
    throw UsageError(problem);
  }
  if (fitting < 1)
    throw Error("planBrickPool: GL_MAX_3D_TEXTURE_SIZE " + std::to_string(max3DTextureSize) +
                " is below the slot edge of " + std::to_string(g.slotEdge) + " texels");
  // The slots stacked along y and z, across x as few as make a texture row a whole number of 64-byte lines:
  // a linear layout pads every row to one (llvmpipe pads to a cache line), and one slot across (36 texels of
  // a 32^3 brick, 1 or 2 bytes each) would take 64 or 128 bytes a row, 78 % more memory than the budget says.
  // A gradient texture of the same dimensions (8 bytes a texel) is then aligned too; tiled GPU layouts do not
  // care. A pool is allocated whole (and zeroed, which is slow where the GL's memory is host memory), so it
  // holds no more slots than the volume has bricks.
  const uint64_t wanted = std::max<uint64_t>(1, std::min(fitting, maxSlots));
  const auto side = [&](uint64_t n) { return std::clamp<uint64_t>(n, 1, maxPerAxis); };
  const auto ceilDiv = [](uint64_t a, uint64_t b) { return (a + b - 1) / b; };
  const uint64_t slotsPerLine =
      kPoolRowAlignBytes / std::gcd(uint64_t(g.slotEdge) * bytesPerSample(storedType), kPoolRowAlignBytes);
  uint64_t gx = ceilDiv(wanted, maxPerAxis * maxPerAxis);
  if (wanted >= slotsPerLine) gx = side(ceilDiv(gx, slotsPerLine) * slotsPerLine);
  // Rows of gx slots on a y-z grid: as many as hold `wanted` (at most as many as fit), then as few to spare,
  // then the squarest.
  const uint64_t rowsFitting = fitting / gx;
  const uint64_t rowsWanted = std::min(ceilDiv(wanted, gx), rowsFitting);
  const auto rank = [&](uint64_t y, uint64_t z) {
    return std::tuple(rowsWanted - std::min(y * z, rowsWanted), y * z, std::max(y, z));
  };
  uint64_t gy = 1, gz = 1;
  for (uint64_t y = 1; y <= std::min(maxPerAxis, rowsWanted); ++y) {
    const uint64_t z = std::min({ceilDiv(rowsWanted, y), rowsFitting / y, maxPerAxis});
    if (z >= 1 && rank(y, z) < rank(gy, gz)) {
      gy = y;
      gz = z;
    }
  }
  g.slotGrid = {uint32_t(gx), uint32_t(gy), uint32_t(gz)};
  g.textureDims = g.slotGrid * g.slotEdge;
  return g;
}

uint64_t defaultGpuBudgetBytes(const GlContextInfo& info) {
  // Half of what the driver reports, but no more than 4 GiB: the pool is allocated whole at start-up, and a
  // renderer that takes tens of GB of a large card by default surprises whoever shares it. --gpu-budget
  // overrides.
  constexpr uint64_t kDefaultCap = 4ull << 30;
  if (info.totalGpuMemoryBytes) return std::min(*info.totalGpuMemoryBytes / 2, kDefaultCap);
  return 512ull << 20;
}

BrickPool::BrickPool(const BrickPoolConfig& config, int max3DTextureSize)
    : config_(config),
      geometry_(planBrickPool(config.brickSize, config.storedType, config.budgetBytes, max3DTextureSize,
                              config.extraBytesPerTexel, config.maxSlots)) {
  while (glGetError() != GL_NO_ERROR) {
  }
  glCreateTextures(GL_TEXTURE_3D, 1, &texture_);
  glTextureStorage3D(texture_, 1, internalFormat(config_.storedType), GLsizei(geometry_.textureDims.x),
                     GLsizei(geometry_.textureDims.y), GLsizei(geometry_.textureDims.z));
  const GLenum e = glGetError();
  if (e != GL_NO_ERROR) {
    glDeleteTextures(1, &texture_);
    throw Error("BrickPool: allocating a " + std::to_string(geometry_.textureDims.x) + "x" +
                std::to_string(geometry_.textureDims.y) + "x" + std::to_string(geometry_.textureDims.z) +
                " 3D texture failed (GL error " + std::to_string(e) + "); lower --gpu-budget");
  }
  glTextureParameteri(texture_, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(texture_, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(texture_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(texture_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTextureParameteri(texture_, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
  if (config_.uploadThroughPbo) glCreateBuffers(1, &pbo_);
}

BrickPool::~BrickPool() {
  if (pbo_) glDeleteBuffers(1, &pbo_);
  if (texture_) glDeleteTextures(1, &texture_);
}

size_t BrickPool::slotBytes() const {
  const size_t e = geometry_.slotEdge;
  return e * e * e * bytesPerSample(config_.storedType);
}

void BrickPool::checkSlot(uint32_t slot, const char* where) const {
  if (slot >= slotCount())
    throw Error(std::string(where) + ": slot " + std::to_string(slot) + " out of range (pool has " +
                std::to_string(slotCount()) + " slots)");
}

void BrickPool::upload(uint32_t slot, std::span<const std::byte> brick) {
  checkSlot(slot, "BrickPool::upload");
  if (brick.size() != slotBytes())
    throw Error("BrickPool::upload: brick of " + std::to_string(brick.size()) + " bytes, expected " +
                std::to_string(slotBytes()));
  const glm::u32vec3 o = geometry_.slotOrigin(slot);
  const GLsizei e = GLsizei(geometry_.slotEdge);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  if (pbo_) {
    // Orphan, fill and upload from the buffer, so the driver may copy asynchronously.
    glNamedBufferData(pbo_, GLsizeiptr(brick.size()), brick.data(), GL_STREAM_DRAW);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, pbo_);
    glTextureSubImage3D(texture_, 0, GLint(o.x), GLint(o.y), GLint(o.z), e, e, e, GL_RED,
                        pixelType(config_.storedType), nullptr);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
  } else {
    glTextureSubImage3D(texture_, 0, GLint(o.x), GLint(o.y), GLint(o.z), e, e, e, GL_RED,
                        pixelType(config_.storedType), brick.data());
  }
}

void BrickPool::uploadBatch(std::span<const BrickPoolUpload> uploads) {
  if (uploads.empty()) return;
  if (!pbo_) {
    for (const BrickPoolUpload& u : uploads) upload(u.slot, u.brick);
    return;
  }
  for (const BrickPoolUpload& u : uploads) {
    checkSlot(u.slot, "BrickPool::uploadBatch");
    if (u.brick.size() != slotBytes())
      throw Error("BrickPool::uploadBatch: brick of " + std::to_string(u.brick.size()) + " bytes, expected " +
                  std::to_string(slotBytes()));
  }
  const size_t total = uploads.size() * slotBytes();
  // Orphan the buffer's previous storage (the GL may still read it), then fill the new one.
  glNamedBufferData(pbo_, GLsizeiptr(total), nullptr, GL_STREAM_DRAW);
  auto* mapped = static_cast<std::byte*>(
      glMapNamedBufferRange(pbo_, 0, GLsizeiptr(total), GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_BUFFER_BIT));
  if (!mapped)
    throw Error("BrickPool::uploadBatch: mapping the pixel buffer of " + std::to_string(total) +
                " bytes failed");
  for (size_t i = 0; i < uploads.size(); ++i)
    std::memcpy(mapped + i * slotBytes(), uploads[i].brick.data(), slotBytes());
  glUnmapNamedBuffer(pbo_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, pbo_);
  const GLsizei e = GLsizei(geometry_.slotEdge);
  for (size_t i = 0; i < uploads.size(); ++i) {
    const glm::u32vec3 o = geometry_.slotOrigin(uploads[i].slot);
    glTextureSubImage3D(texture_, 0, GLint(o.x), GLint(o.y), GLint(o.z), e, e, e, GL_RED,
                        pixelType(config_.storedType), reinterpret_cast<const void*>(i * slotBytes()));
  }
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
}

std::vector<std::byte> BrickPool::readSlot(uint32_t slot) const {
  checkSlot(slot, "BrickPool::readSlot");
  std::vector<std::byte> out(slotBytes());
  const glm::u32vec3 o = geometry_.slotOrigin(slot);
  const GLsizei e = GLsizei(geometry_.slotEdge);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureSubImage(texture_, 0, GLint(o.x), GLint(o.y), GLint(o.z), e, e, e, GL_RED,
                       pixelType(config_.storedType), GLsizei(out.size()), out.data());
  checkGlError("BrickPool::readSlot");
  return out;
}

}  // namespace ropecast
