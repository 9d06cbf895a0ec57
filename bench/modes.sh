#!/usr/bin/env bash
# The single-pass rope ray caster against the multi-pass block renderer (`ropecast bench modes`: the single
# pass with both entry points and --backend multipass on the same cut, camera path and transfer function,
# repetitions interleaved), iso, DVR and MIP, at each image size, on a store with thousands of data leaves in the
# cut: procedural:VOLUME:SIZE converted with BRICK-sample bricks (menger 256 with 16-sample bricks: 3785 data
# nodes, ~3300 data leaves in the cut at 512x512). Prints each run's table; the runs' bench.json,
# frame_times.png and images/ stay under WORK.
#
#   bench/modes.sh [BUILD_DIR]            (default build/perf)
#
# Environment: VOLUME (menger), SIZE (256), BRICK (16), IMAGES ("512x512 1024x1024"), MODES ("iso dvr mip"),
# FRAMES (4 along a 90-degree orbit), REPS (2), WORK (scratch dir; the store is converted once and reused),
# PLOT (1; 0 writes no frame_times.png, for a machine without matplotlib).
# DVR uses the ramp of bench/lib/common.sh from 127.5 up, so the sponge's holes are empty space; MIP its default
# (gray).
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/lib/common.sh
bench_setup modes "${1:-build/perf}"
VOLUME=${VOLUME:-menger}
BRICK=${BRICK:-16}
IMAGES=${IMAGES:-"512x512 1024x1024"}
MODES=${MODES:-"iso dvr mip"}
FRAMES=${FRAMES:-4}
REPS=${REPS:-2}

store="$WORK/${VOLUME}${SIZE}_b${BRICK}.rcast"
[ -f "$store" ] || "$ROPECAST" convert "procedural:$VOLUME:$SIZE" --brick "$BRICK" -o "$store" > /dev/null
write_ramp_tf "$WORK/tf_sparse.json" 127.5
for image in $IMAGES; do
  for mode in $MODES; do
    out="$WORK/${VOLUME}_${mode}_${image}"
    tf=()
    [ "$mode" = dvr ] && tf=(--tf "$WORK/tf_sparse.json")
    "$ROPECAST" bench modes "$store" --mode "$mode" "${tf[@]}" --size "$image" \
      --frames "$FRAMES" --reps "$REPS" --out "$out" --quiet $([ "${PLOT:-1}" = 0 ] && echo --no-plot)
    echo
  done
done
echo "modes: results under $WORK"
