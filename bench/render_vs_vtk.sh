#!/usr/bin/env bash
# Frame time of `ropecast render` against VTK's vtkGPUVolumeRayCastMapper (bench/vtk_raycast.py, offscreen
# under xvfb-run) on exactly the same ~256^3 uint8 volume, image size, camera orbit, half-voxel step,
# isovalue and transfer function, measured in one run; prints the medians and the ratios VTK / ropecast.
#
#   bench/render_vs_vtk.sh [BUILD_DIR]            (default build/perf)
#
# Environment: VOLUMES (procedural names, default "marschner-lobb noise"), SIZE (volume edge, 256),
# IMAGE (512x512), FRAMES (measured frames per renderer, 20), WORK (scratch dir, default a temp dir kept for
# the screenshots), LP_NUM_THREADS (passed through to both renderers' llvmpipe).
#
# The volume is written once by `ropecast convert procedural:NAME:SIZE` and its level 0 extracted to a raw for
# VTK, so both render the same bytes. ropecast renders FRAMES frames on an orbit (--path: a few still frames
# first while the working set loads, then one degree of azimuth per frame, so nothing is reused between
# frames); only frames with no upload and nothing pending are counted. VTK turns one degree per frame too and
# ends on the same azimuth, so the last frames of both (saved as PNGs in WORK) show the same view.
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/lib/common.sh
bench_setup render_vs_vtk "${1:-build/perf}"
VOLUMES=${VOLUMES:-"marschner-lobb noise"}
FRAMES=${FRAMES:-20}
STILL=${STILL:-6}     # ropecast frames at the first camera while the working set loads
VTK_WARMUP=3
AZ=30 EL=20 DIST=3 FOV=40
if ! command -v xvfb-run > /dev/null || ! /usr/bin/python3 -c 'import vtk' 2> /dev/null; then
  echo "render_vs_vtk: needs xvfb-run and python3-vtk9; run scripts/bootstrap --bench" >&2
  exit 1
fi

# DVR transfer function in stored units (uint8 procedural data: data units = stored units): the "linear"
# preset's ramp, written out so VTK reads the very same points.
write_ramp_tf "$WORK/tf.json"
last=$((STILL + FRAMES - 1))
cat > "$WORK/path.json" <<EOF
[{"orbit": [$AZ, $EL, $DIST], "fov": $FOV, "time": 0},
 {"orbit": [$AZ, $EL, $DIST], "fov": $FOV, "time": $STILL},
 {"orbit": [$((AZ + FRAMES - 1)), $EL, $DIST], "fov": $FOV, "time": $last}]
EOF

median_of() {  # median_of STATS FIELD: median over steady frames (nothing uploaded, nothing pending)
  python3 - "$1" "$2" <<'EOF'
import json, statistics, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
steady = [r for r in rows if r["bricks_uploaded"] == 0 and r["requests_pending"] == 0]
if len(steady) < 5:
    sys.exit("render_vs_vtk: only %d steady frames of %d" % (len(steady), len(rows)))
print("%.2f" % statistics.median(r[sys.argv[2]] for r in steady))
EOF
}
vtk_median() { python3 -c 'import json,sys; print("%.2f" % json.loads(sys.stdin.read().strip().splitlines()[-1])["median_ms"])'; }

printf '%-16s %-4s %12s %12s %12s %9s %9s\n' volume mode rc_raycast rc_frame vtk_frame "vtk/rc_rc" "vtk/rc_fr"
for name in $VOLUMES; do
  store=$WORK/$name.rcast raw=$WORK/$name.raw
  if [ ! -f "$store" ]; then
    "$ROPECAST" convert "procedural:$name:$SIZE" -o "$store" -q
    "$ROPECAST" extract "$store" --level 0 -o "$raw" -q
  fi
  for mode in iso dvr; do
    common=(--size "$IMAGE" --step 0.5)  # the path gives the fov
    if [ "$mode" = iso ]; then rcmode=(--mode iso --iso 127.5); vtkmode=(--mode iso --iso 127.5)
    else rcmode=(--mode dvr --tf "$WORK/tf.json"); vtkmode=(--mode dvr --tf "$WORK/tf.json"); fi
    "$ROPECAST" render "$store" "${rcmode[@]}" "${common[@]}" --path "$WORK/path.json" --frames $((last + 1)) \
      --stats "$WORK/$name-$mode.jsonl" -o "$WORK/$name-$mode-ropecast.png"
    rc_ray=$(median_of "$WORK/$name-$mode.jsonl" raycast_ms)
    rc_frame=$(median_of "$WORK/$name-$mode.jsonl" frame_ms)
    vtk=$(xvfb-run -a /usr/bin/python3 bench/vtk_raycast.py "$raw" --dims "$SIZE,$SIZE,$SIZE" "${vtkmode[@]}" \
      --size "$IMAGE" --orbit "$((AZ - VTK_WARMUP)),$EL,$DIST" --fov "$FOV" --frames "$FRAMES" \
      --warmup "$VTK_WARMUP" --screenshot "$WORK/$name-$mode-vtk.png" | vtk_median)
    printf '%-16s %-4s %9s ms %9s ms %9s ms %8.2fx %8.2fx\n' "$name" "$mode" "$rc_ray" "$rc_frame" "$vtk" \
      "$(echo "$vtk / $rc_ray" | bc -l)" "$(echo "$vtk / $rc_frame" | bc -l)"
  done
done
echo "screenshots and stats in $WORK (*-ropecast.png, *-vtk.png: the same last frame)"
