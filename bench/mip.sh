#!/usr/bin/env bash
# What a maximum intensity projection loads and draws beside the isosurface and DVR (docs/BENCHMARKS.md
# "Maximum intensity projection"): the view of converge_vs_sync.sh (the CT-like store, --orbit 30,20,1.6) in
# each mode, synchronously and with --converge, each from a cold cache. A MIP's rays cross the whole volume
# (no early ray termination) and hide nothing (no occlusion queries), so it reads every non-empty node the view
# asks for; its empty nodes are those whose maximum lies below the transfer function's first opacity.
# Prints per run: wall seconds, frames, bricks in the working set, bricks uploaded, MiB read, leaves left coarser
# for want of pool slots, occlusion queries drawn, and the ratios of wall time, bricks and bytes to the iso run's.
# Usage: bench/mip.sh [BUILD_DIR]   (default build/perf)
# env: DIMS (1024x1024x864), ORBIT (30,20,1.6), IMAGE (512x512), GPU (256M), CPU (256M), REPS (1),
#      DVR_TF (ct-bone), WORK (a folder kept between runs: the store is converted once).
# The page cache is dropped before each render when the script runs as root ("cold"), else it is warm.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
. "$here/lib/common.sh"
bench_setup mip "${1:-build/perf}"
DIMS=${DIMS:-1024x1024x864}
GPU=${GPU:-256M}
CPU=${CPU:-256M}
ORBIT=${ORBIT:-30,20,1.6}
REPS=${REPS:-1}
DVR_TF=${DVR_TF:-ct-bone}
store=$(ct_store "$DIMS")
declare -A modes=([iso]="--mode iso" [dvr]="--mode dvr --tf $DVR_TF" [mip]="--mode mip")

echo "machine: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg); store $store ($(du -m "$store" | cut -f1) MiB)"
for rep in $(seq 1 "$REPS"); do
  for mode in iso dvr mip; do
    # shellcheck disable=SC2086  # the mode's options are words
    render_run "sync_${mode}$rep" "$store" ${modes[$mode]} --orbit "$ORBIT" --size "$IMAGE" --gpu-budget "$GPU" \
      --cpu-cache "$CPU"
    # shellcheck disable=SC2086
    render_run "converge_${mode}$rep" "$store" ${modes[$mode]} --orbit "$ORBIT" --size "$IMAGE" \
      --gpu-budget "$GPU" --cpu-cache "$CPU" --converge
  done
done

python3 - "$WORK" "$REPS" "$here/lib" "$DVR_TF" <<'PY'
import sys
work, reps, tf = sys.argv[1], int(sys.argv[2]), sys.argv[4]
sys.path.insert(0, sys.argv[3])
from render_runs import load
labels = {"iso": "iso", "dvr": f"dvr --tf {tf}", "mip": "mip (gray)"}
print(f"{'run':<28} {'cache':<5} {'wall s':>7} {'frames':>6} {'working set':>11} {'bricks up':>9} {'MiB read':>8} "
      f"{'pool-full leaves':>16} {'queries':>8}   against iso (wall, bricks up, MiB read)")
for rep in range(1, reps + 1):
    for kind in ("sync", "converge"):
        iso = load(work, f"{kind}_iso{rep}")
        for mode in ("iso", "dvr", "mip"):
            r = load(work, f"{kind}_{mode}{rep}")
            ratio = "" if mode == "iso" else (f"   {r['s'] / iso['s']:.2f}, {r['uploaded'] / iso['uploaded']:.2f}, "
                                              f"{r['read'] / iso['read']:.2f}")
            print(f"{kind + ' ' + labels[mode]:<28} {r['cache']:<5} {r['s']:7.2f} {r['frames']:6d} {r['working']:11d} "
                  f"{r['uploaded']:9d} {r['read']:8.1f} {r['poolFull']:16d} {r['queries']:8d}{ratio}")
PY
