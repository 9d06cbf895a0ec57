// The shader loader: #include resolution, #line framing, defines after #version, and compile errors pointing
// at the real file and line.
#include <cstdlib>
#include <fstream>
#include <optional>
#include <string>

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include "core/error.h"
#include "render/shader_program.h"
#include "tests/render/testutil_gl.h"

namespace ropecast {
namespace {

namespace fs = std::filesystem;

using test::writeText;

// Points ROPECAST_SHADER_DIR at a folder for the lifetime of the object.
class ShaderDirOverride {
 public:
  explicit ShaderDirOverride(const fs::path& dir) {
    if (const char* old = std::getenv("ROPECAST_SHADER_DIR")) old_ = old;
    setenv("ROPECAST_SHADER_DIR", dir.c_str(), 1);
  }
  ~ShaderDirOverride() {
    if (old_)
      setenv("ROPECAST_SHADER_DIR", old_->c_str(), 1);
    else
      unsetenv("ROPECAST_SHADER_DIR");
  }

 private:
  std::optional<std::string> old_;
};

TEST(ShaderProgram, BrokenIncludeReportsRealFileAndLine) {
  test::sharedGlContext();
  const fs::path dir = test::freshTempDir();
  writeText(dir / "ok.glsl", "float ok() { return 1.0; }\n");
  writeText(dir / "broken.glsl", "// line 1\n// line 2\nfloat broken() {\n  return undefinedThing;\n}\n");
  writeText(
      dir / "main.comp",
      "#version 450 core\nlayout(local_size_x = 1) in;\n#include \"ok.glsl\"\n#include \"broken.glsl\"\n"
      "void main() { float x = ok() + broken(); }\n");
  ShaderDirOverride env(dir);
  try {
    ShaderProgram program({{ShaderStage::Compute, "main.comp"}}, {"SOMETHING 1"});
    FAIL() << "a broken include must not compile";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("main.comp"), std::string::npos) << msg;
    // Mesa "broken.glsl:4(10)", NVIDIA "broken.glsl:4 :": the file name and line 4 either way.
    EXPECT_NE(msg.find("broken.glsl:4"), std::string::npos) << msg;
  }
  while (glGetError() != GL_NO_ERROR) {
  }
}

TEST(ShaderProgram, CompilesWithDefinesAndFindsUniforms) {
  test::sharedGlContext();
  const fs::path dir = test::freshTempDir();
  writeText(dir / "main.comp",
            "#version 450 core\nlayout(local_size_x = 1) in;\nuniform float uScale;\n"
            "layout(std430, binding = 0) buffer Out { float v; };\n"
            "void main() {\n#ifdef DOUBLE_IT\n  v = 2.0 * uScale;\n#else\n  v = uScale;\n#endif\n}\n");
  ShaderDirOverride env(dir);
  for (const bool twice : {false, true}) {
    ShaderProgram program({{ShaderStage::Compute, "main.comp"}},
                          twice ? std::vector<std::string>{"DOUBLE_IT"} : std::vector<std::string>{});
    ASSERT_GE(program.uniform("uScale"), 0);
    EXPECT_EQ(program.uniform("uAbsent"), -1);
    GLuint ssbo = 0;
    glCreateBuffers(1, &ssbo);
    glNamedBufferStorage(ssbo, 4, nullptr, GL_DYNAMIC_STORAGE_BIT);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, ssbo);
    program.use();
    glUniform1f(program.uniform("uScale"), 3.0f);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    float v = 0.0f;
    glGetNamedBufferSubData(ssbo, 0, 4, &v);
    glDeleteBuffers(1, &ssbo);
    EXPECT_EQ(v, twice ? 6.0f : 3.0f);
  }
  checkGlError("ShaderProgram test");
}

}  // namespace
}  // namespace ropecast
