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
  // `moreFields`: the caller's own, as JSON members ("\"time_point\":2"), after FrameStats' in the line.
  void write(const FrameStats& s, const std::string& moreFields = "") {
    if (!file_) return;
    std::string line = toJsonLine(s);
    if (!moreFields.empty()) line.insert(line.size() - 1, "," + moreFields);
    line += '\n';
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
