#!/usr/bin/env bash
# Stepping through a gzip-compressed time series (docs/BENCHMARKS.md, "Compressed series"): a NIfTI .nii.gz of
# TIMES time points of SIZE^3 uint16 (a ball with noise, moving along z), written by a script and gzip.
# Per build, the wall seconds of `ropecast convert --time T` for the first, middle and last time point (each its
# own run), and of the viewer (under xvfb-run, a 64x64 view) shown every time point in turn by a script that
# waits for each to be converted and drawn, and of `ropecast render` (64x64) of every time point: by one run of
# `--times :` (where the build has it) and by a run of `--time T` each; with BEFORE_DIR's ropecast beside
# BUILD_DIR's when given (the same file, from the page cache).
# Usage: bench/gzip_series.sh [BUILD_DIR] [BEFORE_DIR]   (default build/perf; either a tools folder or a build)
# Environment: SIZE (256), TIMES (24), SCRATCH (a temporary directory).
set -euo pipefail
cd "$(dirname "$0")/.."
tool() { if [ -x "$1/tools/ropecast" ]; then realpath "$1/tools/ropecast"; else realpath "$1/ropecast"; fi; }
builds=("$(tool "${1:-build/perf}")")
[ -n "${2:-}" ] && builds+=("$(tool "$2")")
size=${SIZE:-256}
times=${TIMES:-24}
scratch=${SCRATCH:-$(mktemp -d /tmp/ropecast-gzip-series-XXXXXX)}
mkdir -p "$scratch"
trap 'rm -rf "$scratch"' EXIT
if ! command -v xvfb-run > /dev/null; then
  echo "gzip_series: needs xvfb-run (scripts/bootstrap installs it)" >&2
  exit 1
fi

python3 - "$scratch/series.nii" "$size" "$times" <<'PY'
import random, struct, sys
path, n, times = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
header = bytearray(348)
struct.pack_into("<i", header, 0, 348)
struct.pack_into("<8h", header, 40, 4, n, n, n, times, 1, 1, 1)
struct.pack_into("<hh", header, 70, 512, 16)
struct.pack_into("<8f", header, 76, 1, 1, 1, 1, 1, 1, 1, 1)
struct.pack_into("<f", header, 108, 352)
header[344:348] = b"n+1\0"
random.seed(1)
noise = [random.randrange(64) for _ in range(4096)]
c, slope = n // 2, 4000 / (0.3 * n)
profile = [max(0, int(4000 - slope * d2 ** 0.5)) for d2 in range(3 * n * n + 1)]
rows = []
for z in range(n):
    for y in range(n):
        d2 = (y - c) ** 2 + (z - c) ** 2
        rows.append(struct.pack("<%dH" % n, *[profile[d2 + (x - c) ** 2] + noise[(x + y * 7 + z * 13) % 4096]
                                              for x in range(n)]))
ball = b"".join(rows)
shift = 2 * n * n * max(1, n // (2 * times))  # the ball moves along z, a few slices per time point
with open(path, "wb") as out:
    out.write(bytes(header) + bytes(4))
    for t in range(times):
        at = (t * shift) % len(ball)
        out.write(ball[at:] + ball[:at])
PY
gzip -6 "$scratch/series.nii"
series="$scratch/series.nii.gz"
python3 - "$times" > "$scratch/steps.json" <<'PY'
import json, sys
events = []
for t in range(1, int(sys.argv[1])):
    events += [{"event": "set_time_point", "time_point": t}, {"event": "wait_converged"}]
print(json.dumps(events + [{"event": "quit"}]))
PY
echo "series: $series ($(du -h "$series" | cut -f1), $times time points of ${size}^3 uint16)"
seconds() { /usr/bin/time -f %e "$@" 2>&1 > /dev/null | tail -n 1; }
for tool in "${builds[@]}"; do
  line="$tool:"
  for t in 0 $((times / 2)) $((times - 1)); do
    line+=" convert --time $t $(seconds "$tool" convert -q "$series" --time "$t" -o "$scratch/t$t.rcv") s,"
  done
  view=$(seconds xvfb-run -a -s "-screen 0 320x240x24" "$tool" view "$series" --size 64x64 --iso 2000 \
    --script "$scratch/steps.json")
  line+=" view through $times time points $view s,"
  if "$tool" render --help | grep -q -- --times; then
    lapse=$(seconds "$tool" render "$series" --size 64x64 --iso 2000 --times : -o "$scratch/lapse.png" -q)
    line+=" render --times : $lapse s,"
  fi
  start=$(date +%s.%N)
  for ((t = 0; t < times; ++t)); do
    "$tool" render "$series" --size 64x64 --iso 2000 --time "$t" -o "$scratch/one.png" -q 2> /dev/null
  done
  echo "$line render --time T each $(python3 -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.2f}')" \
    "$start" "$(date +%s.%N)") s"
done
