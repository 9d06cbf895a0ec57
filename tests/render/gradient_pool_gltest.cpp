// The DVR sample texture: texels derived from the value pool are (central differences, value), neighbours
// clamped to the region; the budget pays for it; bad regions are refused.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include "core/error.h"
#include "render/brick_pool.h"
#include "render/gradient_pool.h"
#include "tests/render/testutil_gl.h"

namespace ropecast {
namespace {

// A brick of distinct, non-linear values (x fastest).
std::vector<std::byte> patternBrick(uint32_t edge, SampleType type) {
  std::vector<std::byte> bytes(size_t(edge) * edge * edge * bytesPerSample(type));
  for (uint32_t i = 0; i < edge * edge * edge; ++i) {
    const uint32_t x = i % edge, y = (i / edge) % edge, z = i / (edge * edge);
    const uint32_t v = (x * x * 7 + y * 13 + z * z * z * 3 + x * y) % 251;
    if (type == SampleType::UInt8) {
      bytes[i] = std::byte(v);
    } else {
      const uint16_t w = uint16_t(v * 257 + x);
      std::memcpy(&bytes[2 * i], &w, 2);
    }
  }
  return bytes;
}

void expectDerivedFromSlot(SampleType type) {
  const uint32_t brick = 8, edge = brick + 2 * 2;
  BrickPoolConfig config{brick, type, 8ull * edge * edge * edge * 2, false};
  BrickPool pool(config, test::sharedGlContext().info().max3DTextureSize);
  ASSERT_GE(pool.slotCount(), 3u);
  const uint32_t slot = 2;  // not at the texture's origin
  const std::vector<std::byte> bytes = patternBrick(edge, type);
  pool.upload(slot, bytes);

  GradientPool gradients(pool.geometry().textureDims);
  const glm::u32vec3 origin = pool.geometry().slotOrigin(slot);
  gradients.derive(pool.texture(), std::span(&origin, 1), glm::u32vec3(edge));

  std::vector<float> texels(size_t(edge) * edge * edge * 4);
  glGetTextureSubImage(gradients.texture(), 0, GLint(origin.x), GLint(origin.y), GLint(origin.z),
                       GLsizei(edge), GLsizei(edge), GLsizei(edge), GL_RGBA, GL_FLOAT,
                       GLsizei(texels.size() * sizeof(float)), texels.data());
  const double storedMax = type == SampleType::UInt8 ? 255.0 : 65535.0;
  const auto value = [&](int x, int y, int z) {
    const auto c = [&](int v) { return uint32_t(std::clamp(v, 0, int(edge) - 1)); };
    const size_t i = c(x) + edge * (c(y) + size_t(edge) * c(z));
    if (type == SampleType::UInt8) return double(uint8_t(bytes[i])) / storedMax;
    uint16_t w;
    std::memcpy(&w, &bytes[2 * i], 2);
    return double(w) / storedMax;
  };
  // SNORM16 rounding; a GPU may store the code on the other side of a tie.
  const double tolerance = (test::onHardwareGpu() ? 1.5 : 1.0) / 32767.0;
  double largest = 0.0;
  for (int z = 0; z < int(edge); ++z)
    for (int y = 0; y < int(edge); ++y)
      for (int x = 0; x < int(edge); ++x) {
        const float* t = &texels[4 * (x + edge * (y + size_t(edge) * z))];
        const double want[4] = {value(x + 1, y, z) - value(x - 1, y, z),
                                value(x, y + 1, z) - value(x, y - 1, z),
                                value(x, y, z + 1) - value(x, y, z - 1), value(x, y, z)};
        for (int c = 0; c < 4; ++c) {
          ASSERT_NEAR(t[c], want[c], tolerance) << "texel " << x << "," << y << "," << z << " channel " << c;
          largest = std::max(largest, std::abs(want[c]));
        }
      }
  EXPECT_GT(largest, 0.5);  // the pattern exercised the range
}

TEST(GradientPool, TexelsAreCentralDifferencesAndValueOfTheSlotUInt8) {
  expectDerivedFromSlot(SampleType::UInt8);
}

TEST(GradientPool, TexelsAreCentralDifferencesAndValueOfTheSlotUInt16) {
  expectDerivedFromSlot(SampleType::UInt16);
}

TEST(GradientPool, RefusesARegionBeyondTheTexture) {
  test::sharedGlContext();
  GradientPool gradients(glm::u32vec3(16, 16, 8));
  const glm::u32vec3 origin(8, 0, 0);
  GLuint values = 0;
  glCreateTextures(GL_TEXTURE_3D, 1, &values);
  glTextureStorage3D(values, 1, GL_R8, 16, 16, 8);
  EXPECT_THROW(gradients.derive(values, std::span(&origin, 1), glm::u32vec3(12, 4, 4)), Error);
  EXPECT_NO_THROW(gradients.derive(values, std::span(&origin, 1), glm::u32vec3(8, 4, 4)));
  glDeleteTextures(1, &values);
}

TEST(GradientPool, TheBrickPoolBudgetPaysForIt) {
  const uint32_t edge = 36;
  const uint64_t budget = 64ull << 20;
  const BrickPoolGeometry alone = planBrickPool(32, SampleType::UInt8, budget, 2048);
  const BrickPoolGeometry beside =
      planBrickPool(32, SampleType::UInt8, budget, 2048, GradientPool::kBytesPerTexel);
  const uint64_t slotTexels = uint64_t(edge) * edge * edge;
  EXPECT_LE(beside.slotCount() * slotTexels * (1 + GradientPool::kBytesPerTexel), budget);
  EXPECT_GE(beside.slotCount() * slotTexels * (1 + GradientPool::kBytesPerTexel), budget / 2);
  EXPECT_LT(beside.slotCount(), alone.slotCount() / 4);
}

}  // namespace
}  // namespace ropecast
