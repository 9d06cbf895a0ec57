#!/usr/bin/env bash
# What a crop box or a clip plane saves (docs/BENCHMARKS.md "Cropping"): the same view of the CT-like store of
# converge_vs_sync.sh, whole, with --crop and with --clip-plane, synchronously and with --converge, each from a
# cold cache. Bricks wholly outside the box or behind the plane are culled by the refiner, so a cut reads and
# uploads what it keeps; with a pool that cannot hold the whole view, it also gets the detail the whole volume
# was refused for.
# Cuts: a slab of slices (Z 352..511, 160 of 864), the octant nearest the camera (its half of each axis), and
# the plane through the volume's center that keeps its upper half (z above the middle); with an isosurface, each
# cut also with --caps off (the surface left open where the cut cuts it: docs/RENDERING.md "Caps").
# Prints per run: wall seconds, frames, bricks in the working set, bricks uploaded, MiB read, leaves left coarser
# for want of pool slots, solid leaves (capped without a brick), and the ratios of wall time, bricks and bytes to
# the whole volume's.
# Usage: bench/crop.sh [BUILD_DIR]   (default build/perf)
# env: DIMS (1024x1024x864), ORBIT (30,20,1.6), IMAGE (512x512), GPU (256M), CPU (256M), REPS (1),
#      WORK (a folder kept between runs: the store is converted once), MODE_ARGS (--mode iso).
# The page cache is dropped before each render when the script runs as root ("cold"), else it is warm.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
. "$here/lib/common.sh"
bench_setup crop "${1:-build/perf}"
DIMS=${DIMS:-1024x1024x864}
GPU=${GPU:-256M}
CPU=${CPU:-256M}
ORBIT=${ORBIT:-30,20,1.6}
REPS=${REPS:-1}
MODE_ARGS=${MODE_ARGS:---mode iso}
store=$(ct_store "$DIMS")
IFS=x read -r nx ny nz <<<"$DIMS"
# The orbit's camera looks from +x, +y, +z (azimuth 30, elevation 20): the octant of the upper halves faces it.
read -r sx sy sz < <("$ROPECAST" info "$store" --json | python3 -c 'import json, sys; print(*json.load(sys.stdin)["spacing"])')
center=$(python3 -c "print(f'{$nx * $sx / 2:g},{$ny * $sy / 2:g},{$nz * $sz / 2:g}')")
declare -A cuts=([whole]="" [slab]="--crop :,:,352:512" [octant]="--crop $((nx / 2)):,$((ny / 2)):,$((nz / 2)):"
  [half]="--clip-plane $center,0,0,1")
names="whole slab octant half"
if [[ " $MODE_ARGS " == *" --mode iso "* ]]; then
  for name in slab octant half; do cuts[${name}_open]="${cuts[$name]} --caps off"; done
  names="$names slab_open octant_open half_open"
fi

echo "machine: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg); store $store ($(du -m "$store" | cut -f1) MiB)"
for rep in $(seq 1 "$REPS"); do
  for name in $names; do
    # shellcheck disable=SC2086  # the cut's options are words
    render_run "sync_${name}$rep" "$store" $MODE_ARGS --orbit "$ORBIT" --size "$IMAGE" --gpu-budget "$GPU" \
      --cpu-cache "$CPU" ${cuts[$name]}
    # shellcheck disable=SC2086
    render_run "converge_${name}$rep" "$store" $MODE_ARGS --orbit "$ORBIT" --size "$IMAGE" --gpu-budget "$GPU" \
      --cpu-cache "$CPU" ${cuts[$name]} --converge
  done
done

python3 - "$WORK" "$REPS" "$here/lib" $names <<'PY'
import sys
work, reps, names = sys.argv[1], int(sys.argv[2]), sys.argv[4:]
sys.path.insert(0, sys.argv[3])
from render_runs import load
print(f"{'run':<48} {'cache':<5} {'wall s':>7} {'frames':>6} {'working set':>11} {'bricks up':>9} {'MiB read':>8} "
      f"{'pool-full leaves':>16} {'solid':>6}   against the whole volume (wall, bricks up, MiB read)")
for rep in range(1, reps + 1):
    for kind in ("sync", "converge"):
        whole = load(work, f"{kind}_whole{rep}")
        for name in names:
            r = load(work, f"{kind}_{name}{rep}")
            ratio = "" if name == "whole" else (f"   {r['s'] / whole['s']:.2f}, {r['uploaded'] / whole['uploaded']:.2f}, "
                                                f"{r['read'] / whole['read']:.2f}")
            label = name.replace("_open", ", --caps off")
            print(f"{kind + ' ' + label:<48} {r['cache']:<5} {r['s']:7.2f} {r['frames']:6d} {r['working']:11d} "
                  f"{r['uploaded']:9d} {r['read']:8.1f} {r['poolFull']:16d} {r['solid']:6d}{ratio}")
PY
