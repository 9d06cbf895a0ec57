// The shader preprocessor: #include resolution, #line framing, defines after #version, logs rewritten to the
// real file and line, and the embedded copies of the shader files.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "core/error.h"
#include "shaders/shader_source.h"
#include "tests/common/temp_dir.h"

namespace ropecast {
namespace {

namespace fs = std::filesystem;

using test::writeText;

TEST(ShaderPreprocess, IncludesOnceWithLineDirectivesAndDefines) {
  const fs::path dir = test::freshTempDir();
  writeText(dir / "lib/common.glsl", "// common\nfloat one() { return 1.0; }\n");
  writeText(dir / "lib/helper.glsl", "#include \"common.glsl\"\nfloat two() { return one() + one(); }\n");
  writeText(
      dir / "main.comp",
      "#version 450 core\n#include \"lib/helper.glsl\"\n#include \"lib/common.glsl\"\nvoid main() {}\n");
  const PreprocessedShader s =
      preprocessShader("main.comp", {"MODE_ISO", "TILE 64"}, ShaderSearchPath{{dir}, false});
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
    preprocessShader("a.frag", {}, ShaderSearchPath{{dir}, false});
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("a.frag:3: included file 'nowhere.glsl' not found"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(preprocessShader("missing.frag", {}, ShaderSearchPath{{dir}, false}), Error);
  try {
    preprocessShader("noversion.frag", {}, ShaderSearchPath{{dir}, false});
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

TEST(ShaderSource, EveryShaderIsEmbeddedAndItsIncludesResolveWithoutTheSourceTree) {
  const ShaderSearchPath embeddedOnly{{}, true};
  int entryPoints = 0;
  for (const std::string& name : embeddedShaderFileNames()) {
    ASSERT_TRUE(embeddedShaderFile(name));
    for (const char* stage : {".frag", ".vert", ".comp"}) {
      if (!name.ends_with(stage)) continue;
      ++entryPoints;
      const PreprocessedShader s = preprocessShader(name, {}, embeddedOnly);
      EXPECT_NE(s.text.find("void main"), std::string::npos) << name;
    }
  }
  EXPECT_GE(entryPoints, 4);
  EXPECT_TRUE(embeddedShaderFile("index/rope_layout.h"));
  EXPECT_FALSE(embeddedShaderFile("shaders/no_such_file.glsl"));
}

TEST(ShaderSource, AFolderGoesBeforeTheEmbeddedCopies) {
  const fs::path dir = test::freshTempDir();
  writeText(dir / "shaders/shading.glsl", "// edited\n");
  writeText(dir / "main.frag",
            "#version 450 core\n#include \"shaders/shading.glsl\"\n#include \"index/rope_layout.h\"\n");
  const PreprocessedShader s = preprocessShader("main.frag", {}, ShaderSearchPath{{dir}, true});
  EXPECT_NE(s.text.find("// edited"), std::string::npos);
  ASSERT_EQ(s.fileNames.size(), 3u);
  EXPECT_EQ(s.fileNames[1], "shaders/shading.glsl");
  EXPECT_EQ(s.fileNames[2], "index/rope_layout.h");  // from the embedded copies
  EXPECT_THROW(preprocessShader("main.frag", {}, ShaderSearchPath{{dir}, false}), Error);
}

}  // namespace
}  // namespace ropecast
