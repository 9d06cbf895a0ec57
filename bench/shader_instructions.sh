#!/usr/bin/env bash
# Instructions per frame that llvmpipe's JIT-compiled code (shaders, texture sampling) executes for ropecast's
# ray caster and for brute force (`--backend brute`) on the same volume and camera, counted by valgrind's
# callgrind: deterministic, so a small shader change shows where frame times on a shared machine are lost in
# noise. Instructions are not time (memory stalls are not counted): confirm a gain with timed runs.
#
#   bench/shader_instructions.sh [BUILD_DIR]         (default build/vg, configured and built if missing)
#
# The build must be ROPECAST_WITH_OIIO=OFF: OpenImageIO pulls in libhwy, whose start-up runs RDTSCP, which
# valgrind 3.19 cannot execute. Callgrind writes its counts after every frame (bench/callgrind_frames.sh); the
# figure is the last frame's, and the two frames before it must have cost the same, i.e. the working set must
# have converged.
# Environment: VOLUME (default procedural:marschner-lobb:64), MODE (dvr), TF (linear), IMAGE (128x128), FRAMES (10),
# SHADERS (a shader tree for ROPECAST_SHADER_DIR, or a colon list: a folder with the changed files first, then
# the checkout; default the checkout's), EXTRA (more `ropecast render` args), BRUTE_INSTRUCTIONS (brute force's
# per-frame count from an earlier run with the same VOLUME, MODE, TF, IMAGE and brute-force shader: skips measuring
# it again, which halves the run when only ropecast's shaders change). A 256^3 store needs more than 10 frames
# to load under valgrind; an ML 128^3 store (`ropecast convert procedural:marschner-lobb:128`) has ~4 leaves
# per ray and takes ~1 min per renderer here (iso: FRAMES=12).
set -euo pipefail
shopt -s inherit_errexit
cd "$(dirname "$0")/.."
BUILD=${1:-build/vg}
VOLUME=${VOLUME:-procedural:marschner-lobb:64}
MODE=${MODE:-dvr}
TF=${TF:-linear}
IMAGE=${IMAGE:-128x128}
FRAMES=${FRAMES:-10}
SHADERS=${SHADERS:-$PWD}
WORK=$(mktemp -d /tmp/shader_instructions.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
command -v valgrind > /dev/null || { echo "shader_instructions: valgrind missing (scripts/bootstrap --bench)" >&2; exit 1; }
[ "$FRAMES" -ge 3 ] || { echo "shader_instructions: FRAMES ($FRAMES) must be at least 3" >&2; exit 1; }
if [ ! -x "$BUILD/tools/ropecast" ]; then
  cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DROPECAST_WITH_OIIO=OFF -DROPECAST_BUILD_TESTS=OFF >/dev/null
  cmake --build "$BUILD" --target ropecast
fi
source bench/callgrind_frames.sh

# jit_instructions DUMP: instructions in code without an object file (llvmpipe's JIT) in one callgrind dump.
jit_instructions() {
  callgrind_annotate --threshold=100 "$1" |
    awk '/\?\?\?:0x/ && /\[\?\?\?\]/ { gsub(",", "", $1); s += $1 } END { printf "%.0f\n", s }'
}

# per_frame NAME ARGS...: the last frame's JIT instructions, after checking that the two before cost the same.
per_frame() {
  local name=$1
  shift
  # shellcheck disable=SC2086  # EXTRA is a word list
  ROPECAST_SHADER_DIR=$SHADERS "${CALLGRIND_PER_FRAME[@]}" --callgrind-out-file="$WORK/$name.cg" \
    "$BUILD/tools/ropecast" render "$input" --size "$IMAGE" --mode "$MODE" --tf "$TF" --voxels-per-pixel 64 \
    --frames "$FRAMES" -o "$WORK/$name.ppm" ${EXTRA:-} "$@" > "$WORK/$name.log" 2>&1 ||
    { echo "shader_instructions: $name failed:" >&2; tail -5 "$WORK/$name.log" >&2; exit 1; }
  local counts=() i
  for i in $((FRAMES - 2)) $((FRAMES - 1)) "$FRAMES"; do
    [ -f "$WORK/$name.cg.$i" ] || { echo "shader_instructions: $name wrote no counts for frame $i" >&2; exit 1; }
    counts+=("$(jit_instructions "$WORK/$name.cg.$i")")
  done
  if [ "${counts[0]}" != "${counts[1]}" ] || [ "${counts[1]}" != "${counts[2]}" ]; then
    echo "shader_instructions: $name's last three frames differ (${counts[*]}): not converged; raise FRAMES" >&2
    exit 1
  fi
  echo "${counts[2]}"
}

# A store, not the procedural source: reading bricks is fast under valgrind, generating them is not.
case "$VOLUME" in
  procedural:*) "$BUILD/tools/ropecast" convert "$VOLUME" -o "$WORK/volume.rcast" > /dev/null; input=$WORK/volume.rcast ;;
  *) input=$VOLUME ;;
esac
echo "$VOLUME $MODE (tf $TF) $IMAGE, last of $FRAMES frames, shaders $SHADERS"
brute=${BRUTE_INSTRUCTIONS:-$(per_frame brute --backend brute)}
rope=$(per_frame rope)
python3 -c "
b, r = $brute, $rope
print('brute force  %6.1f M instructions per frame' % (b / 1e6))
print('ropecast     %6.1f M instructions per frame' % (r / 1e6))
print('ropecast / brute force = %.3f' % (r / b))"
