#!/usr/bin/env python3
"""Two builds of ropecast side by side on the same renders (docs/BENCHMARKS.md "Comparing two builds").

Each case is one `ropecast render ... --stats`, run by both builds in turn, the order alternating between
repetitions so that a drifting machine affects both alike. Per case and build, medians over the repetitions:
wall seconds, frames, the frames' own seconds (sum of frame_ms), the occlusion queries' draws (sum of
occlusion_draw_ms, and the last frame's), queries issued, the working set of the last frame, the last drawn
frame's milliseconds and the peak resident memory; then the ratios B / A of wall seconds, frames' seconds,
query draws, last frame and peak memory.

Usage: bench/compare_builds.py A_ROPECAST B_ROPECAST --case 'NAME: INPUT RENDER-OPTIONS' [--case ...]
       [--reps N] [--cold]
  --cold  drop the page cache before every render (needs root; otherwise the input is read once to warm it)
Example, the build before a change against this one:
  git worktree add /tmp/before HEAD~1 && (cd /tmp/before && cmake --preset perf &&
      cmake --build build/perf --target ropecast)
  bench/compare_builds.py /tmp/before/build/perf/tools/ropecast build/perf/tools/ropecast \\
      --case 'iso: STORE --mode iso --size 1024x1024 --orbit 30,20,1.6 --converge'
"""
import argparse
import json
import os
import shlex
import statistics
import subprocess
import sys
import tempfile
import time


def parse_case(text):
    name, sep, args = text.partition(":")
    if not sep or not name.strip() or not args.strip():
        raise argparse.ArgumentTypeError(f"--case '{text}': expected 'NAME: INPUT RENDER-OPTIONS'")
    return name.strip(), shlex.split(args)


def run(ropecast, args, cold, work):
    if cold:
        subprocess.run("sync && echo 3 > /proc/sys/vm/drop_caches", shell=True, check=True)
    elif os.path.isfile(args[0]):
        with open(args[0], "rb") as f:  # warm: the same page cache for both builds
            while f.read(1 << 24):
                pass
    stats = os.path.join(work, "stats.jsonl")
    start = time.monotonic()
    child = subprocess.Popen([ropecast, "render", *args, "--stats", stats, "-o", os.path.join(work, "image.png")],
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    stderr = child.stderr.read()
    _, status, usage = os.wait4(child.pid, 0)  # the child's own peak resident memory
    child.returncode = os.waitstatus_to_exitcode(status)
    wall = time.monotonic() - start
    if child.returncode != 0:
        sys.exit(f"compare_builds: {ropecast} render {' '.join(args)} failed:\n{stderr}")
    with open(stats) as f:
        rows = [json.loads(line) for line in f]
    return {
        "wall s": wall,
        "frames": len(rows),
        "frames' s": sum(r["frame_ms"] for r in rows) / 1000,
        "query draws s": sum(r.get("occlusion_draw_ms", 0.0) for r in rows) / 1000,
        "last draw ms": rows[-1].get("occlusion_draw_ms", 0.0),
        "queries": sum(r.get("occlusion_queries", 0) for r in rows),
        "working set": rows[-1]["working_set_bricks"],
        "last frame ms": next((r["frame_ms"] for r in reversed(rows) if r.get("drawn", True)), 0.0),
        "peak MiB": usage.ru_maxrss / 1024,  # KiB on Linux
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("a")
    parser.add_argument("b")
    parser.add_argument("--case", type=parse_case, action="append", required=True)
    parser.add_argument("--reps", type=int, default=3)
    parser.add_argument("--cold", action="store_true")
    opts = parser.parse_args()
    for build in (opts.a, opts.b):
        if not os.access(build, os.X_OK):
            sys.exit(f"compare_builds: {build} is not an executable")
    if opts.reps < 1:
        sys.exit("compare_builds: --reps must be at least 1")
    os.environ.setdefault("EGL_PLATFORM", "surfaceless")

    results = {}
    with tempfile.TemporaryDirectory(prefix="compare_builds.") as work:
        for rep in range(opts.reps):
            for name, args in opts.case:
                for label in ("A", "B") if rep % 2 == 0 else ("B", "A"):
                    build = opts.a if label == "A" else opts.b
                    print(f"compare_builds: {name}, {label}, repetition {rep + 1}", file=sys.stderr)
                    results.setdefault((name, label), []).append(run(build, args, opts.cold, work))

    keys = ["wall s", "frames", "frames' s", "query draws s", "last draw ms", "queries", "working set",
            "last frame ms", "peak MiB"]
    print(f"A = {opts.a}\nB = {opts.b}\nmedians of {opts.reps} ({'cold' if opts.cold else 'warm'} page cache)")
    print(f"{'case':<24}" + "".join(f"{k:>15}" for k in keys))
    for name, _ in opts.case:
        med = {label: {k: statistics.median(r[k] for r in results[(name, label)]) for k in keys}
               for label in ("A", "B")}
        for label in ("A", "B"):
            print(f"{name + ' ' + label:<24}" + "".join(f"{med[label][k]:>15.3f}" for k in keys))
        ratios = [f"{k} {med['B'][k] / med['A'][k]:.2f}"
                  for k in ("wall s", "frames' s", "query draws s", "last frame ms", "peak MiB")
                  if med["A"][k] > 0]
        print(f"{name + ' B/A':<24}  " + ", ".join(ratios))


if __name__ == "__main__":
    main()
