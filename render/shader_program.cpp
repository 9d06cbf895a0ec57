#include "render/shader_program.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <regex>
#include <sstream>
#include <unordered_map>
#include <utility>

#include <epoxy/gl.h>

#include "loader/error.h"

namespace ropecast {

namespace fs = std::filesystem;

std::vector<fs::path> shaderSearchPath() {
  std::vector<fs::path> dirs;
  if (const char* env = std::getenv("ROPECAST_SHADER_DIR"); env && *env) {
    std::stringstream list(env);
    std::string dir;
    while (std::getline(list, dir, ':'))
      if (!dir.empty()) dirs.emplace_back(dir);
  }
  if (dirs.empty()) dirs.emplace_back(ROPECAST_SHADER_SEARCH_PATH);
  return dirs;
}

namespace {

struct Located {
  fs::path file;     // where it was read from
  std::string name;  // how logs name it: the path relative to the search directory that held it
};

bool readFile(const fs::path& p, std::string& out) {
  std::ifstream in(p, std::ios::binary);
  if (!in) return false;
  std::stringstream ss;
  ss << in.rdbuf();
  out = ss.str();
  return true;
}

class Preprocessor {
 public:
  explicit Preprocessor(const std::vector<fs::path>& searchPath) : searchPath_(searchPath) {}

  PreprocessedShader run(const std::string& path, const std::vector<std::string>& defines) {
    const std::optional<Located> top = locate(path, {});
    if (!top)
      throw Error("preprocessShader: shader file '" + path + "' not found on the search path" + pathText());
    std::string text;
    if (!readFile(top->file, text)) throw Error("preprocessShader: cannot read '" + top->file.string() + "'");
    const int fileNo = registerFile(*top);

    std::istringstream lines(text);
    std::string line;
    int lineNo = 0;
    bool sawVersion = false;
    while (!sawVersion && std::getline(lines, line)) {
      ++lineNo;
      out_ << line << '\n';
      sawVersion = std::regex_search(line, std::regex(R"(^\s*#\s*version\b)"));
    }
    if (!sawVersion) throw Error("preprocessShader: '" + top->name + "' has no #version line");
    for (const std::string& d : defines) out_ << "#define " << d << '\n';
    out_ << "#line " << lineNo + 1 << ' ' << fileNo << '\n';
    emitBody(lines, lineNo, *top, fileNo);
    return {out_.str(), fileNames_};
  }

 private:
  std::optional<Located> locate(const std::string& path, const fs::path& includingDir) const {
    const fs::path p(path);
    if (p.is_absolute()) {
      if (fs::is_regular_file(p)) return Located{p, path};
      return std::nullopt;
    }
    if (!includingDir.empty() && fs::is_regular_file(includingDir / p)) {
      const fs::path file = (includingDir / p).lexically_normal();
      for (const fs::path& root : searchPath_) {  // name it relative to the root that holds it, when one does
        const fs::path rel = file.lexically_relative(root.lexically_normal());
        if (!rel.empty() && *rel.begin() != "..") return Located{file, rel.generic_string()};
      }
      return Located{file, file.generic_string()};
    }
    for (const fs::path& root : searchPath_)
      if (fs::is_regular_file(root / p))
        return Located{(root / p).lexically_normal(), p.lexically_normal().generic_string()};
    return std::nullopt;
  }

  int registerFile(const Located& f) {
    fileNames_.push_back(f.name);
    included_.emplace(fs::weakly_canonical(f.file).string(), int(fileNames_.size()) - 1);
    return int(fileNames_.size()) - 1;
  }

  void emitBody(std::istream& lines, int lineNo, const Located& self, int fileNo) {
    static const std::regex includeRe(R"(^\s*#\s*include\s+"([^"]+)\"\s*(//.*)?$)");
    static const std::regex pragmaOnceRe(R"(^\s*#\s*pragma\s+once\b)");
    std::string line;
    while (std::getline(lines, line)) {
      ++lineNo;
      std::smatch m;
      if (std::regex_match(line, m, includeRe)) {
        const std::string target = m[1].str();
        const std::optional<Located> inc = locate(target, self.file.parent_path());
        if (!inc)
          throw Error("preprocessShader: " + self.name + ":" + std::to_string(lineNo) + ": included file '" +
                      target + "' not found next to it or on the search path" + pathText());
        if (included_.count(fs::weakly_canonical(inc->file).string())) {
          out_ << '\n';  // already included once: keep the line count
          continue;
        }
        std::string text;
        if (!readFile(inc->file, text))
          throw Error("preprocessShader: cannot read '" + inc->file.string() + "'");
        const int incNo = registerFile(*inc);
        out_ << "#line 1 " << incNo << '\n';
        std::istringstream incLines(text);
        emitBody(incLines, 0, *inc, incNo);
        out_ << "#line " << lineNo + 1 << ' ' << fileNo << '\n';
      } else if (std::regex_search(line, pragmaOnceRe)) {
        out_ << '\n';
      } else {
        out_ << line << '\n';
      }
    }
  }

  std::string pathText() const {
    std::string s = " (search path:";
    for (const fs::path& p : searchPath_) s += " " + p.string();
    return s + ")";
  }

  const std::vector<fs::path>& searchPath_;
  std::ostringstream out_;
  std::vector<std::string> fileNames_;
  std::unordered_map<std::string, int> included_;
};

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

PreprocessedShader preprocessShader(const std::string& path, const std::vector<std::string>& defines,
                                    const std::vector<fs::path>& searchPath) {
  return Preprocessor(searchPath).run(path, defines);
}

std::string rewriteShaderLog(const std::string& log, const std::vector<std::string>& fileNames) {
  // Mesa "0:12(5): error", NVIDIA "0(12) : error", AMD/others "ERROR: 0:12: ...".
  static const std::regex mesaRe(R"(^(\s*)(\d+):(\d+)\((\d+)\))");
  static const std::regex nvidiaRe(R"(^(\s*)(\d+)\((\d+)\))");
  static const std::regex genericRe(R"(^(\s*(?:ERROR|WARNING): )(\d+):(\d+):)");
  auto name = [&](const std::string& no) {
    const size_t i = size_t(std::stoul(no));
    return i < fileNames.size() ? fileNames[i] : no;
  };
  std::istringstream in(log);
  std::ostringstream out;
  std::string line;
  while (std::getline(in, line)) {
    std::smatch m;
    if (std::regex_search(line, m, mesaRe))
      line = m[1].str() + name(m[2]) + ":" + m[3].str() + "(" + m[4].str() + ")" + m.suffix().str();
    else if (std::regex_search(line, m, genericRe))
      line = m[1].str() + name(m[2]) + ":" + m[3].str() + ":" + m.suffix().str();
    else if (std::regex_search(line, m, nvidiaRe))
      line = m[1].str() + name(m[2]) + ":" + m[3].str() + m.suffix().str();
    out << line << '\n';
  }
  return out.str();
}

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
