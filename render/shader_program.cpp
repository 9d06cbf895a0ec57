#include "render/shader_program.h"

#include <algorithm>
#include <cstring>
#include <utility>

#include <epoxy/gl.h>

#include "core/error.h"

namespace ropecast {

namespace {

std::string stageName(ShaderStage s) {
  switch (s) {
    case ShaderStage::Vertex:
      return "vertex";
    case ShaderStage::Fragment:
      return "fragment";
    case ShaderStage::Compute:
      return "compute";
  }
  return "?";
}

GLenum glStage(ShaderStage s) {
  switch (s) {
    case ShaderStage::Vertex:
      return GL_VERTEX_SHADER;
    case ShaderStage::Fragment:
      return GL_FRAGMENT_SHADER;
    case ShaderStage::Compute:
      return GL_COMPUTE_SHADER;
  }
  return 0;
}

}  // namespace

ShaderProgram::ShaderProgram(const std::vector<ShaderFile>& files, const std::vector<std::string>& defines) {
  program_ = glCreateProgram();
  std::vector<GLuint> shaders;
  auto cleanup = [&]() {
    for (GLuint s : shaders) glDeleteShader(s);
    glDeleteProgram(program_);
    program_ = 0;
  };
  std::string names;
  for (const ShaderFile& f : files) {
    PreprocessedShader src;
    try {
      src = preprocessShader(f.path, defines);
    } catch (...) {
      cleanup();
      throw;
    }
    const GLuint shader = glCreateShader(glStage(f.stage));
    shaders.push_back(shader);
    const char* text = src.text.c_str();
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
      GLint length = 0;
      glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
      std::string log(size_t(std::max(length, 1)), '\0');
      glGetShaderInfoLog(shader, length, nullptr, log.data());
      log.resize(std::strlen(log.c_str()));
      cleanup();
      throw Error("ShaderProgram: compiling " + stageName(f.stage) + " shader '" + f.path + "' failed:\n" +
                  rewriteShaderLog(log, src.fileNames));
    }
    glAttachShader(program_, shader);
    names += (names.empty() ? "" : ", ") + f.path;
  }
  glLinkProgram(program_);
  GLint ok = 0;
  glGetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetProgramiv(program_, GL_INFO_LOG_LENGTH, &length);
    std::string log(size_t(std::max(length, 1)), '\0');
    glGetProgramInfoLog(program_, length, nullptr, log.data());
    log.resize(std::strlen(log.c_str()));
    cleanup();
    throw Error("ShaderProgram: linking " + names + " failed:\n" + log);
  }
  for (GLuint s : shaders) {
    glDetachShader(program_, s);
    glDeleteShader(s);
  }
}

ShaderProgram::~ShaderProgram() {
  if (program_) glDeleteProgram(program_);
}

ShaderProgram::ShaderProgram(ShaderProgram&& other) noexcept : program_(std::exchange(other.program_, 0)) {}

ShaderProgram& ShaderProgram::operator=(ShaderProgram&& other) noexcept {
  if (this != &other) {
    if (program_) glDeleteProgram(program_);
    program_ = std::exchange(other.program_, 0);
  }
  return *this;
}

void ShaderProgram::use() const {
  glUseProgram(program_);
}

int ShaderProgram::uniform(const char* name) const {
  return glGetUniformLocation(program_, name);
}

}  // namespace ropecast
