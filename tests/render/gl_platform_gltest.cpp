// GL platform pieces: the headless context, the GPU timer and the index buffer texture.
#include <chrono>
#include <cstdint>
#include <vector>

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include "core/error.h"
#include "render/gpu_timer.h"
#include "render/index_texture.h"
#include "tests/render/testutil_gl.h"

namespace ropecast {
namespace {

TEST(GlContext, CreatesHeadless45CoreContext) {
  GlContext& ctx = test::sharedGlContext();
  EXPECT_GE(epoxy_gl_version(), 45);
  GLint mask = 0;
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &mask);
  EXPECT_TRUE(mask & GL_CONTEXT_CORE_PROFILE_BIT);
  EXPECT_FALSE(ctx.info().renderer.empty());
  EXPECT_TRUE(ctx.info().platform == "device" || ctx.info().platform == "surfaceless");
  EXPECT_GE(ctx.info().max3DTextureSize, 256);
  EXPECT_GT(ctx.info().maxTextureBufferTexels, 0);
  if (ctx.info().totalGpuMemoryBytes) {
    EXPECT_GT(*ctx.info().totalGpuMemoryBytes, 0u);
  }
  std::printf("renderer: %s (%s platform), GL %s\n", ctx.info().renderer.c_str(), ctx.info().platform.c_str(),
              ctx.info().version.c_str());
  EXPECT_NO_THROW(checkGlError("after context creation"));
}

TEST(GlContext, CheckGlErrorNamesTheCaller) {
  test::sharedGlContext();
  glBindTexture(GL_TEXTURE_2D, 0xdeadbeef);  // not a texture name: GL_INVALID_OPERATION
  try {
    checkGlError("MyPass::run");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("MyPass::run: GL error 0x0502"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(checkGlError("cleared"));
}

TEST(GpuTimer, MeasuresNonNegativeTime) {
  test::sharedGlContext();
  GpuTimer timer;
  EXPECT_THROW(timer.elapsedMs(), Error);
  GLuint buffer = 0;
  glCreateBuffers(1, &buffer);
  glNamedBufferStorage(buffer, 1 << 20, nullptr, 0);
  const auto wallBegin = std::chrono::steady_clock::now();
  timer.begin();
  glClearNamedBufferData(buffer, GL_R8, GL_RED, GL_UNSIGNED_BYTE, nullptr);
  timer.end();
  const double elapsed = timer.elapsedMs();
  const double wallMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wallBegin).count();
  glDeleteBuffers(1, &buffer);
  EXPECT_GE(elapsed, 0.0);
  EXPECT_LE(elapsed, wallMs);  // elapsedMs() waits for the GPU, so the span fits in the wall time around it
  EXPECT_EQ(timer.elapsedMs(), elapsed);
  EXPECT_THROW(timer.end(), Error);
}

// Reads texel i of a buffer texture through a compute shader, to check what the shader actually sees.
std::vector<uint32_t> readThroughShader(const IndexTexture& index, uint32_t texels) {
  const char* src = R"(#version 450 core
layout(local_size_x = 1) in;
uniform usamplerBuffer uTex;
layout(std430, binding = 0) buffer Out { uvec4 outTexels[]; };
void main() { outTexels[gl_GlobalInvocationID.x] = texelFetch(uTex, int(gl_GlobalInvocationID.x)); }
)";
  const GLuint shader = glCreateShader(GL_COMPUTE_SHADER);
  glShaderSource(shader, 1, &src, nullptr);
  glCompileShader(shader);
  const GLuint program = glCreateProgram();
  glAttachShader(program, shader);
  glLinkProgram(program);
  glDeleteShader(shader);
  GLuint ssbo = 0;
  glCreateBuffers(1, &ssbo);
  glNamedBufferStorage(ssbo, texels * 16, nullptr, GL_DYNAMIC_STORAGE_BIT);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, ssbo);
  index.bind(3);
  glUseProgram(program);
  glUniform1i(glGetUniformLocation(program, "uTex"), 3);
  glDispatchCompute(texels, 1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  std::vector<uint32_t> out(texels * 4);
  glGetNamedBufferSubData(ssbo, 0, GLsizeiptr(out.size() * 4), out.data());
  glDeleteBuffers(1, &ssbo);
  glDeleteProgram(program);
  return out;
}

TEST(IndexTexture, UploadsAndGrows) {
  GlContext& ctx = test::sharedGlContext();
  IndexTexture index(4, ctx.info().maxTextureBufferTexels);
  std::vector<uint32_t> words(4 * 5);
  for (size_t i = 0; i < words.size(); ++i) words[i] = uint32_t(i * 2654435761u);
  index.upload(words);
  EXPECT_EQ(index.texelCount(), 5u);
  EXPECT_EQ(readThroughShader(index, 5), words);

  std::vector<uint32_t> bigger(4 * 3000);  // beyond the first 4 KiB capacity
  for (size_t i = 0; i < bigger.size(); ++i) bigger[i] = uint32_t(i ^ 0x5a5a5a5au);
  index.upload(bigger);
  EXPECT_GE(index.capacityBytes(), bigger.size() * 4);
  EXPECT_EQ(readThroughShader(index, 3000), bigger);
  checkGlError("IndexTexture test");
}

TEST(IndexTexture, TwoComponentTexels) {
  GlContext& ctx = test::sharedGlContext();
  IndexTexture index(2, ctx.info().maxTextureBufferTexels);
  const std::vector<uint32_t> words = {1, 2, 3, 4, 5, 6};
  index.upload(words);
  const std::vector<uint32_t> seen = readThroughShader(index, 3);
  for (uint32_t t = 0; t < 3; ++t) {
    EXPECT_EQ(seen[t * 4 + 0], words[t * 2 + 0]);
    EXPECT_EQ(seen[t * 4 + 1], words[t * 2 + 1]);
  }
  EXPECT_THROW(index.upload(std::vector<uint32_t>{1, 2, 3}), Error);
  EXPECT_THROW(IndexTexture(3, 1000), Error);
}

}  // namespace
}  // namespace ropecast
