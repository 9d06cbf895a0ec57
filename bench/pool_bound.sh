#!/usr/bin/env bash
# Convergence when the GPU pool only just holds the view, or cannot (docs/BENCHMARKS.md "Visibility"): with
# occlusion queries and ray feedback on (the defaults), `render --converge` from a cold cache must settle on one
# cut instead of swapping nodes between frames. Views: procedural:menger:SIZE, iso and DVR (semi-transparent
# ramp) from one camera and iso from a nearer one, at --gpu-budget 1G, 64M and 32M; the CT-like store of
# converge_vs_sync.sh, iso, two cameras, at 256M and 128M.
# Prints per view: converged or not within MAX_FRAMES, frames, working set, bricks uploaded in all and in the
# last frames (what a still view keeps uploading), seconds. Exits non-zero when a view did not converge.
# Usage: bench/pool_bound.sh [BUILD_DIR]   (default build/perf)
# env: SIZE (729), DIMS (the CT store, 1024x1024x864), IMAGE (512x512), MAX_FRAMES (80), WORK (a folder kept
#      between runs: the stores are converted once).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
. "$here/lib/common.sh"
SIZE=${SIZE:-729}
bench_setup pool_bound "${1:-build/perf}"
DIMS=${DIMS:-1024x1024x864}
MAX_FRAMES=${MAX_FRAMES:-80}

menger="$WORK/menger$SIZE.rcast"
[ -f "$menger" ] || "$ROPECAST" convert "procedural:menger:$SIZE" -o "$menger" --quiet
ct=$(ct_store "$DIMS")
printf '{"points": [[0, 0.0, 0.0, 0.0, 0.0], [100, 0.9, 0.6, 0.3, 0.0], [255, 1.0, 0.9, 0.7, 0.3]]}\n' \
  >"$WORK/semi.json"

views=()
# view NAME STORE GPU ORBIT MODE_ARGS...: renders to convergence, stats in WORK/NAME.jsonl
view() {
  local name=$1 store=$2 gpu=$3 orbit=$4
  shift 4
  echo "pool_bound.sh: $name" >&2
  local t0 t1
  t0=$(date +%s.%N)
  "$ROPECAST" render "$store" "$@" --size "$IMAGE" --orbit "$orbit" --converge --max-frames "$MAX_FRAMES" \
    --gpu-budget "$gpu" --cpu-cache 1G --stats "$WORK/$name.jsonl" -o "$WORK/$name.png" 2>"$WORK/$name.log" ||
    true  # a view that does not converge says so in its stats
  t1=$(date +%s.%N)
  awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.1f\n", b - a }' >"$WORK/$name.s"
  views+=("$name")
}
for gpu in 1G 64M 32M; do
  view "menger_iso_$gpu" "$menger" "$gpu" 30,20,1.6 --mode iso
  view "menger_dvr_$gpu" "$menger" "$gpu" 30,20,1.6 --mode dvr --tf "$WORK/semi.json" --gradients computed
  view "menger_iso_near_$gpu" "$menger" "$gpu" 60,30,0.9 --mode iso
done
for gpu in 256M 128M; do
  view "ct_iso_$gpu" "$ct" "$gpu" 30,20,1.6 --mode iso
  view "ct_iso_near_$gpu" "$ct" "$gpu" 120,10,0.8 --mode iso
done

python3 - "$WORK" "${views[@]}" <<'PY'
import json, sys
work, names = sys.argv[1], sys.argv[2:]
print(f"{'view':<22} {'converged':>9} {'frames':>6} {'working set':>11} {'uploaded':>8}  {'last 5 frames uploaded':<24} {'s':>5}")
failed = 0
for name in names:
    rows = [json.loads(l) for l in open(f"{work}/{name}.jsonl")]
    converged = rows[-1]["converged"]
    failed += not converged
    tail = [r["bricks_uploaded"] for r in rows[-5:]]
    print(f"{name:<22} {str(converged):>9} {len(rows):6d} {rows[-1]['working_set_bricks']:11d} "
          f"{sum(r['bricks_uploaded'] for r in rows):8d}  {str(tail):<24} {open(f'{work}/{name}.s').read().strip():>5}")
sys.exit(1 if failed else 0)
PY
