// The shader loader: #include resolution, #line framing, defines after #version, and compile errors pointing
// at the real file and line.
#include <cstdlib>
#include <fstream>
#include <optional>
#include <string>

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include "loader/error.h"
#include "render/shader_program.h"
#include "tests/render/testutil_gl.h"

namespace ropecast {
namespace {

namespace fs = std::filesystem;

void writeText(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

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

TEST(ShaderPreprocess, IncludesOnceWithLineDirectivesAndDefines) {
  const fs::path dir = test::freshTempDir();
  writeText(dir / "lib/common.glsl", "// common\nfloat one() { return 1.0; }\n");
  writeText(dir / "lib/helper.glsl", "#include \"common.glsl\"\nfloat two() { return one() + one(); }\n");
  writeText(
      dir / "main.comp",
      "#version 450 core\n#include \"lib/helper.glsl\"\n#include \"lib/common.glsl\"\nvoid main() {}\n");
  const PreprocessedShader s = preprocessShader("main.comp", {"MODE_ISO", "TILE 64"}, {dir});
  ASSERT_EQ(s.fileNames.size(), 3u);
  EXPECT_EQ(s.fileNames[0], "main.comp");
  EXPECT_EQ(s.fileNames[1], "lib/helper.glsl");
  EXPECT_EQ(s.fileNames[2], "lib/common.glsl");
  const std::string expected =
      "#version 450 core\n"
      "#define MODE_ISO\n"
      "#define TILE 64\n"
      "#line 2 0\n"
      "#line 1 1\n"
      "#line 1 2\n"
      "// common\n"
      "float one() { return 1.0; }\n"
      "#line 2 1\n"
      "float two() { return one() + one(); }\n"
      "#line 3 0\n"
      "\n"  // the second include of common.glsl is skipped
      "void main() {}\n";
  EXPECT_EQ(s.text, expected);
}

TEST(ShaderPreprocess, MissingFilesAreNamed) {
  const fs::path dir = test::freshTempDir();
  writeText(dir / "a.frag", "#version 450 core\n\n#include \"nowhere.glsl\"\n");
  writeText(dir / "noversion.frag", "void main() {}\n");
  try {
    preprocessShader("a.frag", {}, {dir});
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("a.frag:3: included file 'nowhere.glsl' not found"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(preprocessShader("missing.frag", {}, {dir}), Error);
  try {
    preprocessShader("noversion.frag", {}, {dir});
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'noversion.frag' has no #version line"), std::string::npos)
        << e.what();
  }
}

TEST(ShaderPreprocess, RewritesLogsOfKnownDrivers) {
  const std::vector<std::string> names = {"main.comp", "lib/x.glsl"};
  EXPECT_EQ(rewriteShaderLog("1:7(12): error: bad\n", names), "lib/x.glsl:7(12): error: bad\n");
  EXPECT_EQ(rewriteShaderLog("1(7) : error C1008: bad\n", names), "lib/x.glsl:7 : error C1008: bad\n");
  EXPECT_EQ(rewriteShaderLog("ERROR: 0:3: bad\n", names), "ERROR: main.comp:3: bad\n");
  EXPECT_EQ(rewriteShaderLog("no location here\n", names), "no location here\n");
}

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
