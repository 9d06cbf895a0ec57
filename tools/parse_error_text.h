// A command-line parse error in ropecast's words, for main() to print after "ropecast: error: ": the option
// first, then what was expected and what was given ("--orbit: expected 3 values separated by ',', got 2"), an
// unknown option with those it may have been meant for ("unknown option --voxel-per-pixel (did you mean
// --voxels-per-pixel?)"); CLI11's own text where it has no better one. Main thread.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace ropecast::tools {

// The message for `error`, thrown by app.parse() (one line).
std::string parseErrorText(const CLI::App& app, const CLI::ParseError& error);

// The command app.parse() was parsing ("ropecast bench modes"), whose --help lists its options.
std::string parsedCommandPath(const CLI::App& app);

// The long options of `options` that `given` (an option as typed, "--voxel-per-pixel" or "--iso=3") was
// probably meant to be: those within a small edit distance of it, or that it begins; nearest first, at most
// three.
std::vector<std::string> likelyMeant(const std::string& given, const std::vector<std::string>& options);

}  // namespace ropecast::tools
