// `ropecast bench modes`: the single-pass ray caster against the multi-pass block renderer (and the single
// pass's other entry point) on the same input, transfer function and camera path, side by side in one run
// (tools/gl_cmd_bench_modes.cpp; docs/BENCHMARKS.md). Registered by tools/cmd_bench.cpp in GL builds. Main
// thread only.
#pragma once

#include <functional>

#include <CLI/CLI.hpp>

namespace ropecast::tools {

// Adds the benchmark's options to `app`; returns the function that runs it.
std::function<int()> setupModesBench(CLI::App& app);

}  // namespace ropecast::tools
