// ShaderProgram: a linked GLSL program built from files on the shader search path, and the small preprocessor
// that assembles its sources.
//
// Sources are found on the search path: the directories in ROPECAST_SHADER_DIR (colon-separated) if set, else
// the compile-time ROPECAST_SHADER_SEARCH_PATH (the repository root), so shaders name files like
// "shaders/shading.glsl" and "index/rope_layout.h". `#include "path"` is resolved textually, first relative
// to the including file's folder, then on the search path; each file is included at most once per source
// (include guards are implicit, so shared headers may be included from several places). Every inserted file
// is framed by
// `#line N FILE-NUMBER` directives, and the file-number -> file-name table turns compiler logs back into
// "file:line" of the real file. Variants come from `#define` lines inserted right after `#version`, never
// from text substitution inside a template.
//
// preprocessShader and rewriteShaderLog are pure functions (any thread). ShaderProgram owns a GL program
// object: render thread only, with the GlContext current.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace ropecast {

enum class ShaderStage { Vertex, Fragment, Compute };

struct PreprocessedShader {
  std::string text;                    // complete source, ready for glShaderSource
  std::vector<std::string> fileNames;  // index = the file number used in #line directives
};

// Search path directories in order (ROPECAST_SHADER_DIR entries, else ROPECAST_SHADER_SEARCH_PATH).
std::vector<std::filesystem::path> shaderSearchPath();

// Loads `path` (relative to the search path, or absolute), resolves includes and inserts `defines` (each line
// becomes "#define <entry>", e.g. "ISO_MODE" or "TILE_SIZE 64") after the #version line. Throws
// ropecast::Error naming the file (and the including file and line for a missing include) when something
// cannot be read, or when the top file has no #version line.
PreprocessedShader preprocessShader(
    const std::string& path, const std::vector<std::string>& defines,
    const std::vector<std::filesystem::path>& searchPath = shaderSearchPath());

// Replaces the file numbers of compiler log locations ("0:12(5): ...", "0(12) : ...", "ERROR: 0:12: ...") by
// the file names of `fileNames`, giving "shaders/x.glsl:12(5): ..." etc.
std::string rewriteShaderLog(const std::string& log, const std::vector<std::string>& fileNames);

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
