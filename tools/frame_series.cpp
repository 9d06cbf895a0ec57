#include "tools/frame_series.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "core/error.h"

namespace ropecast::tools {

std::string framePath(const std::string& output, uint64_t frame) {
  const std::filesystem::path p(output);
  char suffix[32];
  std::snprintf(suffix, sizeof suffix, "_%04llu", static_cast<unsigned long long>(frame));
  return (p.parent_path() / (p.stem().string() + suffix + p.extension().string())).string();
}

FrameSeries::FrameSeries(const std::string& output, bool enabled) : output_(output) {
  if (!enabled) return;
  const std::filesystem::path out(output);
  const std::filesystem::path parent = out.parent_path().empty() ? "." : out.parent_path();
  std::string prefix = ".";  // hidden beside the output while it fills
  prefix += out.stem().string();
  prefix += "_frames";
  staging_.emplace(parent, prefix);
}

void FrameSeries::write(uint64_t frame, const FloatImage& color) {
  if (!staging_) return;
  const std::string name = std::filesystem::path(framePath(output_, frame)).filename().string();
  writePng((staging_->path() / name).string(), color, false);
  staged_.push_back(name);
}

void FrameSeries::checkTargets() const {
  const std::filesystem::path parent = std::filesystem::path(output_).parent_path();
  for (const std::string& name : staged_) {
    std::error_code ec;
    if (std::filesystem::is_directory(parent / name, ec))
      throw Error("render: --every: the frame '" + (parent / name).string() +
                  "' cannot be written: a folder has its name; nothing was written");
  }
}

void FrameSeries::commit() {
  if (!staging_) return;
  const std::filesystem::path parent = std::filesystem::path(output_).parent_path();
  for (const std::string& name : staged_) {
    const std::filesystem::path to = parent / name;
    if (std::rename((staging_->path() / name).c_str(), to.c_str()) != 0)
      throw Error("render: --every: cannot move the frame '" + to.string() +
                  "' into place: " + std::strerror(errno));
  }
  staged_.clear();
}

}  // namespace ropecast::tools
