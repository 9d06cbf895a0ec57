#include "tests/shaders/testutil_glslang.h"

#include <cstdlib>
#include <fstream>
#include <sstream>

#include <sys/wait.h>

#include "shaders/shader_source.h"
#include "tests/common/temp_dir.h"

namespace ropecast::test {

GlslValidation validateGlsl(const std::string& source, const std::string& stage) {
  const auto dir = freshTempDir();
  writeText(dir / "main.glsl", source);
  const PreprocessedShader shader = preprocessShader((dir / "main.glsl").string(), {});
  writeText(dir / ("test." + stage), shader.text);
  const std::string command = "glslangValidator '" + (dir / ("test." + stage)).string() + "' > '" +
                              (dir / "log.txt").string() + "' 2>&1";
  const int status = std::system(command.c_str());
  std::stringstream log;
  log << std::ifstream(dir / "log.txt").rdbuf();
  return {WIFEXITED(status) && WEXITSTATUS(status) == 0, rewriteShaderLog(log.str(), shader.fileNames)};
}

}  // namespace ropecast::test
