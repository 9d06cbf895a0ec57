// The GPU brick pool: slot planning within budget and texture limits, allocation, upload and readback.
#include <cstdint>
#include <cstring>
#include <fstream>
#include <numeric>
#include <set>
#include <vector>

#include <epoxy/gl.h>
#include <gtest/gtest.h>
#include <glm/vector_relational.hpp>

#include "core/error.h"
#include "render/brick_pool.h"
#include "render/gl_context.h"
#include "render/shader_program.h"
#include "tests/render/testutil_gl.h"

namespace ropecast {
namespace {

TEST(BrickPoolPlan, StaysWithinBudgetAndTextureLimit) {
  const BrickPoolGeometry g = planBrickPool(32, SampleType::UInt16, 64ull << 20, 2048);
  EXPECT_EQ(g.slotEdge, 36u);
  const uint64_t slotBytes = 36ull * 36 * 36 * 2;
  EXPECT_LE(uint64_t(g.slotCount()) * slotBytes, 64ull << 20);
  EXPECT_GE(uint64_t(g.slotCount()) * slotBytes, (64ull << 20) / 2);  // not wasteful
  EXPECT_EQ(g.textureDims, g.slotGrid * 36u);
  EXPECT_EQ(g.slotGrid.x * 36u * 2u % 64u, 0u);  // texture rows need no padding in a linear layout
  EXPECT_EQ(g.slotGrid.x, 8u);                   // and are no wider than that takes
  // A texture limit smaller than the budget's cube caps the grid.
  const BrickPoolGeometry capped = planBrickPool(16, SampleType::UInt8, 1ull << 30, 100);
  EXPECT_EQ(capped.slotGrid, glm::u32vec3(5));
  EXPECT_THROW(planBrickPool(32, SampleType::UInt8, 1000, 2048), Error);
  EXPECT_THROW(planBrickPool(32, SampleType::Float32, 1 << 20, 2048), Error);
}

// Where rows are padded to 64 bytes (llvmpipe), the texture still takes no more memory than the budget.
TEST(BrickPoolPlan, RowsPaddedTo64BytesStayWithinBudget) {
  for (const SampleType type : {SampleType::UInt8, SampleType::UInt16}) {
    for (const uint32_t brickSize : {16u, 32u, 64u}) {
      for (const uint64_t budget : {8ull << 20, 256ull << 20, 1ull << 30}) {
        const BrickPoolGeometry g = planBrickPool(brickSize, type, budget, 2048);
        const uint64_t rowBytes = uint64_t(g.textureDims.x) * bytesPerSample(type);
        const uint64_t paddedBytes = (rowBytes + 63) / 64 * 64 * g.textureDims.y * g.textureDims.z;
        EXPECT_LE(paddedBytes, budget) << sampleTypeName(type) << " " << brickSize << " " << budget;
      }
    }
  }
}

TEST(BrickPoolPlan, HoldsNoMoreSlotsThanTheVolumeHasBricks) {
  const uint64_t slotBytes = 36ull * 36 * 36;
  const uint64_t budget = 512ull << 20;
  for (uint64_t bricks : {1ull, 2ull, 35ull, 37ull, 585ull, 1000ull}) {
    const BrickPoolGeometry g = planBrickPool(32, SampleType::UInt8, budget, 2048, 0, bricks);
    EXPECT_GE(g.slotCount(), bricks) << bricks << " bricks";
    // The rounding: a partly filled row of slots across x, the y and z sides.
    EXPECT_LE(g.slotCount(), bricks + bricks / 4 + g.slotGrid.x) << bricks << " bricks";
    EXPECT_EQ(g.slotGrid.x, bricks >= 16 ? 16u : 1u) << bricks << " bricks";  // 36 one-byte texels a slot
  }
  // The budget still rules when it holds fewer slots than the volume has bricks.
  const BrickPoolGeometry tight = planBrickPool(32, SampleType::UInt8, 100 * slotBytes, 2048, 0, 1000);
  EXPECT_LE(tight.slotCount(), 100u);
  EXPECT_GE(tight.slotCount(), 50u);
  EXPECT_EQ(planBrickPool(32, SampleType::UInt8, budget, 2048, 0, UINT64_MAX).slotGrid,
            planBrickPool(32, SampleType::UInt8, budget, 2048).slotGrid);
}

TEST(BrickPoolPlan, HoldsAtMostTheSlotsTheShaderAddressesExactly) {
  // 4^3 bricks (8^3 slots) in a terabyte and a 16384 texture limit would be 2^33 slots.
  const BrickPoolGeometry g = planBrickPool(4, SampleType::UInt8, 1ull << 40, 16384);
  EXPECT_LE(g.slotCount(), kMaxPoolSlots);
  EXPECT_GE(g.slotCount(), kMaxPoolSlots / 2);
}

// The shader's poolSlotOrigin (shaders/brick_pool.glsl, in float) against BrickPoolGeometry::slotOrigin for
// every slot of grids with up to kMaxPoolSlots slots.
TEST(BrickPoolShader, SlotOriginMatchesTheCppTwinUpToTheSlotLimit) {
  test::sharedGlContext();
  const auto dir = test::freshTempDir();
  const auto shader = dir / "slot_origin.comp";
  std::ofstream(shader)
      << "#version 450 core\nlayout(local_size_x = 64) in;\n"
         "#include \"shaders/brick_pool.glsl\"\n"
         "uniform uvec3 uPoolSlotGrid;\n"
         "uniform float uPoolSlotEdge;\n"
         "layout(std430, binding = 0) buffer Origins { uvec4 origins[]; };\n"
         "void main() {\n"
         "  uint slot = gl_GlobalInvocationID.x;\n"
         "  origins[slot] = uvec4(uvec3(poolSlotOrigin(slot, uPoolSlotGrid, uPoolSlotEdge)), 0u);\n"
         "}\n";
  ShaderProgram program({{ShaderStage::Compute, shader.string()}});
  const glm::u32vec3 grids[] = {{1, 1448, 1448}, {3, 697, 1002}, {7, 5, 3}};
  for (const glm::u32vec3& grid : grids) {
    BrickPoolGeometry g;
    g.slotEdge = 36;
    g.slotGrid = grid;
    ASSERT_LE(g.slotCount(), kMaxPoolSlots);
    const uint32_t groups = (g.slotCount() + 63) / 64;
    GLuint ssbo = 0;
    glCreateBuffers(1, &ssbo);
    glNamedBufferStorage(ssbo, GLsizeiptr(groups) * 64 * 16, nullptr, 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, ssbo);
    program.use();
    glUniform3ui(program.uniform("uPoolSlotGrid"), grid.x, grid.y, grid.z);
    glUniform1f(program.uniform("uPoolSlotEdge"), float(g.slotEdge));
    glDispatchCompute(groups, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<glm::u32vec4> origins(size_t(groups) * 64);
    glGetNamedBufferSubData(ssbo, 0, GLsizeiptr(origins.size() * sizeof(origins[0])), origins.data());
    glDeleteBuffers(1, &ssbo);
    uint32_t mismatches = 0;
    for (uint32_t s = 0; s < g.slotCount(); ++s)
      if (glm::u32vec3(origins[s]) != g.slotOrigin(s) && ++mismatches <= 3)
        ADD_FAILURE() << "slot " << s << " of grid " << grid.x << "x" << grid.y << "x" << grid.z;
    EXPECT_EQ(mismatches, 0u);
  }
  checkGlError("poolSlotOrigin test");
}

TEST(BrickPoolPlan, SlotOriginsAreDistinctAndInside) {
  const BrickPoolGeometry g = planBrickPool(8, SampleType::UInt8, 100 * 12 * 12 * 12, 1024);
  std::set<std::tuple<uint32_t, uint32_t, uint32_t>> seen;
  for (uint32_t s = 0; s < g.slotCount(); ++s) {
    const glm::u32vec3 o = g.slotOrigin(s);
    EXPECT_TRUE(glm::all(glm::lessThanEqual(o + g.slotEdge, g.textureDims)));
    EXPECT_EQ(o.x % g.slotEdge, 0u);
    seen.insert({o.x, o.y, o.z});
  }
  EXPECT_EQ(seen.size(), g.slotCount());
}

template <typename T>
std::vector<std::byte> patternBrick(uint32_t edge, uint32_t seed) {
  std::vector<T> v(size_t(edge) * edge * edge);
  for (size_t i = 0; i < v.size(); ++i)
    v[i] = T((i * 7919u + seed * 104729u) % (sizeof(T) == 1 ? 256u : 65536u));
  std::vector<std::byte> bytes(v.size() * sizeof(T));
  std::memcpy(bytes.data(), v.data(), bytes.size());
  return bytes;
}

void roundTrip(SampleType type, bool pbo) {
  test::sharedGlContext();
  const uint32_t edge = 8 + 2 * 2;
  BrickPoolConfig config{8, type, uint64_t(10) * edge * edge * edge * bytesPerSample(type), pbo};
  BrickPool pool(config, test::sharedGlContext().info().max3DTextureSize);
  ASSERT_GE(pool.slotCount(), 8u);
  ASSERT_LE(pool.slotCount(), 10u);
  std::vector<uint32_t> slots(pool.slotCount());
  std::iota(slots.begin(), slots.end(), 0u);
  for (uint32_t s : slots)
    pool.upload(s,
                type == SampleType::UInt8 ? patternBrick<uint8_t>(edge, s) : patternBrick<uint16_t>(edge, s));
  for (uint32_t s : slots)
    EXPECT_EQ(pool.readSlot(s),
              type == SampleType::UInt8 ? patternBrick<uint8_t>(edge, s) : patternBrick<uint16_t>(edge, s))
        << "slot " << s;
  EXPECT_THROW(pool.upload(pool.slotCount(), patternBrick<uint8_t>(edge, 0)), Error);
  EXPECT_THROW(pool.readSlot(pool.slotCount()), Error);
  EXPECT_THROW(pool.upload(slots[3], std::vector<std::byte>(5)), Error);
  checkGlError("BrickPool test");
}

TEST(BrickPool, RoundTripUInt8) {
  roundTrip(SampleType::UInt8, false);
}
TEST(BrickPool, RoundTripUInt16ThroughPbo) {
  roundTrip(SampleType::UInt16, true);
}

TEST(BrickPool, DefaultBudget) {
  GlContextInfo info;
  EXPECT_EQ(defaultGpuBudgetBytes(info), 512ull << 20);
  info.totalGpuMemoryBytes = 4ull << 30;
  EXPECT_EQ(defaultGpuBudgetBytes(info), 2ull << 30);  // half of what the driver reports
  info.totalGpuMemoryBytes = 80ull << 30;
  EXPECT_EQ(defaultGpuBudgetBytes(info), 4ull << 30);  // capped: the pool is allocated whole
}

}  // namespace
}  // namespace ropecast
