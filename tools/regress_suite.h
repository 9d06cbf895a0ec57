// A regression suite of `ropecast regress` (docs/REGRESS.md): JSON read into plain data, its paths resolved
// against the suite file's folder, its tolerances merged with the suite-wide ones. GL-free; any thread.
#pragma once

#include <string>
#include <vector>

#include "core/error.h"

namespace ropecast::tools {

// A suite that cannot be run as written (bad JSON, a missing or unknown key, a bad value): regress exits 2.
class SuiteError : public Error {
 public:
  using Error::Error;
};

// When a case's render counts as its golden image. Values are in [0, 1] per channel (8-bit PNG: v / 255).
struct RegressTolerances {
  double minPsnrDb = 40.0;                 // "min_psnr_db": PSNR (peak 1) of the RGB channels
  double maxPixelError = 0.25;             // "max_pixel_error": largest |golden - render| of any channel
  double failingPixelError = 2.0 / 255.0;  // "failing_pixel_error": a pixel fails when a channel differs more
  double maxFailingShare = 0.005;          // "max_failing_share": share of failing pixels allowed
};

struct RegressCase {
  std::string name;   // [A-Za-z0-9._-]+, unique in the suite (report files are named by it)
  std::string input;  // procedural:NAME:SIZE, or a store path resolved against the suite folder
  std::vector<std::string> options;  // `ropecast render` options as on its command line
  std::string golden;                // image path resolved against the suite folder
  RegressTolerances tolerances;
};

struct RegressSuite {
  std::string path;  // the suite file
  std::vector<RegressCase> cases;
};

// Reads a suite from `text`; `suitePath` resolves relative paths and names the file in errors. Throws
// SuiteError naming the file, the case and the key, and what was expected.
RegressSuite parseRegressSuite(const std::string& text, const std::string& suitePath);
// Reads the file at `suitePath` and parses it. Throws SuiteError.
RegressSuite loadRegressSuite(const std::string& suitePath);

}  // namespace ropecast::tools
