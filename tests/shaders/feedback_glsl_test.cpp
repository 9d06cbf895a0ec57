// Compile checks of shaders/feedback.glsl (and through it shaders/feedback_layout.h as GLSL) with
// glslangValidator, from a fragment and a compute entry point: glslangValidator is stricter than Mesa's
// compiler, so a construct llvmpipe accepts and other drivers reject shows here. A misuse is rejected.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/wait.h>

#include "shaders/shader_source.h"
#include "tests/common/temp_dir.h"

namespace ropecast {
namespace {

struct Validation {
  bool ok = false;
  std::string log;
};

// Resolves the includes of `source` (a file in a fresh folder) and runs glslangValidator on it.
Validation validate(const std::string& source, const std::string& stage) {
  const auto dir = test::freshTempDir();
  test::writeText(dir / "main.glsl", source);
  const PreprocessedShader shader = preprocessShader((dir / "main.glsl").string(), {});
  test::writeText(dir / ("test." + stage), shader.text);
  const std::string command = "glslangValidator '" + (dir / ("test." + stage)).string() + "' > '" +
                              (dir / "log.txt").string() + "' 2>&1";
  const int status = std::system(command.c_str());
  std::stringstream log;
  log << std::ifstream(dir / "log.txt").rdbuf();
  return {WIFEXITED(status) && WEXITSTATUS(status) == 0, rewriteShaderLog(log.str(), shader.fileNames)};
}

// A ray's feedback over a few leaves, as shaders/raycast_common.glsl calls it.
const char* kRay = R"(#version 450 core
#include "shaders/raycast_block.h"
#include "shaders/feedback.glsl"
void rayFeedback(uint firstLeaf) {
  RayFeedback fb = rayFeedbackBegin();
  for (uint i = 0u; i < 4u; ++i)
    feedbackSampled(fb, firstLeaf + i, feedbackWantsFiner(i, float(i), 0.5));
}
)";

TEST(FeedbackGlsl, FragmentEntryPointCompiles) {
  const Validation v = validate(std::string(kRay) + R"(
layout(location = 0) out vec4 fragColor;
void main() {
  rayFeedback(uint(gl_FragCoord.x));
  fragColor = vec4(1.0);
}
)",
                                "frag");
  EXPECT_TRUE(v.ok) << v.log;
}

TEST(FeedbackGlsl, ComputeEntryPointCompiles) {
  const Validation v = validate(std::string(kRay) + R"(
layout(local_size_x = 8, local_size_y = 8) in;
void main() { rayFeedback(gl_GlobalInvocationID.x); }
)",
                                "comp");
  EXPECT_TRUE(v.ok) << v.log;
}

TEST(FeedbackGlsl, AMisuseIsRejected) {
  const Validation v = validate(std::string(kRay) + R"(
layout(local_size_x = 8, local_size_y = 8) in;
void main() { feedbackSampled(gl_GlobalInvocationID.x, true); }
)",
                                "comp");
  EXPECT_FALSE(v.ok);
}

}  // namespace
}  // namespace ropecast
