// FrameSeries: --every's numbered frames of `ropecast render` (OUT.png -> OUT_0007.png), staged in a
// temporary folder next to the output and moved into place by commit(), with the render's other outputs:
// a failed or interrupted render leaves none of them behind (TemporaryFolder: removed on destruction and,
// with removeTemporaryFilesOnSignals, on a signal). Owned by the render thread.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/temporary_file.h"
#include "reference/image_io.h"

namespace ropecast::tools {

// "out.png", frame 7 -> "out_0007.png".
std::string framePath(const std::string& output, uint64_t frame);

class FrameSeries {
 public:
  // Frames of `output` (-o); `enabled` false writes nothing. Throws ropecast::Error when the staging folder
  // cannot be made next to the output.
  FrameSeries(const std::string& output, bool enabled);
  // Stages frame `frame`'s PNG (8-bit color, no alpha).
  void write(uint64_t frame, const FloatImage& color);
  // Throws ropecast::Error naming a staged frame whose name is taken by a folder (commit() would fail there).
  void checkTargets() const;
  // Moves every staged frame onto its name. Throws ropecast::Error naming the frame that could not be moved.
  void commit();

 private:
  std::string output_;
  std::optional<TemporaryFolder> staging_;
  std::vector<std::string> staged_;  // file names, in staging_ and beside the output
};

}  // namespace ropecast::tools
