// glslangValidator over a shader source, for the compile checks of shaders/*.glsl: glslangValidator is
// stricter than Mesa's compiler, so a construct llvmpipe accepts and other drivers reject shows there. It is
// installed by scripts/bootstrap (glslang-tools): its absence is a failure, not a skip. Test thread only.
#pragma once

#include <string>

namespace ropecast::test {

struct GlslValidation {
  bool ok = false;
  std::string log;  // glslangValidator's output, with the include files' names (rewriteShaderLog)
};

// Resolves the includes of `source` with the shader loader (shaders/shader_source.h, from the embedded
// copies), writes it with the extension of `stage` ("frag", "comp", ...) to a fresh folder and runs
// glslangValidator on it (OpenGL semantics, the GLSL version of its #version line).
GlslValidation validateGlsl(const std::string& source, const std::string& stage);

}  // namespace ropecast::test
