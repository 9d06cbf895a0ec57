// `ropecast verify STORE`: reads every node and checks checksums and structure (store/verify.h). Exit 0 when
// everything holds, 3 when a check fails (each problem names its node), 1 when the store cannot be opened.
// Main thread.
#include <cstdio>
#include <memory>

#include "store/verify.h"
#include "tools/command.h"
#include "tools/progress_bar.h"

namespace ropecast::tools {
namespace {

constexpr int kVerifyFailed = 3;

int runVerify(const std::string& path, bool quiet, size_t maxProblems) {
  const auto store = Store::open(path);
  ProgressBar bar("verifying", "nodes", quiet);
  const VerifyReport report =
      verifyStore(*store, maxProblems, [&](uint64_t done, uint64_t total) { bar.update(done, total); });
  bar.finish();
  for (const std::string& problem : report.problems)
    std::fprintf(stderr, "ropecast verify: %s\n", problem.c_str());
  if (!report.ok()) {
    std::fprintf(stderr, "ropecast verify: %s: %llu problem(s) in %llu nodes\n", path.c_str(),
                 (unsigned long long)report.problemCount, (unsigned long long)report.nodesChecked);
    return kVerifyFailed;
  }
  std::printf("%s: ok, %llu nodes checked\n", path.c_str(), (unsigned long long)report.nodesChecked);
  return 0;
}

const CommandRegistration verifyCommand("verify", 30, [](CLI::App& app) -> std::function<int()> {
  app.description("read every node of a store and check checksums, ranges, borders and filtering");
  auto path = std::make_shared<std::string>();
  auto quiet = std::make_shared<bool>(false);
  auto maxProblems = std::make_shared<size_t>(20);
  app.add_option("store", *path, "store file")->required();
  app.add_option("--max-problems", *maxProblems, "problems to print at most")->capture_default_str();
  app.add_flag("-q,--quiet", *quiet, "no progress bar");
  return [path, quiet, maxProblems] { return runVerify(*path, *quiet, *maxProblems); };
});

}  // namespace
}  // namespace ropecast::tools
