#!/usr/bin/env bash
# What a slice reads (docs/BENCHMARKS.md "Slices"): the same view of the CT-like store of converge_vs_sync.sh as
# a MIP (which reads every brick in view that holds a value), a DVR, slices (--mode slice: the default axial
# plane through the center, an oblique plane through it, and the axial plane seen from above with --view
# superior) and a MIP of the slab of SLAB world units about the middle slice (--slab), synchronously and with
# --converge, each from a cold cache. The refiner keeps only the nodes a slice's plane crosses, or a slab's
# faces bound, so a slice reads and uploads the bricks of its plane, at the level the view needs there.
# Prints per run: wall seconds, frames, bricks in the working set, bricks uploaded, MiB read, and the ratios of
# wall time, bricks uploaded and bytes read to the MIP's.
# Usage: bench/slice.sh [BUILD_DIR]   (default build/perf)
# env: DIMS (1024x1024x864), ORBIT (30,20,1.6), IMAGE (512x512), GPU (256M), CPU (256M), REPS (1), SLAB (40),
#      WORK (a folder kept between runs: the store is converted once).
# The page cache is dropped before each render when the script runs as root ("cold"), else it is warm.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
. "$here/lib/common.sh"
bench_setup slice "${1:-build/perf}"
DIMS=${DIMS:-1024x1024x864}
GPU=${GPU:-256M}
CPU=${CPU:-256M}
ORBIT=${ORBIT:-30,20,1.6}
REPS=${REPS:-1}
SLAB=${SLAB:-40}
store=$(ct_store "$DIMS")
IFS=x read -r nx ny nz <<<"$DIMS"
read -r sx sy sz < <("$ROPECAST" info "$store" --json | python3 -c 'import json, sys; print(*json.load(sys.stdin)["spacing"])')
center=$(python3 -c "print(f'{$nx * $sx / 2:g},{$ny * $sy / 2:g},{$nz * $sz / 2:g}')")
declare -A views=([dvr]="--mode dvr --tf ct-soft --orbit $ORBIT" [mip]="--mode mip --orbit $ORBIT"
  [axial]="--mode slice --orbit $ORBIT" [oblique]="--mode slice --orbit $ORBIT --clip-plane $center,1,0.5,0.8"
  [from_above]="--mode slice --view superior" [slab]="--mode mip --orbit $ORBIT --slice z:$((nz / 2)) --slab $SLAB")
names="mip dvr axial oblique from_above slab"

echo "machine: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg); store $store ($(du -m "$store" | cut -f1) MiB)"
for rep in $(seq 1 "$REPS"); do
  for name in $names; do
    # shellcheck disable=SC2086  # the view's options are words
    render_run "sync_${name}$rep" "$store" ${views[$name]} --size "$IMAGE" --gpu-budget "$GPU" --cpu-cache "$CPU"
    # shellcheck disable=SC2086
    render_run "converge_${name}$rep" "$store" ${views[$name]} --size "$IMAGE" --gpu-budget "$GPU" \
      --cpu-cache "$CPU" --converge
  done
done

python3 - "$WORK" "$REPS" "$here/lib" $names <<'PY'
import sys
work, reps, names = sys.argv[1], int(sys.argv[2]), sys.argv[4:]
sys.path.insert(0, sys.argv[3])
from render_runs import load
print(f"{'run':<28} {'cache':<5} {'wall s':>7} {'frames':>6} {'working set':>11} {'bricks up':>9} {'MiB read':>8}"
      f"   against the MIP (wall, bricks up, MiB read)")
for rep in range(1, reps + 1):
    for kind in ("sync", "converge"):
        mip = load(work, f"{kind}_mip{rep}")
        for name in names:
            r = load(work, f"{kind}_{name}{rep}")
            ratio = "" if name == "mip" else (f"   {r['s'] / mip['s']:.2f}, {r['uploaded'] / mip['uploaded']:.2f}, "
                                              f"{r['read'] / mip['read']:.2f}")
            print(f"{kind + ' ' + name:<28} {r['cache']:<5} {r['s']:7.2f} {r['frames']:6d} {r['working']:11d} "
                  f"{r['uploaded']:9d} {r['read']:8.1f}{ratio}")
PY
