// StatsWriter: `--stats FILE` of render and view, one FrameStats JSON line per frame, written under a
// temporary name and renamed by finish(), so that a failed or interrupted run leaves no partial file
// (TemporaryFile: removed on destruction and, with removeTemporaryFilesOnSignals, on a signal). Without a
// path it writes nothing. Owned by the render thread.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "core/temporary_file.h"
#include "render/frame_stats.h"

namespace ropecast::tools {

class StatsWriter {
 public:
  // `who` names the writer in errors ("render: --stats"); the file's folder is checked here.
  StatsWriter(const std::string& path, const std::string& who) {
    if (!path.empty()) file_.emplace(path, who);
  }
  void write(const FrameStats& s) {
    if (!file_) return;
    const std::string line = toJsonLine(s) + '\n';
    file_->writeAt(offset_, std::as_bytes(std::span(line)));
    offset_ += line.size();
  }
  void finish() {
    if (file_) file_->commit();
  }

 private:
  std::optional<TemporaryFile> file_;
  uint64_t offset_ = 0;
};

}  // namespace ropecast::tools
