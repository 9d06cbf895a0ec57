// The GLSL traversal (shaders/rope_traversal.glsl) run for real, in a compute shader, against the CPU
// reference (index/rope_traversal.h): same index, same rays, same leaves in the same order. Runs on any
// GL 4.5 (llvmpipe without a GPU).
//
// Leaves must match exactly. The t's are compared bit for bit where the GPU's 1/dir is correctly rounded
// (llvmpipe) and within a relative 1e-5 otherwise (GLSL allows an approximate reciprocal): the count of
// bit-identical t's is printed. Rays are generic (random origins and targets, and axis-parallel rays whose
// zero components are exactly 0 on both sides); rays exactly through edges are left to the CPU property test,
// since with a reciprocal one ulp apart a corner crossing may legitimately become a leaf a few ulps long.
#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <random>
#include <vector>

#include "index/random_cut.h"
#include "index/rope_index.h"
#include "index/rope_traversal.h"
#include "render/gl_context.h"
#include "render/index_texture.h"
#include "render/shader_program.h"

namespace ropecast {
namespace {

constexpr uint32_t kMaxHits = 256;

struct GpuHit {
  uint32_t leafIndex, tEnterBits, tExitBits, depthKind;
};

class Buffer {
 public:
  Buffer(const void* data, size_t bytes) {
    glCreateBuffers(1, &id_);
    glNamedBufferData(id_, GLsizeiptr(bytes), data, GL_DYNAMIC_READ);
  }
  ~Buffer() { glDeleteBuffers(1, &id_); }
  GLuint id() const { return id_; }

 private:
  GLuint id_ = 0;
};

struct Ray {
  glm::vec3 origin, dir;
  float tStart, tEnd;
};

std::vector<Ray> makeRays(uint64_t seed, int count) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Ray> rays;
  for (int i = 0; i < count; ++i) {
    const glm::vec3 target(u(rng), u(rng), u(rng));
    glm::vec3 origin = glm::vec3(u(rng), u(rng), u(rng)) * 3.0f - 1.0f;
    if (i % 4 == 1) origin = glm::vec3(u(rng), u(rng), u(rng));  // starts inside
    glm::vec3 dir = target - origin;
    if (i % 4 == 2) {  // axis-parallel: one or two components exactly 0
      dir[i % 3] = 0.0f;
      if (i % 8 == 2) dir[(i + 1) % 3] = 0.0f;
      if (dir == glm::vec3(0.0f)) dir.z = 1.0f;
    }
    const float tEnd = i % 4 == 3 ? 0.5f + u(rng) : 1e30f;  // some end inside the cube
    rays.push_back({origin, dir, i % 4 == 1 ? 0.0f : -1e30f, tEnd});
  }
  return rays;
}

class RopeTraversalGl : public testing::Test {
 protected:
  static void SetUpTestSuite() { context_ = new GlContext(); }
  static void TearDownTestSuite() {
    delete context_;
    context_ = nullptr;
  }
  static GlContext* context_;
};
GlContext* RopeTraversalGl::context_ = nullptr;

TEST_F(RopeTraversalGl, ComputeShaderMatchesCpuReference) {
  std::printf("GL: %s | %s\n", context_->info().renderer.c_str(), context_->info().version.c_str());
  // The test shader is not embedded: read from the source tree, or from ROPECAST_SHADER_DIR's folders (a
  // copy of the tree on another machine, where this build's source path does not exist).
  const char* shaderDir = std::getenv("ROPECAST_SHADER_DIR");
  const std::string walk = "tests/index/rope_walk_test.comp";
  ShaderProgram program({{ShaderStage::Compute,
                          shaderDir && *shaderDir ? walk : std::string(ROPECAST_SOURCE_DIR) + "/" + walk}});
  size_t leavesCompared = 0, tCompared = 0, tBitIdentical = 0;

  for (uint64_t seed = 1; seed <= 6; ++seed) {
    RandomCutParams params;
    params.seed = seed;
    params.targetLeaves = seed <= 3 ? 300 : 3000;
    params.maxDepth = 3 + uint32_t(seed);
    const Cut cut = makeRandomCut(params);
    const RopeIndex index = buildRopeIndex(cut);
    const std::vector<Ray> rays = makeRays(seed, 4096);
    SCOPED_TRACE(testing::Message() << "cut seed " << seed << ", " << cut.leaves.size() << " leaves");

    IndexTexture texture(kRopeTexelComponents, context_->info().maxTextureBufferTexels);
    texture.upload({reinterpret_cast<const uint32_t*>(index.texels.data()), index.texels.size() * 4});
    std::vector<glm::vec4> packed;
    for (const Ray& r : rays) {
      packed.emplace_back(r.origin, r.tStart);
      packed.emplace_back(r.dir, r.tEnd);
    }
    Buffer rayBuffer(packed.data(), packed.size() * sizeof(glm::vec4));
    std::vector<GpuHit> hits(rays.size() * kMaxHits);
    Buffer hitBuffer(hits.data(), hits.size() * sizeof(GpuHit));
    std::vector<uint32_t> counts(rays.size());
    Buffer countBuffer(counts.data(), counts.size() * sizeof(uint32_t));

    program.use();
    texture.bind(0);
    glUniform1i(program.uniform("uRopeIndex"), 0);
    glUniform1ui(program.uniform("uRayCount"), GLuint(rays.size()));
    glUniform1ui(program.uniform("uMaxHits"), kMaxHits);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, rayBuffer.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, hitBuffer.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, countBuffer.id());
    glDispatchCompute(GLuint((rays.size() + 63) / 64), 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(hitBuffer.id(), 0, GLsizeiptr(hits.size() * sizeof(GpuHit)), hits.data());
    glGetNamedBufferSubData(countBuffer.id(), 0, GLsizeiptr(counts.size() * sizeof(uint32_t)), counts.data());
    checkGlError("RopeTraversalGl");

    for (size_t r = 0; r < rays.size(); ++r) {
      std::vector<RopeLeaf> cpu;
      RopeCursor cursor;
      RopeLeaf leaf;
      if (ropeBegin(cursor, index, rays[r].origin, rays[r].dir, rays[r].tStart, rays[r].tEnd))
        while (ropeNextLeaf(cursor, index, leaf)) cpu.push_back(leaf);
      ASSERT_LE(cpu.size(), kMaxHits);
      ASSERT_EQ(counts[r], cpu.size()) << "ray " << r;
      for (size_t i = 0; i < cpu.size(); ++i) {
        const GpuHit& g = hits[r * kMaxHits + i];
        float tEnter, tExit;
        std::memcpy(&tEnter, &g.tEnterBits, 4);
        std::memcpy(&tExit, &g.tExitBits, 4);
        ASSERT_EQ(g.leafIndex, cpu[i].leafIndex) << "ray " << r << " step " << i;
        ASSERT_EQ(g.depthKind, (cpu[i].depth << 8) | cpu[i].kind) << "ray " << r << " step " << i;
        for (auto [gpuT, cpuT] : {std::pair{tEnter, cpu[i].tEnter}, std::pair{tExit, cpu[i].tExit}}) {
          if (std::abs(cpuT) >= 1e29f) continue;  // tStart/tEnd passed through
          ASSERT_NEAR(gpuT, cpuT, 1e-5f * (1.0f + std::abs(cpuT))) << "ray " << r << " step " << i;
          ++tCompared;
          tBitIdentical += gpuT == cpuT;
        }
      }
      leavesCompared += cpu.size();
    }
  }
  std::printf("compared %zu leaves; %zu of %zu t values bit-identical to the CPU reference\n", leavesCompared,
              tBitIdentical, tCompared);
  EXPECT_GT(leavesCompared, 50000u);
}

}  // namespace
}  // namespace ropecast
