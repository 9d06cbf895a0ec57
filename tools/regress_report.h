// The outcome of each regression case and the HTML report of `ropecast regress --report DIR`: one page,
// index.html, beside the images it shows (golden, render, amplified difference), so DIR can be copied
// anywhere. Main thread.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "tools/regress_images.h"
#include "tools/regress_suite.h"

namespace ropecast::tools {

struct CaseOutcome {
  const RegressCase* regressCase = nullptr;
  bool converges = true;  // rendered with --converge (all but --reference cases)
  bool passed = false;
  bool updated = false;                        // its golden was (re)written from this render
  std::vector<std::string> problems;           // why it failed, one phrase each
  std::optional<GoldenDifference> difference;  // absent when there was no render or no golden to compare
  double seconds = 0.0;                        // render wall time
  // Report files, relative to the report folder ("" when absent).
  std::string goldenFile, renderFile, differenceFile;
};

// Writes DIR/index.html over the outcomes, failing cases first. Throws ropecast::Error naming the file.
void writeRegressReport(const std::string& directory, const std::string& suitePath,
                        const std::vector<CaseOutcome>& outcomes);

}  // namespace ropecast::tools
