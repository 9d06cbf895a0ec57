// ShaderProgram: a linked GLSL program built from shader files (shaders/shader_source.h: the embedded copies,
// or ROPECAST_SHADER_DIR), whose compile errors name the real file and line. Owns a GL program object: render
// thread only, with the GlContext current.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "shaders/shader_source.h"

namespace ropecast {

enum class ShaderStage { Vertex, Fragment, Compute };

struct ShaderFile {
  ShaderStage stage;
  std::string path;
};

class ShaderProgram {
 public:
  // Compiles and links; throws ropecast::Error with the rewritten log on any compile or link error.
  ShaderProgram(const std::vector<ShaderFile>& files, const std::vector<std::string>& defines = {});
  ~ShaderProgram();
  ShaderProgram(ShaderProgram&& other) noexcept;
  ShaderProgram& operator=(ShaderProgram&& other) noexcept;
  ShaderProgram(const ShaderProgram&) = delete;
  ShaderProgram& operator=(const ShaderProgram&) = delete;

  uint32_t id() const { return program_; }
  void use() const;
  // Uniform location, -1 when the uniform is absent or optimized away (setting -1 is a no-op in GL).
  int uniform(const char* name) const;

 private:
  uint32_t program_ = 0;
};

}  // namespace ropecast
