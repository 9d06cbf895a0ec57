// Compile checks of shaders/rope_traversal.glsl (and through it index/rope_layout.h as GLSL) with
// glslangValidator, from a fragment and a compute entry point. Includes are resolved by the shader loader
// (shaders/shader_source.h), from the embedded copies. glslangValidator is installed by scripts/bootstrap
// (glslang-tools): its absence is a failure, not a skip.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

#include "shaders/shader_source.h"

namespace ropecast {
namespace {

namespace fs = std::filesystem;

std::string readFile(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

struct Validation {
  int exitCode;
  std::string log;
};

// Writes `source` (after the shader loader resolved its includes) to a temporary file with the stage's
// extension and runs glslangValidator on it (OpenGL semantics, GLSL 4.50 from the #version line).
Validation validate(const std::string& source, const std::string& stage) {
  const fs::path dir = fs::temp_directory_path() / ("ropecast_glsl_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path shader = dir / ("test." + stage), log = dir / "log.txt";
  std::ofstream(dir / "main.glsl") << source;
  std::ofstream(shader) << preprocessShader((dir / "main.glsl").string(), {}).text;
  const std::string command = "glslangValidator '" + shader.string() + "' > '" + log.string() + "' 2>&1";
  const int status = std::system(command.c_str());
  Validation result{WIFEXITED(status) ? WEXITSTATUS(status) : -1, readFile(log)};
  fs::remove_all(dir);
  return result;
}

// Walks every leaf of a ray and folds what it learns into a value, so nothing is optimized away.
const char* kWalk = R"(
float walkRay(vec3 origin, vec3 dir) {
  float sum = 0.0;
  RopeCursor cursor;
  if (ropeBegin(cursor, origin, dir, 0.0, 1e30)) {
    RopeLeaf leaf;
    while (ropeNextLeaf(cursor, leaf)) {
      if (leaf.kind == kRopeTagDataLeaf) sum += float(leaf.brickSlot) * (leaf.tExit - leaf.tEnter);
      sum += leaf.boxSize + leaf.boxMin.x + float(leaf.depth + leaf.leafIndex);
    }
  }
  return sum;
}
)";

TEST(RopeGlsl, ValidatorIsInstalled) {
  ASSERT_EQ(std::system("glslangValidator --version > /dev/null 2>&1"), 0)
      << "glslangValidator not found: run scripts/bootstrap (package glslang-tools)";
}

TEST(RopeGlsl, FragmentEntryPointCompiles) {
  const std::string source =
      std::string("#version 450 core\n#include \"shaders/rope_traversal.glsl\"\n") + kWalk + R"(
uniform vec3 uOrigin;
layout(location = 0) out vec4 fragColor;
void main() {
  vec3 dir = vec3(gl_FragCoord.xy / 512.0, 1.0) - uOrigin;
  fragColor = vec4(walkRay(uOrigin, dir));
}
)";
  const Validation v = validate(source, "frag");
  EXPECT_EQ(v.exitCode, 0) << v.log;
}

TEST(RopeGlsl, ComputeEntryPointCompiles) {
  const std::string source =
      std::string("#version 450 core\n#include \"shaders/rope_traversal.glsl\"\n") + kWalk + R"(
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba32f, binding = 0) uniform writeonly image2D uImage;
uniform vec3 uOrigin;
void main() {
  vec3 dir = vec3(vec2(gl_GlobalInvocationID.xy) / 512.0, 1.0) - uOrigin;
  imageStore(uImage, ivec2(gl_GlobalInvocationID.xy), vec4(walkRay(uOrigin, dir)));
}
)";
  const Validation v = validate(source, "comp");
  EXPECT_EQ(v.exitCode, 0) << v.log;
}

// The check can fail: a shader that misuses the include (wrong argument types) is rejected.
TEST(RopeGlsl, BrokenShaderIsRejected) {
  const std::string source = R"(#version 450 core
#include "shaders/rope_traversal.glsl"
layout(location = 0) out vec4 fragColor;
void main() {
  RopeCursor cursor;
  fragColor = vec4(ropeBegin(cursor, 1.0, vec3(1.0), 0.0, 1.0));
}
)";
  const Validation v = validate(source, "frag");
  EXPECT_NE(v.exitCode, 0) << v.log;
  EXPECT_NE(v.log.find("ropeBegin"), std::string::npos) << v.log;
}

}  // namespace
}  // namespace ropecast
