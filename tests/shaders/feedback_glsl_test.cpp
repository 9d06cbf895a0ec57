// Compile checks of shaders/feedback.glsl (and through it shaders/feedback_layout.h as GLSL) with
// glslangValidator (tests/shaders/testutil_glslang.h), from a fragment and a compute entry point. A misuse is
// rejected.
#include <gtest/gtest.h>

#include <string>

#include "tests/shaders/testutil_glslang.h"

namespace ropecast {
namespace {

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
  const test::GlslValidation v = test::validateGlsl(std::string(kRay) + R"(
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
  const test::GlslValidation v = test::validateGlsl(std::string(kRay) + R"(
layout(local_size_x = 8, local_size_y = 8) in;
void main() { rayFeedback(gl_GlobalInvocationID.x); }
)",
                                                    "comp");
  EXPECT_TRUE(v.ok) << v.log;
}

TEST(FeedbackGlsl, AMisuseIsRejected) {
  const test::GlslValidation v = test::validateGlsl(std::string(kRay) + R"(
layout(local_size_x = 8, local_size_y = 8) in;
void main() { feedbackSampled(gl_GlobalInvocationID.x, true); }
)",
                                                    "comp");
  EXPECT_FALSE(v.ok);
}

}  // namespace
}  // namespace ropecast
