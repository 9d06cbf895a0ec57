// Field-by-field check of shaders/raycast_block.h: the offsets of the C++ RaycastBlock against those the GLSL
// compiler gives the std140 block, every field of the block covered, and the block's size.
#include <cstddef>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include "render/gl_context.h"
#include "render/shader_program.h"
#include "shaders/raycast_block.h"
#include "tests/render/testutil_gl.h"

namespace ropecast {
namespace {

#define FIELD(name) \
  { "RaycastBlock." #name, offsetof(RaycastBlock, name) }
const std::map<std::string, size_t> kCppOffsets = {
    FIELD(eye),
    FIELD(tanHalfFov),
    FIELD(forward),
    FIELD(aspect),
    FIELD(right),
    FIELD(depthNear),
    FIELD(up),
    FIELD(depthFar),
    FIELD(imageSize),
    FIELD(stepVoxels),
    FIELD(ert),
    FIELD(clipMax),
    FIELD(minSpacing),
    FIELD(spacing),
    FIELD(isoValue),
    FIELD(cubeWorld),
    FIELD(brickSize),
    FIELD(valueTexelSize),
    FIELD(maxDepth),
    FIELD(poolSlotGrid),
    FIELD(poolSlotEdge),
    FIELD(background),
    FIELD(ambient),
    FIELD(isoBaseColor),
    FIELD(diffuse),
    FIELD(specular),
    FIELD(shininess),
    FIELD(feedbackRequestDistance),
    FIELD(feedbackMinDistance),
    FIELD(clipMin),
    FIELD(clipPlaneOffset),
    FIELD(clipPlaneNormal),
    FIELD(leafMaximaCount),
    FIELD(leafMaximaLargest),
    FIELD(capBounds),
    FIELD(clipPlaneFar),
    FIELD(unused2),
};
#undef FIELD

TEST(RaycastBlock, CppLayoutMatchesTheGlslStd140Block) {
  test::sharedGlContext();
  const auto dir = test::freshTempDir();
  const auto shader = dir / "block.comp";
  // std140 blocks have every member active, so the compiler reports all of them even when unread.
  std::ofstream(shader) << "#version 450 core\nlayout(local_size_x = 1) in;\n"
                           "#include \"shaders/raycast_block.h\"\n"
                           "layout(std430, binding = 1) buffer Out { vec4 result; };\n"
                           "void main() { result = vec4(raycast.eye, raycast.ert); }\n";
  const ShaderProgram program({{ShaderStage::Compute, shader.string()}});
  const GLuint id = program.id();

  const GLuint block = glGetProgramResourceIndex(id, GL_UNIFORM_BLOCK, "RaycastBlock");
  ASSERT_NE(block, GL_INVALID_INDEX);
  const GLenum blockProps[] = {GL_BUFFER_DATA_SIZE, GL_BUFFER_BINDING, GL_NUM_ACTIVE_VARIABLES};
  GLint blockValues[3] = {};
  glGetProgramResourceiv(id, GL_UNIFORM_BLOCK, block, 3, blockProps, 3, nullptr, blockValues);
  EXPECT_EQ(size_t(blockValues[0]), sizeof(RaycastBlock));
  EXPECT_EQ(blockValues[1], kRaycastBlockBinding);
  EXPECT_EQ(size_t(blockValues[2]), kCppOffsets.size()) << "a field of the block is missing from this test";

  std::vector<GLint> members(static_cast<size_t>(blockValues[2]));
  const GLenum activeVariables = GL_ACTIVE_VARIABLES;
  glGetProgramResourceiv(id, GL_UNIFORM_BLOCK, block, 1, &activeVariables, GLsizei(members.size()), nullptr,
                         members.data());
  for (GLint member : members) {
    char name[128] = {};
    glGetProgramResourceName(id, GL_UNIFORM, GLuint(member), sizeof name, nullptr, name);
    const GLenum offsetProp = GL_OFFSET;
    GLint offset = -1;
    glGetProgramResourceiv(id, GL_UNIFORM, GLuint(member), 1, &offsetProp, 1, nullptr, &offset);
    const auto cpp = kCppOffsets.find(name);
    ASSERT_NE(cpp, kCppOffsets.end()) << name << " has no C++ twin in this test";
    EXPECT_EQ(size_t(offset), cpp->second) << name;
  }
  checkGlError("RaycastBlock layout test");
}

}  // namespace
}  // namespace ropecast
