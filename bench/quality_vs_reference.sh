#!/usr/bin/env bash
# Image quality of the adaptive ray caster: PSNR of `ropecast render --voxels-per-pixel 1` (coarser levels
# where a voxel projects below a pixel) against `--reference` (CPU brute-force ray marching of the full-
# resolution data, no octree) for the same camera, on ~256^3 volumes, iso and DVR. Goal >= 35 dB.
#
#   bench/quality_vs_reference.sh [BUILD_DIR]       (default build/perf)
#
# Environment: VOLUMES (default "marschner-lobb noise"), SIZE (256), IMAGE (512x512), VPP (1), WORK.
set -euo pipefail
VOLUMES=${VOLUMES:-"marschner-lobb noise"}
VPP=${VPP:-1}
cd "$(dirname "$0")/.."
source bench/lib/common.sh
bench_setup quality_vs_reference "${1:-build/perf}"
write_ramp_tf "$WORK/tf.json"

printf '%-15s %-4s %8s %10s %10s %8s\n' volume mode psnr_db max_abs mean_abs leaves
for name in $VOLUMES; do
  store=$WORK/$name.rcast
  [ -f "$store" ] || "$ROPECAST" convert "procedural:$name:$SIZE" -o "$store" -q
  for mode in iso dvr; do
    args=(--size "$IMAGE" --mode "$mode" --iso 127.5)
    [ "$mode" = dvr ] && args=(--size "$IMAGE" --mode dvr --tf "$WORK/tf.json")
    "$ROPECAST" render "$store" "${args[@]}" --voxels-per-pixel "$VPP" --stats "$WORK/$name-$mode.jsonl" \
      -o "$WORK/$name-$mode-adaptive.png"
    "$ROPECAST" render "$store" "${args[@]}" --reference -o "$WORK/$name-$mode-reference.png"
    leaves=$(python3 -c 'import json,sys; print(json.loads(open(sys.argv[1]).readline())["leaves"])' \
      "$WORK/$name-$mode.jsonl")
    "$ROPECAST" compare "$WORK/$name-$mode-adaptive.png" "$WORK/$name-$mode-reference.png" |
      python3 -c 'import json,sys; d=json.loads(sys.stdin.read()); print("%-15s %-4s %8.2f %10.4f %10.5f %8s" % (sys.argv[1], sys.argv[2], float(d["psnr_db"]), d["max_abs"], d["mean_abs"], sys.argv[3]))' \
      "$name" "$mode" "$leaves"
  done
done
echo "images in $WORK (*-adaptive.png, *-reference.png)"
