#!/usr/bin/env bash
# Where llvmpipe's JIT code (the ray-cast shaders, texture sampling) spends its instructions in one frame:
# execution-count classes and blocks of the last frame's code, from callgrind per-instruction counts matched
# with a disassembly of the JIT code (bench/jit_profile/); bench/shader_instructions.sh gives the totals alone.
#
#   bench/jit_profile.sh [BUILD_DIR] -- ROPECAST_RENDER_ARGS...      (default build/vg, as shader_instructions)
#   e.g. bench/jit_profile.sh -- ml128.rcast --size 128x128 --mode dvr --tf linear --voxels-per-pixel 64
#   (ml128.rcast from `ropecast convert procedural:marschner-lobb:128 -o ml128.rcast`)
#
# Environment: FRAMES (10: the last one is profiled; it must have converged), BLOCKS=1 (also list the blocks in
# address order), LISTING=FILE (write the annotated disassembly), SHADERS (as in shader_instructions.sh).
# Needs valgrind, gcc and objdump (scripts/bootstrap --bench), and a ROPECAST_WITH_OIIO=OFF build.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=build/vg
if [ $# -gt 0 ] && [ "$1" != "--" ]; then BUILD=$1; shift; fi
[ "${1:-}" = "--" ] && shift
[ $# -gt 0 ] || { echo "usage: bench/jit_profile.sh [BUILD_DIR] -- ROPECAST_RENDER_ARGS..." >&2; exit 1; }
FRAMES=${FRAMES:-10}
for tool in valgrind gcc objdump; do
  command -v $tool > /dev/null || { echo "jit_profile: $tool missing (scripts/bootstrap --bench)" >&2; exit 1; }
done
[ -x "$BUILD/tools/ropecast" ] || { echo "jit_profile: $BUILD/tools/ropecast not built" >&2; exit 1; }
WORK=$(mktemp -d /tmp/jit_profile.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
gcc -O2 -shared -fPIC bench/jit_profile/exec_dump.c -o "$WORK/exec_dump.so" -ldl
mkdir "$WORK/regions"
source bench/callgrind_frames.sh
ROPECAST_SHADER_DIR=${SHADERS:-$PWD} JIT_DUMP_DIR="$WORK/regions" LD_PRELOAD="$WORK/exec_dump.so" \
  "${CALLGRIND_PER_FRAME[@]}" --dump-instr=yes --callgrind-out-file="$WORK/cg" \
  "$BUILD/tools/ropecast" render "$@" --frames "$FRAMES" -o "$WORK/out.ppm" \
  > "$WORK/log" 2>&1 || { echo "jit_profile: ropecast render failed:" >&2; tail -5 "$WORK/log" >&2; exit 1; }
[ -f "$WORK/cg.$FRAMES" ] || { echo "jit_profile: no counts for frame $FRAMES" >&2; exit 1; }
python3 bench/jit_profile/blocks.py "$WORK/cg.$FRAMES" "$WORK/regions" ${BLOCKS:+--blocks} \
  ${LISTING:+--listing "$LISTING"}
