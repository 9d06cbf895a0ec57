// The progress lines of a conversion (`convert`, and a volume converted for render or view): the value-range
// pre-pass where there is one, then the bricks. Owned by the thread that converts.
#pragma once

#include "store/converter.h"
#include "tools/progress_bar.h"

namespace ropecast::tools {

class ConvertProgressBars {
 public:
  explicit ConvertProgressBars(bool quiet)
      : scan_("scanning range", "B", quiet), bricks_("converting", "B", quiet) {}

  // For ConvertOptions::progress (a lambda that calls it: the bars stay here).
  void update(const ConvertProgress& p) {
    if (p.phase == ConvertProgress::Phase::ValueRange) {
      scan_.update(p.bytesDone, p.bytesTotal);
    } else {
      scan_.finish();
      bricks_.update(p.bytesDone, p.bytesTotal);
    }
  }
  void finish() { bricks_.finish(); }

 private:
  ProgressBar scan_, bricks_;
};

}  // namespace ropecast::tools
