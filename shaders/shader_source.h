// Shader sources: the GLSL files of shaders/ and the layout headers they share with C++ (index/rope_layout.h,
// ...), embedded into the binary at build time so an installed or copied `ropecast` needs no source tree, and
// the small preprocessor that assembles a program's source from them.
//
// A file is named by its path from the repository root ("shaders/shading.glsl", "index/rope_layout.h"). Files
// come from the folders of ROPECAST_SHADER_DIR (colon-separated) when it is set, so that GLSL can be edited
// without rebuilding, else from the embedded copies. `#include "path"` is resolved textually, first relative
// to the including file's folder, then from the root; each file is included at most once per source (include
// guards are implicit, so shared headers may be included from several places). Every inserted file is framed
// by `#line N FILE-NUMBER` directives, and the file-number -> file-name table turns compiler logs back into
// "file:line" of the real file. Variants come from `#define` lines inserted right after `#version`, never
// from text substitution inside a template.
//
// GL-free pure functions; any thread.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ropecast {

struct PreprocessedShader {
  std::string text;                    // complete source, ready for glShaderSource
  std::vector<std::string> fileNames;  // index = the file number used in #line directives
};

// Where sources are read from: folders searched in order, and after them (or alone, when `folders` is empty)
// the embedded copies when `embedded` is set.
struct ShaderSearchPath {
  std::vector<std::filesystem::path> folders;
  bool embedded = true;
};

// The folders of ROPECAST_SHADER_DIR, without the embedded copies, when it is set; else the embedded copies.
ShaderSearchPath shaderSearchPath();

// The embedded copy of a file by its root-relative name, or nullopt.
std::optional<std::string_view> embeddedShaderFile(std::string_view name);
// The names of every embedded file.
std::vector<std::string> embeddedShaderFileNames();

// Loads `path` (root-relative, or an absolute file path), resolves includes and inserts `defines` (each line
// becomes "#define <entry>", e.g. "ISO_MODE" or "TILE_SIZE 64") after the #version line. Throws
// ropecast::Error naming the file (and the including file and line for a missing include) when something
// cannot be read, or when the top file has no #version line.
PreprocessedShader preprocessShader(const std::string& path, const std::vector<std::string>& defines,
                                    const ShaderSearchPath& searchPath = shaderSearchPath());

// Replaces the file numbers of compiler log locations ("0:12(5): ...", "0(12) : ...", "ERROR: 0:12: ...") by
// the file names of `fileNames`, giving "shaders/x.glsl:12(5): ..." etc.
std::string rewriteShaderLog(const std::string& log, const std::vector<std::string>& fileNames);

}  // namespace ropecast
