// Compile checks of shaders/rope_traversal.glsl (and through it index/rope_layout.h as GLSL) with
// glslangValidator (tests/shaders/testutil_glslang.h), from a fragment and a compute entry point.
#include <gtest/gtest.h>

#include <string>

#include "tests/shaders/testutil_glslang.h"

namespace ropecast {
namespace {

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
  const test::GlslValidation v = test::validateGlsl(source, "frag");
  EXPECT_TRUE(v.ok) << v.log;
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
  const test::GlslValidation v = test::validateGlsl(source, "comp");
  EXPECT_TRUE(v.ok) << v.log;
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
  const test::GlslValidation v = test::validateGlsl(source, "frag");
  EXPECT_FALSE(v.ok) << v.log;
  EXPECT_NE(v.log.find("ropeBegin"), std::string::npos) << v.log;
}

}  // namespace
}  // namespace ropecast
