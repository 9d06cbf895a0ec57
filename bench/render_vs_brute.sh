#!/usr/bin/env bash
# ropecast's ray caster against a brute-force single-3D-texture ray caster (`ropecast render --backend brute`:
# level 0 in one texture, every ray marched entry to exit at half a voxel, no index) on the same in-core
# volume, image size and camera orbit, measured in one run; prints median ray-cast times and the ratios
# brute / ropecast (> 1: ropecast is faster). Both run in the same shader stage unless told otherwise, so that
# the ratio compares the two methods rather than a fragment and a compute shader.
#
#   bench/render_vs_brute.sh [BUILD_DIR]            (default build/perf)
#
# Two ropecast figures per case: "full" refines to level 0 everywhere (--voxels-per-pixel 64: the same
# samples as brute force, so the ratio is the cost or gain of the index and of skipping empty leaves) and
# "adaptive" at --voxels-per-pixel 1 (the method: coarser levels where a voxel is smaller than a pixel).
# DVR uses tf.json (opacity from 25.5 up) on dense volumes and tf_sparse.json (from the isovalue 127.5 up) on
# sparse ones, so that their outside is empty space.
# Environment: DENSE (default "marschner-lobb"), SPARSE (default "sphere menger"), SIZE (256), BRICK (the
# stores' brick edge, default the converter's 32), IMAGE (512x512), FRAMES (6 measured), ROUNDS (3: the three
# renderers run in turn this many times; each figure is the median over rounds of a run's median frame, the
# ratios are of those), RENDER_ARGS (more `ropecast render` arguments for all three, e.g. "--gradients
# computed"), ROPE_ARGS (more for the two ropecast runs only, e.g. "--backend fragment": ropecast's stage
# where --backend auto would pick compute), BRUTE_ARGS (more for the brute-force runs only; default
# "--brute-stage S", S the shader stage the ropecast runs cast their rays in, found by a one-frame render
# with RENDER_ARGS and ROPE_ARGS; e.g. "--brute-stage fragment" for brute force in a fragment shader whatever
# ropecast runs in), EXT (png, or ppm for a build without OpenImageIO: then the images are not compared), WORK
# (scratch dir). Volumes are converted once into WORK and reused. The stages compared are printed below the
# first line, from those renders' --stats.
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/lib/common.sh
bench_setup render_vs_brute "${1:-build/perf}"
DENSE=${DENSE:-"marschner-lobb"}
SPARSE=${SPARSE:-"sphere menger"}
BRICK=${BRICK:-32}
EXT=${EXT:-png}
FRAMES=${FRAMES:-6}
ROUNDS=${ROUNDS:-3}
STILL=${STILL:-6}

write_ramp_tf "$WORK/tf.json"
# Sparse volumes in DVR: the same ramp from the isovalue up, so that (as in data with empty space) what lies
# outside the isosurface has no opacity; with tf.json the sphere's falloff fills the whole cube.
write_ramp_tf "$WORK/tf_sparse.json" 127.5
last=$((STILL + FRAMES - 1))
cat > "$WORK/path.json" <<EOF2
[{"orbit": [30, 20, 3], "time": 0}, {"orbit": [30, 20, 3], "time": $STILL},
 {"orbit": [$((30 + FRAMES - 1)), 20, 3], "time": $last}]
EOF2

# stage_of ARGS...: the shader stage (--stats "stage") in which a small one-frame render with ARGS casts its rays.
stage_of() {
  "$ROPECAST" render procedural:sphere:32 --brick 16 --size 16x16 "$@" --stats "$WORK/stage.jsonl" \
    -o "$WORK/stage.$EXT" -q
  python3 -c 'import json, sys; print(json.loads(open(sys.argv[1]).readline())["stage"])' "$WORK/stage.jsonl"
}
# shellcheck disable=SC2086  # RENDER_ARGS, ROPE_ARGS and BRUTE_ARGS are word lists
rope_stage=$(stage_of ${RENDER_ARGS:-} ${ROPE_ARGS:-})
BRUTE_ARGS=${BRUTE_ARGS-"--brute-stage $rope_stage"}
# shellcheck disable=SC2086
brute_stage=$(stage_of ${RENDER_ARGS:-} --backend brute $BRUTE_ARGS)

# median STATS: median raycast_ms over the measured frames: the last FRAMES, less those that uploaded or had
# requests pending (the camera turns while they are drawn, and a fast frame rate can meet a late brick); at
# least half of them must be left.
median() {
  python3 - "$1" "$FRAMES" <<'EOF2'
import json, statistics, sys
rows = [json.loads(l) for l in open(sys.argv[1])][-int(sys.argv[2]):]
still = [r for r in rows if not (r["bricks_uploaded"] or r["requests_pending"])]
if 2 * len(still) < len(rows):
    sys.exit("render_vs_brute: %d of the last %d frames still loading; raise STILL" % (len(rows) - len(still), len(rows)))
print("%.3f" % statistics.median(r["raycast_ms"] for r in still))
EOF2
}

echo "volumes ${SIZE}^3 in ${BRICK}^3 bricks, image $IMAGE, median of $FRAMES frames per run, $ROUNDS rounds," \
  "extra render args: ${RENDER_ARGS:-none}, ropecast only: ${ROPE_ARGS:-none}"
echo "shader stages: ropecast $rope_stage, brute force $brute_stage (brute force only: ${BRUTE_ARGS:-none})"
printf '%-15s %-6s %-4s %10s %10s %10s %8s %8s  %s\n' volume kind mode brute_ms full_ms adapt_ms "b/full" "b/adapt" \
  "per-round b/full, b/adapt"
for name in $DENSE $SPARSE; do
  kind=sparse; case " $DENSE " in *" $name "*) kind=dense;; esac
  store=$WORK/$name-$SIZE-b$BRICK.rcast
  [ -f "$store" ] || "$ROPECAST" convert "procedural:$name:$SIZE" --brick "$BRICK" -o "$store" -q
  tf=$WORK/tf.json
  [ "$kind" = sparse ] && tf=$WORK/tf_sparse.json
  for mode in iso dvr; do
    # shellcheck disable=SC2206,SC2086  # RENDER_ARGS, ROPE_ARGS and BRUTE_ARGS are word lists
    mode_args=(--iso 127.5)
    [ "$mode" = dvr ] && mode_args=(--tf "$tf")
    args=(--size "$IMAGE" --mode "$mode" "${mode_args[@]}" --path "$WORK/path.json"
          --frames $((last + 1)) ${RENDER_ARGS:-})
    # ROUNDS alternations of the three renderers, so that a change of the machine's load (other jobs on this
    # shared VM) falls on all three rather than on one.
    b=() f=() a=()
    for _ in $(seq "$ROUNDS"); do
      "$ROPECAST" render "$store" "${args[@]}" --backend brute $BRUTE_ARGS --stats "$WORK/$name-$mode-brute.jsonl" \
        -o "$WORK/$name-$mode-brute.$EXT"
      "$ROPECAST" render "$store" "${args[@]}" ${ROPE_ARGS:-} --voxels-per-pixel 64 --stats "$WORK/$name-$mode-full.jsonl" \
        -o "$WORK/$name-$mode-full.$EXT"
      "$ROPECAST" render "$store" "${args[@]}" ${ROPE_ARGS:-} --voxels-per-pixel 1 --stats "$WORK/$name-$mode-adaptive.jsonl" \
        -o "$WORK/$name-$mode-adaptive.$EXT"
      b+=("$(median "$WORK/$name-$mode-brute.jsonl")")
      f+=("$(median "$WORK/$name-$mode-full.jsonl")")
      a+=("$(median "$WORK/$name-$mode-adaptive.jsonl")")
    done
    python3 - "$name" "$kind" "$mode" "${b[*]}" "${f[*]}" "${a[*]}" <<'EOF2'
import statistics, sys
name, kind, mode = sys.argv[1:4]
b, f, a = ([float(x) for x in arg.split()] for arg in sys.argv[4:7])
mb, mf, ma = (statistics.median(x) for x in (b, f, a))
rounds = " ".join("%.2f/%.2f" % (bi / fi, bi / ai) for bi, fi, ai in zip(b, f, a))
print("%-15s %-6s %-4s %10.3f %10.3f %10.3f %7.2fx %7.2fx  %s"
      % (name, kind, mode, mb, mf, ma, mb / mf, mb / ma, rounds))
EOF2
    if [ "$EXT" = png ]; then
      "$ROPECAST" compare "$WORK/$name-$mode-brute.png" "$WORK/$name-$mode-full.png" |
        sed "s/^/  brute vs full-resolution ropecast image: /"
    fi
  done
done
echo "images and stats in $WORK"
