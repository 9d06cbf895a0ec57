#!/usr/bin/env bash
# Instructions per frame that llvmpipe's JIT-compiled code (shaders, texture sampling) executes for ropecast's
# ray caster and for brute force (`--backend brute`) on the same volume and camera, counted by valgrind's
# callgrind: deterministic, so a shader change of 1 % shows where frame times on this shared 2-core VM move
# by +-15 %. Instructions are not time (memory stalls are not counted): confirm a gain with timed runs.
#
#   bench/shader_instructions.sh [BUILD_DIR]         (default build/vg, configured and built if missing)
#
# The build must be ROPECAST_WITH_OIIO=OFF: OpenImageIO pulls in libhwy, whose start-up runs RDTSCP, which
# valgrind 3.19 cannot execute. Per frame = (run of FB frames - run of FA frames) / (FB - FA), both after the
# working set has converged, so start-up, shader compilation and uploads cancel out; the Mesa shader cache is
# off, and valgrind schedules threads fairly (without it the loader thread starved and nothing was drawn).
# Environment: VOLUME (default procedural:marschner-lobb:64), MODE (dvr), IMAGE (128x128), FA (8), FB (11),
# SHADERS (a shader tree for ROPECAST_SHADER_DIR, or a colon list: a folder with the changed files first, then
# the checkout; default the checkout's), EXTRA (more `ropecast render` args), BRUTE_INSTRUCTIONS (brute force's
# per-frame count from an earlier run with the same VOLUME, MODE, IMAGE and brute-force shader: skips measuring
# it again, which halves the run when only ropecast's shaders change). A 256^3 store needs more than 8 frames to
# load under valgrind; an ML 128^3 store (`ropecast convert procedural:marschner-lobb:128`) with FA=5 FB=7 has 7
# leaves per ray and takes ~2.5 min per renderer here.
set -euo pipefail
shopt -s inherit_errexit
cd "$(dirname "$0")/.."
BUILD=${1:-build/vg}
VOLUME=${VOLUME:-procedural:marschner-lobb:64}
MODE=${MODE:-dvr}
IMAGE=${IMAGE:-128x128}
FA=${FA:-8}
FB=${FB:-11}
SHADERS=${SHADERS:-$PWD}
WORK=$(mktemp -d /tmp/shader_instructions.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
command -v valgrind > /dev/null || { echo "shader_instructions: valgrind missing (scripts/bootstrap --bench)" >&2; exit 1; }
[ "$FB" -gt "$FA" ] || { echo "shader_instructions: FB ($FB) must exceed FA ($FA)" >&2; exit 1; }
if [ ! -x "$BUILD/tools/ropecast" ]; then
  cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DROPECAST_WITH_OIIO=OFF -DROPECAST_BUILD_TESTS=OFF >/dev/null
  cmake --build "$BUILD" --target ropecast
fi
export EGL_PLATFORM=${EGL_PLATFORM:-surfaceless} LP_NUM_THREADS=0 MESA_SHADER_CACHE_DISABLE=true

# jit_instructions NAME FRAMES ARGS...: instructions in code without an object file (llvmpipe's JIT).
jit_instructions() {
  local name=$1 frames=$2
  shift 2
  ROPECAST_SHADER_DIR=$SHADERS valgrind --tool=callgrind --fair-sched=yes --callgrind-out-file="$WORK/$name.cg" \
    "$BUILD/tools/ropecast" render "$input" --size "$IMAGE" --mode "$MODE" --tf linear --voxels-per-pixel 64 \
    --frames "$frames" --stats "$WORK/$name.jsonl" -o "$WORK/$name.ppm" ${EXTRA:-} "$@" > "$WORK/$name.log" 2>&1 ||
    { echo "shader_instructions: $name failed:" >&2; tail -5 "$WORK/$name.log" >&2; exit 1; }
  callgrind_annotate --threshold=100 "$WORK/$name.cg" |
    awk '/\?\?\?:0x/ && /\[\?\?\?\]/ { gsub(",", "", $1); s += $1 } END { printf "%.0f\n", s }'
}

per_frame() {
  local name=$1
  shift
  local a b
  a=$(jit_instructions "${name}_a" "$FA" "$@")
  b=$(jit_instructions "${name}_b" "$FB" "$@")
  # Both runs must have drawn the same cuts in their first FA frames (loading is asynchronous) and converged.
  python3 - "$WORK/${name}_a.jsonl" "$WORK/${name}_b.jsonl" "$FA" <<'EOF'
import json, sys
a, b = ([json.loads(l) for l in open(f)] for f in sys.argv[1:3])
fa = int(sys.argv[3])
cuts = lambda rows: [(r.get("leaves"), r.get("bricks_resident")) for r in rows]
if not a[-1].get("converged", True) or not b[-1].get("converged", True):
    sys.exit("shader_instructions: not converged after %d frames; raise FA" % fa)
if cuts(a) != cuts(b)[:fa]:
    sys.exit("shader_instructions: the two runs loaded at different frames; run again or raise FA")
EOF
  echo $(((b - a) / (FB - FA)))
}

# A store, not the procedural source: reading bricks is fast under valgrind, generating them is not.
case "$VOLUME" in
  procedural:*) "$BUILD/tools/ropecast" convert "$VOLUME" -o "$WORK/volume.rcast" > /dev/null; input=$WORK/volume.rcast ;;
  *) input=$VOLUME ;;
esac
echo "$VOLUME $MODE $IMAGE, frames $FA..$FB, shaders $SHADERS"
brute=${BRUTE_INSTRUCTIONS:-$(per_frame brute --backend brute)}
rope=$(per_frame rope)
python3 -c "
b, r = $brute, $rope
print('brute force  %6.1f M instructions per frame' % (b / 1e6))
print('ropecast     %6.1f M instructions per frame' % (r / 1e6))
print('ropecast / brute force = %.3f' % (r / b))"
