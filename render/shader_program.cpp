#include "render/shader_program.h"

#include <algorithm>
#include <cstring>
#include <iterator>
#include <utility>

#include <epoxy/gl.h>

#include "core/error.h"

namespace ropecast {

namespace {

struct StageInfo {
  GLenum glStage;
  const char* name;
};

StageInfo stageInfo(ShaderStage s) {
  static constexpr StageInfo kStages[] = {
      {GL_VERTEX_SHADER, "vertex"}, {GL_FRAGMENT_SHADER, "fragment"}, {GL_COMPUTE_SHADER, "compute"}};
  static_assert(std::size(kStages) == size_t(ShaderStage::Compute) + 1, "an entry per ShaderStage");
  return kStages[size_t(s)];
}

// The info log of a shader or program object (glGetShaderiv + glGetShaderInfoLog, or the program pair).
template <typename GetInteger, typename GetLog>
std::string infoLog(GLuint object, GetInteger getInteger, GetLog getLog) {
  GLint length = 0;
  getInteger(object, GL_INFO_LOG_LENGTH, &length);
  std::string log(size_t(std::max(length, 1)), '\0');
  getLog(object, length, nullptr, log.data());
  log.resize(std::strlen(log.c_str()));
  return log;
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
    const GLuint shader = glCreateShader(stageInfo(f.stage).glStage);
    shaders.push_back(shader);
    const char* text = src.text.c_str();
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
      const std::string log = infoLog(shader, glGetShaderiv, glGetShaderInfoLog);
      cleanup();
      throw Error("ShaderProgram: compiling " + std::string(stageInfo(f.stage).name) + " shader '" + f.path +
                  "' failed:\n" + rewriteShaderLog(log, src.fileNames));
    }
    glAttachShader(program_, shader);
    names += (names.empty() ? "" : ", ") + f.path;
  }
  glLinkProgram(program_);
  GLint ok = 0;
  glGetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (!ok) {
    const std::string log = infoLog(program_, glGetProgramiv, glGetProgramInfoLog);
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
