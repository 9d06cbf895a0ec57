// `ropecast bench NAME [options]`: benchmarks measured in one run and printed as figures and ratios (never a
// timed test). Each benchmark is one row of kBenchmarks: its name, a line of help, and a setup function that
// adds its options and returns the function that runs it. Add a benchmark by adding a row. Main thread only.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numeric>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/elapsed.h"
#include "index/random_cut.h"
#include "index/rope_index.h"
#include "index/rope_traversal.h"
#include "tools/cli_checks.h"
#include "tools/cli_values.h"
#include "tools/command.h"
#ifdef ROPECAST_HAVE_GL
#include "tools/bench_modes.h"
#endif

namespace ropecast::tools {
namespace {

struct Benchmark {
  const char* name;
  const char* description;
  CommandSetup setup;
};

struct TimingMs {
  double min, median, mean, max;
};

TimingMs summarize(std::vector<double> samplesMs) {
  std::sort(samplesMs.begin(), samplesMs.end());
  const double sum = std::accumulate(samplesMs.begin(), samplesMs.end(), 0.0);
  const size_t n = samplesMs.size();
  const double median = n % 2 ? samplesMs[n / 2] : 0.5 * (samplesMs[n / 2 - 1] + samplesMs[n / 2]);
  return {samplesMs.front(), median, sum / double(n), samplesMs.back()};
}

template <typename F>
std::vector<double> timeRepeatedMs(uint32_t repeats, F&& body) {
  std::vector<double> samplesMs;
  samplesMs.reserve(repeats);
  for (uint32_t i = 0; i < repeats; ++i) {
    const auto start = SteadyClock::now();
    body();
    samplesMs.push_back(millisecondsSince(start));
  }
  return samplesMs;
}

void printTiming(const char* what, uint32_t repeats, const TimingMs& t) {
  std::printf("  %-34s x%-5u min %8.4f ms  median %8.4f ms  mean %8.4f ms  max %8.4f ms\n", what, repeats,
              t.min, t.median, t.mean, t.max);
}

// bench index: build the rope index over a random cut of about N leaves, K times, with a reused builder (as
// the renderer does every frame) and one-shot; then walk rays through it with the CPU reference traversal.
std::function<int()> setupIndexBench(CLI::App& app) {
  struct Options {
    uint32_t leaves = 10000;
    uint32_t frames = 200;
    uint32_t maxDepth = 10;
    float emptyFraction = 0.3f;
    uint64_t seed = 1;
    uint32_t rays = 100000;
    double goalMs = 1.0;
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  // A leaf costs the cut, the index and the traversal test about 230 bytes: 10 million take over 2 GiB.
  app.add_option("--leaves", options->leaves, "leaves in the random cut (at least this many)")
      ->capture_default_str()
      ->transform(integerRange(1, 10000000));
  app.add_option("--frames", options->frames, "builds to time")
      ->capture_default_str()
      ->transform(integerRange(1, 1000000));
  app.add_option("--max-depth", options->maxDepth, "deepest leaf of the random cut")
      ->capture_default_str()
      ->transform(integerRange(0, kCutMaxDepth));
  app.add_option("--empty-fraction", options->emptyFraction, "share of Empty leaves")
      ->capture_default_str()
      ->check(finiteIn(0.0, 1.0));
  app.add_option("--seed", options->seed, "random cut seed")->capture_default_str();
  app.add_option("--rays", options->rays, "rays walked by the CPU reference traversal (0: skip)")
      ->capture_default_str();
  app.add_option("--goal-ms", options->goalMs, "build time goal per frame")
      ->capture_default_str()
      ->check(finiteIn(0.0, HUGE_VAL));
  app.add_flag("--json", options->json, "also print the figures as one JSON line");

  return [options]() -> int {
    const Options& o = *options;
    RandomCutParams params;
    params.seed = o.seed;
    params.targetLeaves = o.leaves;
    params.maxDepth = o.maxDepth;
    params.emptyFraction = o.emptyFraction;
    const Cut cut = makeRandomCut(params);
    if (cut.leaves.size() < o.leaves)  // the tree of --max-depth holds fewer leaves
      std::fprintf(stderr,
                   "ropecast bench index: warning: --max-depth %u gives %zu leaves, fewer than --leaves %u\n",
                   o.maxDepth, cut.leaves.size(), o.leaves);

    RopeIndexBuilder builder;
    RopeIndex index;
    builder.build(cut, index);  // warm-up: grows the buffers once
    const TimingMs reused = summarize(timeRepeatedMs(o.frames, [&] { builder.build(cut, index); }));
    const TimingMs fresh = summarize(timeRepeatedMs(o.frames, [&] {
      RopeIndex oneShot = buildRopeIndex(cut);
      if (oneShot.texels.empty()) std::abort();
    }));

    std::printf(
        "bench index: %zu leaves (max depth %u, leaf depth <= %u, %.0f%% empty), %u nodes, %zu texels = "
        "%llu bytes\n",
        cut.leaves.size(), index.maxDepth, o.maxDepth, 100.0 * o.emptyFraction, index.nodeCount,
        index.texels.size(), (unsigned long long)index.bytes());
    printTiming("build, builder reused (per frame)", o.frames, reused);
    printTiming("build, one-shot buildRopeIndex", o.frames, fresh);
    const double nsPerLeaf = reused.median * 1e6 / double(cut.leaves.size());
    std::printf("  per leaf: %.1f ns (median build)\n", nsPerLeaf);
    std::printf("  goal: <= %.3f ms per build at %zu leaves: %s (median %.4f ms, ratio goal/median %.1fx)\n",
                o.goalMs, cut.leaves.size(), reused.median <= o.goalMs ? "met" : "NOT met", reused.median,
                o.goalMs / reused.median);

    // CPU reference traversal: rays from a sphere around the cube through random points inside it.
    double leavesPerRay = 0.0, raysPerSecond = 0.0;
    if (o.rays > 0) {
      uint64_t state = o.seed * 0x9E3779B97F4A7C15ull + 1;
      auto uniform = [&state] {  // xorshift: cheap and reproducible
        state ^= state << 13, state ^= state >> 7, state ^= state << 17;
        return float(state >> 40) / float(1 << 24);
      };
      uint64_t visited = 0;
      const auto start = SteadyClock::now();
      for (uint32_t r = 0; r < o.rays; ++r) {
        const glm::vec3 target(uniform(), uniform(), uniform());
        const glm::vec3 origin = glm::vec3(uniform(), uniform(), uniform()) * 4.0f - 1.5f;
        RopeCursor cursor;
        RopeLeaf leaf;
        if (!ropeBegin(cursor, index, origin, target - origin, 0.0f, 1e30f)) continue;
        while (ropeNextLeaf(cursor, index, leaf)) ++visited;
      }
      const double seconds = secondsSince(start);
      leavesPerRay = double(visited) / double(o.rays);
      raysPerSecond = double(o.rays) / seconds;
      std::printf("  CPU reference traversal: %u rays, %.1f leaves/ray, %.2f M rays/s, %.1f ns/leaf\n",
                  o.rays, leavesPerRay, raysPerSecond * 1e-6,
                  seconds * 1e9 / double(std::max<uint64_t>(visited, 1)));
    }

    if (o.json) {
      nlohmann::json j = {
          {"bench", "index"},
          {"leaves", cut.leaves.size()},
          {"nodes", index.nodeCount},
          {"texels", index.texels.size()},
          {"bytes", index.bytes()},
          {"frames", o.frames},
          {"build_reused_ms", {{"min", reused.min}, {"median", reused.median}, {"mean", reused.mean}}},
          {"build_oneshot_ms", {{"min", fresh.min}, {"median", fresh.median}, {"mean", fresh.mean}}},
          {"goal_ms", o.goalMs},
          {"goal_met", reused.median <= o.goalMs},
          {"traversal_rays_per_s", raysPerSecond},
          {"traversal_leaves_per_ray", leavesPerRay}};
      std::printf("%s\n", j.dump().c_str());
    }
    return 0;
  };
}

const Benchmark kBenchmarks[] = {
    {"index", "rope index build time over a random cut (goal: 10 000 leaves in <= 1 ms), CPU traversal speed",
     setupIndexBench},
#ifdef ROPECAST_HAVE_GL
    {"modes",
     "single-pass ray casting against the multi-pass block renderer (and the other entry point) on one input "
     "and "
     "camera path: bench.json, frame_times.png, images/, a table",
     setupModesBench},
#endif
};

const CommandRegistration benchCommand("bench", 80, [](CLI::App& app) -> std::function<int()> {
  app.description("benchmarks, measured side by side in one run (see docs/BENCHMARKS.md)");
  app.require_subcommand(1);
  auto runs = std::make_shared<std::vector<std::pair<CLI::App*, std::function<int()>>>>();
  for (const Benchmark& benchmark : kBenchmarks) {
    CLI::App* sub = app.add_subcommand(benchmark.name, benchmark.description);
    runs->emplace_back(sub, benchmark.setup(*sub));
  }
  return [runs]() -> int {
    for (auto& [sub, run] : *runs)
      if (sub->parsed()) return run();
    return 1;
  };
});

}  // namespace
}  // namespace ropecast::tools
