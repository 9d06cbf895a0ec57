#include "shaders/shader_source.h"

#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>
#include <unordered_set>

#include "core/error.h"
#include "shaders/embedded_files.h"

namespace ropecast {

namespace fs = std::filesystem;

ShaderSearchPath shaderSearchPath() {
  ShaderSearchPath path;
  if (const char* env = std::getenv("ROPECAST_SHADER_DIR"); env && *env) {
    std::stringstream list(env);
    std::string dir;
    while (std::getline(list, dir, ':'))
      if (!dir.empty()) path.folders.emplace_back(dir);
    path.embedded = path.folders.empty();
  }
  return path;
}

std::optional<std::string_view> embeddedShaderFile(std::string_view name) {
  for (size_t i = 0; i < kEmbeddedShaderFileCount; ++i)
    if (name == kEmbeddedShaderFiles[i].name) return std::string_view(kEmbeddedShaderFiles[i].text);
  return std::nullopt;
}

std::vector<std::string> embeddedShaderFileNames() {
  std::vector<std::string> names;
  for (size_t i = 0; i < kEmbeddedShaderFileCount; ++i) names.emplace_back(kEmbeddedShaderFiles[i].name);
  return names;
}

namespace {

// A source file found: its text, the name logs give it (root-relative where it has one) and the key that
// makes "each file once" work whether it came from a folder or from the embedded copies.
struct Located {
  std::string text;
  std::string name;
  std::string key;
  fs::path folder;  // the folder of a file read from disk (for relative includes), empty for embedded ones
};

std::optional<std::string> readFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) return std::nullopt;
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

class Preprocessor {
 public:
  explicit Preprocessor(const ShaderSearchPath& searchPath) : searchPath_(searchPath) {}

  PreprocessedShader run(const std::string& path, const std::vector<std::string>& defines) {
    const std::optional<Located> top = locate(path, nullptr);
    if (!top) throw Error("preprocessShader: shader file '" + path + "' not found" + whereText());
    const int fileNo = registerFile(*top);

    std::istringstream lines(top->text);
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
  std::optional<Located> fromDisk(const fs::path& file) const {
    if (!fs::is_regular_file(file)) return std::nullopt;
    std::optional<std::string> text = readFile(file);
    if (!text) throw Error("preprocessShader: cannot read '" + file.string() + "'");
    const fs::path normal = file.lexically_normal();
    std::string name = normal.generic_string();
    for (const fs::path& root :
         searchPath_.folders) {  // named relative to the folder that holds it, if one does
      const fs::path rel = normal.lexically_relative(root.lexically_normal());
      if (!rel.empty() && *rel.begin() != "..") {
        name = rel.generic_string();
        break;
      }
    }
    return Located{std::move(*text), name, fs::weakly_canonical(file).string(), normal.parent_path()};
  }

  std::optional<Located> fromEmbedded(const std::string& name) const {
    if (!searchPath_.embedded) return std::nullopt;
    const std::optional<std::string_view> text = embeddedShaderFile(name);
    if (!text) return std::nullopt;
    return Located{std::string(*text), name, "embedded:" + name, {}};
  }

  // `including` is the file whose #include names `path` (nullptr for the top file).
  std::optional<Located> locate(const std::string& path, const Located* including) const {
    const fs::path p(path);
    if (p.is_absolute()) return fromDisk(p);
    if (including && !including->folder.empty())
      if (std::optional<Located> f = fromDisk(including->folder / p)) return f;
    if (including &&
        including->folder.empty()) {  // embedded: relative to its folder among the embedded names
      const std::string sibling =
          (fs::path(including->name).parent_path() / p).lexically_normal().generic_string();
      if (std::optional<Located> f = fromEmbedded(sibling)) return f;
    }
    for (const fs::path& root : searchPath_.folders)
      if (std::optional<Located> f = fromDisk(root / p)) return f;
    return fromEmbedded(p.lexically_normal().generic_string());
  }

  int registerFile(const Located& f) {
    fileNames_.push_back(f.name);
    included_.insert(f.key);
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
        const std::optional<Located> inc = locate(target, &self);
        if (!inc)
          throw Error("preprocessShader: " + self.name + ":" + std::to_string(lineNo) + ": included file '" +
                      target + "' not found next to it or" + whereText());
        if (included_.count(inc->key)) {
          out_ << '\n';  // already included once: keep the line count
          continue;
        }
        const int incNo = registerFile(*inc);
        out_ << "#line 1 " << incNo << '\n';
        std::istringstream incLines(inc->text);
        emitBody(incLines, 0, *inc, incNo);
        out_ << "#line " << lineNo + 1 << ' ' << fileNo << '\n';
      } else if (std::regex_search(line, pragmaOnceRe)) {
        out_ << '\n';
      } else {
        out_ << line << '\n';
      }
    }
  }

  std::string whereText() const {
    std::string s = " (searched:";
    for (const fs::path& p : searchPath_.folders) s += " " + p.string();
    if (searchPath_.embedded) s += " the shaders built into ropecast";
    return s + ")";
  }

  const ShaderSearchPath& searchPath_;
  std::ostringstream out_;
  std::vector<std::string> fileNames_;
  std::unordered_set<std::string> included_;
};

}  // namespace

PreprocessedShader preprocessShader(const std::string& path, const std::vector<std::string>& defines,
                                    const ShaderSearchPath& searchPath) {
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

}  // namespace ropecast
