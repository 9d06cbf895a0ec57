// Subcommands of the `ropecast` executable. Each tools/cmd_*.cpp registers itself with a static
// CommandRegistration, so adding a command touches no other file. Main thread only.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "core/error.h"

namespace ropecast::tools {

// Adds the subcommand to `app` and returns the function to run when it was chosen (returns the exit code).
using CommandSetup = std::function<std::function<int()>(CLI::App& app)>;

struct CommandEntry {
  std::string name;
  int order;  // position in --help
  CommandSetup setup;
};

std::vector<CommandEntry>& commandRegistry();

struct CommandRegistration {
  CommandRegistration(std::string name, int order, CommandSetup setup) {
    commandRegistry().push_back({std::move(name), order, std::move(setup)});
  }
};

}  // namespace ropecast::tools
