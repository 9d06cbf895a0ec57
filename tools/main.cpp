// ropecast: the command line over the libraries. Prints library errors and exits non-zero.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>

#include "core/error.h"
#include "tools/command.h"
#include "tools/parse_error_text.h"

namespace ropecast::tools {
std::vector<CommandEntry>& commandRegistry() {
  static std::vector<CommandEntry> registry;
  return registry;
}
}  // namespace ropecast::tools

namespace {
// Exit statuses: 0 done, 1 a runtime error (a bad file, I/O, GL), 2 a usage error (README.md "Exit status").
constexpr int kUsageError = 2;
}  // namespace

int main(int argc, char** argv) {
  using namespace ropecast::tools;
  CLI::App app{"ropecast: out-of-core GPU ray casting of massive volumes (rope octree, single pass)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "ropecast 0.1");

  auto& registry = commandRegistry();
  std::sort(registry.begin(), registry.end(), [](auto& a, auto& b) { return a.order < b.order; });
  std::vector<std::pair<CLI::App*, std::function<int()>>> runs;
  for (auto& entry : registry) {
    auto* sub = app.add_subcommand(entry.name);
    runs.emplace_back(sub, entry.setup(*sub));
  }

  // A mistyped command would be "A subcommand is required": name it and the commands there are.
  if (argc >= 2 && argv[1][0] != '-' &&
      std::none_of(registry.begin(), registry.end(), [&](auto& e) { return e.name == argv[1]; })) {
    std::string names;
    for (const auto& entry : registry) names += (names.empty() ? "" : ", ") + entry.name;
    std::fprintf(stderr, "ropecast: unknown command '%s'; the commands are %s (ropecast --help)\n", argv[1],
                 names.c_str());
    return kUsageError;
  }
  // Likewise a mistyped subcommand of a command that has them ("bench foo").
  for (const auto& [sub, run] : runs) {
    if (argc < 3 || argv[2][0] == '-' || sub->get_name() != argv[1]) continue;
    const std::vector<CLI::App*> subs = sub->get_subcommands([](CLI::App*) { return true; });
    if (subs.empty() ||
        std::any_of(subs.begin(), subs.end(), [&](CLI::App* s) { return s->get_name() == argv[2]; }))
      continue;
    std::string names;
    for (const CLI::App* s : subs) names += (names.empty() ? "" : ", ") + s->get_name();
    std::fprintf(stderr, "ropecast %s: unknown subcommand '%s'; they are %s (ropecast %s --help)\n", argv[1],
                 argv[2], names.c_str(), argv[1]);
    return kUsageError;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version end here with 0; every usage error exits 2 (CLI11 would use its own 100+ codes).
    if (e.get_exit_code() == 0) return app.exit(e);
    std::fprintf(stderr, "ropecast: error: %s\n(%s --help lists the options)\n",
                 parseErrorText(app, e).c_str(), parsedCommandPath(app).c_str());
    return kUsageError;
  }
  try {
    for (auto& [sub, run] : runs)
      if (sub->parsed()) return run();
  } catch (const ropecast::UsageError& e) {
    std::fprintf(stderr, "ropecast: error: %s\n", e.what());
    return kUsageError;
  } catch (const ropecast::Error& e) {
    std::fprintf(stderr, "ropecast: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    // Not ropecast::Error (out of memory, say): a runtime error all the same.
    std::fprintf(stderr, "ropecast: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
